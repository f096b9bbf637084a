// Decode every accessor of glTF/GLB files with three.js's GLTFLoader (and meshoptimizer's MeshoptDecoder), in Node,
// and print a SHA-256 of each accessor's bytes: an independent reader of what `baker bake --compress meshopt` writes.
//   node test/accessor_digests.mjs FILE.glb...     prints one JSON line per file: {file, accessors: [hex, ...]}
// Used by tests/test_meshopt_output.py. Only accessors are read: the GLB is re-packed without its scenes, materials
// and images (the buffers, bufferViews and accessors untouched), so no DOM is needed.
import { createHash } from 'node:crypto';
import { readFileSync } from 'node:fs';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

for (const file of process.argv.slice(2)) {
	const loader = new GLTFLoader();
	loader.setMeshoptDecoder(MeshoptDecoder);
	const buffer = accessorsOnly(readFileSync(file));
	const parser = await new Promise((resolve, reject) => loader.parse(buffer, '', (gltf) => resolve(gltf.parser), reject));
	const accessors = [];
	for (let i = 0; i < (parser.json.accessors || []).length; i++) {
		const attribute = await parser.getDependency('accessor', i);
		const array = attribute.isInterleavedBufferAttribute ? deinterleave(attribute) : attribute.array;
		accessors.push(createHash('sha256').update(new Uint8Array(array.buffer, array.byteOffset, array.byteLength)).digest('hex'));
	}
	console.log(JSON.stringify({ file, accessors }));
}

// an interleaved accessor (a strided bufferView) as its own tightly packed elements, as stored (getComponent would
// denormalize a normalized one)
function deinterleave(attribute) {
	const out = new attribute.array.constructor(attribute.count * attribute.itemSize);
	const { array, stride } = attribute.data;
	for (let i = 0; i < attribute.count; i++) {
		for (let c = 0; c < attribute.itemSize; c++) out[i * attribute.itemSize + c] = array[i * stride + attribute.offset + c];
	}
	return out;
}

// a GLB with only what accessors need: JSON without scenes, nodes, meshes, materials, textures and images
function accessorsOnly(glb) {
	const jsonLength = glb.readUInt32LE(12);
	const json = JSON.parse(glb.subarray(20, 20 + jsonLength).toString('utf8'));
	for (const key of ['scene', 'scenes', 'nodes', 'meshes', 'materials', 'textures', 'images', 'samplers', 'skins', 'animations']) delete json[key];
	let text = Buffer.from(JSON.stringify(json), 'utf8');
	text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
	const rest = glb.subarray(20 + jsonLength);  // the BIN chunk, header and all
	const header = Buffer.alloc(20);
	header.writeUInt32LE(0x46546c67, 0);
	header.writeUInt32LE(2, 4);
	header.writeUInt32LE(20 + text.length + rest.length, 8);
	header.writeUInt32LE(text.length, 12);
	header.writeUInt32LE(0x4e4f534a, 16);
	const out = Buffer.concat([header, text, rest]);
	return out.buffer.slice(out.byteOffset, out.byteOffset + out.byteLength);
}
