// Read a baked asset, run glTF-Transform's pipeline steps, write it back: `node roundtrip.mjs IN OUT`.
// The caller (tests/test_gltf_transform.py) then checks the BAKER_* data survived and still validates.
import { NodeIO } from '@gltf-transform/core';
import { KHRONOS_EXTENSIONS } from '@gltf-transform/extensions';
import { dedup, prune, flatten, resample, sparse } from '@gltf-transform/functions';
import { BAKER_EXTENSIONS } from '../src/index.js';

const [input, output] = process.argv.slice(2);
// BAKER_GLTF_TRANSFORM_CONTROL=1 leaves our classes out: the control run shows what a pipeline loses without them
const baker = process.env.BAKER_GLTF_TRANSFORM_CONTROL === '1' ? [] : BAKER_EXTENSIONS;
const io = new NodeIO().registerExtensions([...KHRONOS_EXTENSIONS, ...baker]);
const document = await io.read(input);
// optimize's steps that keep vertex data as is (no weld, no simplify, no quantize, no texture compression)
await document.transform(dedup(), flatten(), resample(), prune(), sparse());
await io.write(output, document);
