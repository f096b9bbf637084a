// The vertex attributes of the first primitive of glTF/GLB files as two web readers give them, in Node: three.js's
// GLTFLoader (BufferAttribute.getX.. : normalized integers denormalized) and @baker/babylon's readAccessor (what its
// loader extensions feed the shaders). An independent check that KHR_mesh_quantization's forms (gltf-transform
// quantize) are read as numbers, not as the stored integers.
//   esbuild test/attribute_values.mjs --bundle --platform=node ... (tests/test_gltf_transform_steps.py bundles it)
//   node attribute_values.js FILE.glb...   prints one JSON line per file: {file, three: {NAME: [...]}, babylon: {...}}
import { readFileSync } from 'node:fs';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { readAccessor } from '../../../runtime-shaders/babylon/src/common.js';

for (const file of process.argv.slice(2)) {
	const glb = readFileSync(file);
	const jsonLength = glb.readUInt32LE(12);
	const json = JSON.parse(glb.subarray(20, 20 + jsonLength).toString('utf8'));
	const bin = glb.subarray(20 + jsonLength + 8);
	const attributes = json.meshes[0].primitives[0].attributes;

	// three.js: only the accessors are parsed (no DOM for images)
	const accessorsOnly = { ...json };
	for (const key of ['scene', 'scenes', 'nodes', 'meshes', 'materials', 'textures', 'images', 'samplers']) delete accessorsOnly[key];
	let text = Buffer.from(JSON.stringify(accessorsOnly), 'utf8');
	text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
	const rest = glb.subarray(20 + jsonLength);
	const header = Buffer.alloc(20);
	header.writeUInt32LE(0x46546c67, 0); header.writeUInt32LE(2, 4);
	header.writeUInt32LE(20 + text.length + rest.length, 8); header.writeUInt32LE(text.length, 12);
	header.writeUInt32LE(0x4e4f534a, 16);
	const packed = Buffer.concat([header, text, rest]);
	const parser = await new Promise((resolve, reject) => new GLTFLoader().parse(
		packed.buffer.slice(packed.byteOffset, packed.byteOffset + packed.byteLength), '', (g) => resolve(g.parser), reject));
	const three = {};
	const getters = ['getX', 'getY', 'getZ', 'getW'];
	for (const [name, index] of Object.entries(attributes)) {
		const attribute = await parser.getDependency('accessor', index);
		const values = [];
		for (let i = 0; i < attribute.count; i++) {
			for (let c = 0; c < attribute.itemSize; c++) values.push(attribute[getters[c]](i));
		}
		three[name] = values;
	}

	// @baker/babylon's reader, on a loader that serves the GLB's buffer views
	const loader = {
		gltf: json,
		loadBufferViewAsync: async (_context, view) =>
			new Uint8Array(bin.buffer, bin.byteOffset + (view.byteOffset || 0), view.byteLength),
	};
	const babylon = {};
	for (const [name, index] of Object.entries(attributes)) babylon[name] = Array.from((await readAccessor(loader, index)).data);
	console.log(JSON.stringify({ file, three, babylon }));
}
