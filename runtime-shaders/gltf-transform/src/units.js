// Baked data in mesh units through steps that change a mesh's units (quantize, meshopt's quantization).
//
// KHR_mesh_quantization stores POSITION as integers and moves the dequantization (a scale and an offset) into the
// node drawing the mesh: glTF-Transform's `quantize` (and `meshopt`, which quantizes first) rewrites POSITION and
// the node's transform so that world positions stay where they were. It does not know the other data baker writes
// in the mesh's units, so those would stay in the old units while the mesh's units changed:
// - the fin primitives' `_FIN_V0` .. `_FIN_V3` (BAKER_edges and BAKER_fur fins) are positions: the fin shaders
//   build the fin from them in the node's space, so left alone a fin is drawn scaled and shifted off its edge;
// - BAKER_fur's `length`, `shellSpacing` and `tileSize` (material) and BAKER_hair's `length`, `rootWidth` and
//   `tipWidth` (primitive) are lengths in mesh units: shells and strand widths would grow by the dequantization.
// So when a class reads a document it remembers the world matrix of each mesh's node (M0), and before the document
// is written it compares with the node's world matrix then (M1): the positions go through M1^-1 M0 and the lengths
// are multiplied by its scale. A material shared by meshes whose units changed differently keeps its lengths, with
// a warning. The per-vertex scalars of the bake (`_THICKNESS` in mesh units, curvatures in 1/mesh units) are
// shading inputs and keep the units of the bake (they are stored as the bake wrote them, or quantized in [-1, 1]).
import { PropertyType } from '@gltf-transform/core';

const FUR = 'BAKER_fur';
const HAIR = 'BAKER_hair';
const FIN_POSITIONS = ['_FIN_V0', '_FIN_V1', '_FIN_V2', '_FIN_V3'];
const FUR_LENGTHS = ['length', 'shellSpacing', 'tileSize'];
const HAIR_LENGTHS = ['length', 'rootWidth', 'tipWidth'];

// mesh -> world matrix (column-major 16) of its first node, as read (and after each settle, as written)
const WORLD = new WeakMap();

const nodeOf = (mesh) => mesh.listParents().find((p) => p.propertyType === PropertyType.NODE);

/** Remember the world matrix of every mesh's node (once per mesh). Called by the classes' read(). */
export function rememberUnits(document) {
	for (const mesh of document.getRoot().listMeshes()) {
		const node = nodeOf(mesh);
		if (node && !WORLD.has(mesh)) WORLD.set(mesh, Array.from(node.getWorldMatrix()));
	}
}

/** a^-1 b for affine column-major 4x4 matrices (the 3x3 part invertible). */
function invertTimes(a, b) {
	const [m00, m10, m20, , m01, m11, m21, , m02, m12, m22] = a;
	const det = m00 * (m11 * m22 - m12 * m21) - m01 * (m10 * m22 - m12 * m20) + m02 * (m10 * m21 - m11 * m20);
	const inv = [
		(m11 * m22 - m12 * m21) / det, (m12 * m20 - m10 * m22) / det, (m10 * m21 - m11 * m20) / det,
		(m02 * m21 - m01 * m22) / det, (m00 * m22 - m02 * m20) / det, (m01 * m20 - m00 * m21) / det,
		(m01 * m12 - m02 * m11) / det, (m02 * m10 - m00 * m12) / det, (m00 * m11 - m01 * m10) / det,
	]; // row-major 3x3
	const t = [a[12], a[13], a[14]];
	const apply = (x, y, z) => [0, 1, 2].map((r) => inv[3 * r] * x + inv[3 * r + 1] * y + inv[3 * r + 2] * z);
	const out = new Array(16).fill(0);
	for (let c = 0; c < 4; c++) {
		const [x, y, z] = c < 3 ? [b[4 * c], b[4 * c + 1], b[4 * c + 2]]
			: [b[12] - t[0], b[13] - t[1], b[14] - t[2]];
		const col = apply(x, y, z);
		out[4 * c] = col[0]; out[4 * c + 1] = col[1]; out[4 * c + 2] = col[2];
	}
	out[15] = 1;
	return out;
}

const isIdentity = (m) => m.every((v, i) => Math.abs(v - (i % 5 === 0 ? 1 : 0)) < 1e-9);

/** The length scale of an affine map (the cube root of its 3x3 determinant: exact for the uniform scale of
 * KHR_mesh_quantization's dequantization). */
function lengthScale(m) {
	const det = m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) + m[8] * (m[1] * m[6] - m[5] * m[2]);
	return Math.cbrt(Math.abs(det));
}

function replaceAttribute(document, prim, semantic, array) {
	const old = prim.getAttribute(semantic);
	const accessor = document.createAccessor(old.getName()).setType(old.getType()).setArray(array)
		.setBuffer(old.getBuffer());
	prim.setAttribute(semantic, accessor);
	if (old.listParents().every((p) => p.propertyType === PropertyType.ROOT)) old.dispose();
}

/** Move the mesh-unit data of every mesh whose node's world matrix changed since it was read (see above). */
export function settleUnits(document) {
	const logger = document.getLogger();
	const furScales = new Map(); // material -> [scale, ...]
	for (const mesh of document.getRoot().listMeshes()) {
		const node = nodeOf(mesh);
		const before = WORLD.get(mesh);
		if (!node || !before) continue;
		const after = Array.from(node.getWorldMatrix());
		const map = invertTimes(after, before); // old local -> new local
		WORLD.set(mesh, after);
		if (!map.every(Number.isFinite)) continue; // a node scaled to zero: nothing to measure units by
		const scale = isIdentity(map) ? 1 : lengthScale(map);
		for (const prim of mesh.listPrimitives()) {
			const material = prim.getMaterial();
			if (material?.getExtension(FUR)) furScales.set(material, [...(furScales.get(material) || []), scale]);
			if (scale === 1) continue;
			for (const semantic of FIN_POSITIONS) {
				const accessor = prim.getAttribute(semantic);
				if (!accessor) continue;
				const count = accessor.getCount();
				const size = accessor.getElementSize();
				const out = new Float32Array(count * size);
				const v = [];
				for (let i = 0; i < count; i++) {
					accessor.getElement(i, v); // dequantized when stored as normalized integers
					for (let r = 0; r < size; r++) {
						out[i * size + r] = r < 3 ? map[r] * v[0] + map[4 + r] * v[1] + map[8 + r] * v[2] + map[12 + r] : v[r];
					}
				}
				replaceAttribute(document, prim, semantic, out);
			}
			const hair = prim.getExtension(HAIR);
			if (hair) {
				const params = { ...hair.getParams() };
				for (const key of HAIR_LENGTHS) if (typeof params[key] === 'number') params[key] *= scale;
				hair.setParams(params);
			}
		}
	}
	for (const [material, scales] of furScales) {
		if (scales.every((s) => s === 1)) continue;
		if (scales.some((s) => Math.abs(s - scales[0]) > 1e-6 * scales[0])) {
			logger.warn(`@baker/gltf-transform: material ${JSON.stringify(material.getName())}: meshes whose units ` +
				`changed differently share it; its ${FUR} lengths are kept as baked`);
			continue;
		}
		const fur = material.getExtension(FUR);
		const params = { ...fur.getParams() };
		for (const key of FUR_LENGTHS) if (typeof params[key] === 'number') params[key] *= scales[0];
		fur.setParams(params);
	}
}
