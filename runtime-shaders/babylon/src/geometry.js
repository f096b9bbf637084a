// Mesh building shared by the geometry techniques (edges, fur, hair, text): primitives read back from their
// accessors (engine-independent: the glTF vertices and indices as written), vertex data from generic accessors.
import { Constants } from '@babylonjs/core/Engines/constants.js';
import { Mesh } from '@babylonjs/core/Meshes/mesh.js';
import { glslType, readAccessor } from './common.js';

/** The primitive's indices (or 0..n-1 for a non-indexed primitive) as a Uint32Array. */
export async function primitiveIndices(loader, primitive, vertexCount) {
	if (primitive.indices === undefined) return Uint32Array.from({ length: vertexCount }, (_, i) => i);
	return (await readAccessor(loader, primitive.indices, { integer: true })).data;
}

/**
 * A mesh of `positions` (Float32Array, 3 per vertex) and `indices`, with the vertex data `attributes`
 * ({ kind: { data, size } }), under `parent` at the identity transform, always drawn (no frustum culling: the
 * vertex shader moves the vertices).
 */
export function bakerMesh(name, scene, parent, positions, indices, attributes = {}) {
	const mesh = new Mesh(name, scene);
	mesh.setVerticesData('position', positions, false, 3);
	for (const [kind, { data, size }] of Object.entries(attributes)) mesh.setVerticesData(kind, data, false, size);
	mesh.setIndices(indices, positions.length / 3);
	if (parent) mesh.parent = parent;
	mesh.alwaysSelectAsActiveMesh = true;
	mesh.isPickable = false;
	return mesh;
}

/**
 * The primitive attributes `names` (glTF semantics) as vertex data { kind: { data, size } }, each under its lowercased
 * name (`_FIN_V0` -> `_fin_v0`), the attribute name the shared stages (runtime-shaders/hosts/web) declare. A buffer
 * of another size than the declaration binds as GL does: extra components unread, missing ones 0.
 */
export async function primitiveAttributes(loader, primitive, names) {
	const attributes = {};
	for (const name of names) {
		const index = primitive.attributes?.[name];
		if (index === undefined) throw new Error(`@baker/babylon: primitive attribute ${name} is missing`);
		const { data, size } = await readAccessor(loader, index);
		attributes[name.toLowerCase()] = { data, size };
	}
	return attributes;
}

/** `expression` of `size` components as a `want`-component value (custom attributes may carry padding). */
export function asComponents(expression, size, want) {
	if (size === want) return expression;
	if (size > want) return `${expression}.${'xyzw'.slice(0, want)}`;
	return `${glslType(want)}(${expression}${', 0.0'.repeat(want - size)})`;
}

/** Blending like three's premultiplied CustomBlending (ONE, ONE_MINUS_SRC_ALPHA) without depth writes. */
export function premultiplied(material) {
	material.alphaMode = Constants.ALPHA_PREMULTIPLIED;
	material.disableDepthWrite = true;
	return material;
}
