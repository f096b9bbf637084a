// Vertex- and triangle-indexed baker data through glTF-Transform's steps that reorder, weld, simplify or compress.
//
// BAKER_edges' `edges`/`oppositeVertices` and EXT_mesh_primitive_edge_visibility's `silhouetteMates` and
// `lineStrings` hold vertex indices; the wireframe mask and the visibility bits are per triangle (per triangle
// edge, in corner order). glTF-Transform remaps a primitive's attributes and indices (reorder, weld, unweld,
// simplify, dedup, meshopt's reorder) but never an extension's accessors. So when these classes read a primitive
// with such data they give it one more vertex attribute, `_BAKER_VERTEX_ID` (FLOAT, the vertex's index as read),
// which every step carries with the vertex; quantize leaves it alone (it is outside [-1, 1]). When the document is
// written, before any compression step sees the primitive, the attribute is removed and the data is remapped:
// vertex indices through the ids, per-triangle-edge values through the directed edge (old id, old id) each new
// triangle edge comes from. A step that made triangle edges that were not there (simplify collapses edges) leaves
// data that cannot be remapped: it is dropped, with one warning line, never written wrong.
//
// Draco's encoder renumbers vertices and triangles inside the compressed stream (edgebreaker and sequential alike,
// as glTF-Transform 4.5 calls it). So a primitive Draco will compress gets one more attribute before it does,
// `_BAKER_DRACO_ID_<n>` (unsigned integers, which Draco stores losslessly): after the encoder ran, the stream is
// decoded (with the decoder given to setDracoDecoder), the ids say where each decoded vertex came from and the data
// is remapped to the decoded vertex and triangle order; the id attribute is left out of the written primitive.
// Without a decoder the data is dropped, with one warning line. meshopt's index codec may rotate a triangle's corners: with its codec given
// (setMeshoptIndexCodec) the triangles are rotated as it will before the remap.
import { PropertyType } from '@gltf-transform/core';
import { rememberUnits, settleUnits } from './units.js';

export const VERTEX_ID = '_BAKER_VERTEX_ID';
const EDGES = 'BAKER_edges';
const HAIR = 'BAKER_hair';
const EDGE_VISIBILITY = 'EXT_mesh_primitive_edge_visibility';
const DRACO = 'KHR_draco_mesh_compression';
const MESHOPT = 'EXT_meshopt_compression';
const TRIANGLES = 4;
const FLOAT = 5126;

// primitive -> { indices (Uint32Array as read), vertexCount }
const SNAPSHOTS = new WeakMap();
// each primitive's id attribute has a name of its own (`_BAKER_VERTEX_ID_<n>`), so `join` (which merges primitives
// with the same attribute names, and drops their extensions) leaves these primitives alone
let serial = 0;

function triangleIndices(prim) {
	const indices = prim.getIndices();
	if (indices) return Uint32Array.from(indices.getArray());
	const count = prim.getAttribute('POSITION')?.getCount() ?? 0;
	return Uint32Array.from({ length: count }, (_, i) => i);
}

function hasTopologyData(prim) {
	const edges = prim.getExtension(EDGES);
	const edgeData = edges && ['edges', 'oppositeVertices', 'wireframeMask'].some((p) => edges.getAccessor(p));
	return Boolean(edgeData || prim.getExtension(EDGE_VISIBILITY));
}

// BAKER_hair's strands are runs of `verticesPerStrand` vertices and its accessors are per strand or index the
// ribbon vertices: they hold only while the primitive keeps its vertex order (meshopt, quantize and draco keep it
// for line primitives); a step that changes it drops BAKER_hair from the mesh's primitives, with a warning
const hasStrands = (prim) => Boolean(prim.getExtension(HAIR));

function idSemantic(prim) {
	return prim.listSemantics().find((semantic) => semantic.startsWith(VERTEX_ID));
}

/** Give `prim` its vertex ids (once), remembering its triangles as read. Called by the classes' read(). */
export function markVertices(document, prim) {
	if (SNAPSHOTS.has(prim)) return;
	if (!(prim.getMode() === TRIANGLES && hasTopologyData(prim)) && !hasStrands(prim)) return;
	const position = prim.getAttribute('POSITION');
	if (!position) return;
	const vertexCount = position.getCount();
	const ids = document.createAccessor(VERTEX_ID).setType('SCALAR')
		.setArray(Float32Array.from({ length: vertexCount }, (_, i) => i)).setBuffer(position.getBuffer());
	prim.setAttribute(`${VERTEX_ID}_${serial++}`, ids);
	SNAPSHOTS.set(prim, { indices: triangleIndices(prim), vertexCount });
}

function disposeIfUnused(property) {
	if (property && property.listParents().every((p) => p.propertyType === PropertyType.ROOT)) property.dispose();
}

function sameArray(a, b) {
	if (a.length !== b.length) return false;
	for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
	return true;
}

// meshoptimizer's codec ({encoder, decoder}, both ready) for the index rotation EXT_meshopt_compression makes
let indexCodec = null;
// draco3dgltf's decoder module (ready), to read back the vertex order of a Draco stream
let dracoDecoder = null;
const DRACO_ID = '_BAKER_DRACO_ID';
// primitive -> the semantic of its Draco id attribute, between the accessor and buffer prewrite phases
const DRACO_IDS = new WeakMap();

/** Give the decoder of draco3dgltf (`await draco3d.createDecoderModule()`; gltf-transform.config.mjs does): with it
 * the edge data of a primitive KHR_draco_mesh_compression compresses is remapped to the stream's vertex order;
 * without it, the data is dropped (with a warning). */
export function setDracoDecoder(module) {
	dracoDecoder = module;
}

/** Give the codec EXT_meshopt_compression writes with (gltf-transform.config.mjs does): its index encoder may
 * rotate a triangle's corners, which moves per-triangle-edge data; with the codec the triangles are rotated as it
 * will, before the data is remapped. Without it, the data of a primitive written with meshopt is dropped. */
export function setMeshoptIndexCodec(codec) {
	indexCodec = codec;
}

/** The triangles as meshopt's index codec will store them (stable under another round trip), or null. */
function meshoptRotated(indices) {
	const { encoder, decoder } = indexCodec;
	// the codec takes 2- or 4-byte indices
	let current = indices instanceof Uint8Array ? Uint16Array.from(indices) : indices;
	for (let round = 0; round < 4; round++) {
		const size = current.BYTES_PER_ELEMENT;
		const encoded = encoder.encodeGltfBuffer(current, current.length, size, 'TRIANGLES');
		const target = new Uint8Array(current.length * size);
		decoder.decodeGltfBuffer(target, current.length, size, encoded, 'TRIANGLES');
		const decoded = new current.constructor(target.buffer);
		if (sameArray(decoded, current)) return current;
		current = decoded;
	}
	return null;
}

/** Remove the vertex ids of every primitive and remap (or drop) its topology-indexed data. */
export function settleTopology(document) {
	const root = document.getRoot();
	const logger = document.getLogger();
	const draco = root.listExtensionsUsed().find((e) => e.extensionName === DRACO);
	const meshopt = root.listExtensionsUsed().some((e) => e.extensionName === MESHOPT);
	for (const mesh of root.listMeshes()) {
		let strandsMoved = false;
		for (const [p, prim] of mesh.listPrimitives().entries()) {
			const semantic = idSemantic(prim);
			if (!semantic) continue;
			const idAttribute = prim.getAttribute(semantic);
			const ids = idAttribute.getComponentType() === FLOAT && !idAttribute.getNormalized()
				? Array.from(idAttribute.getArray()) : null;
			prim.setAttribute(semantic, null);
			disposeIfUnused(idAttribute);
			const snapshot = SNAPSHOTS.get(prim);
			if (snapshot && hasStrands(prim) && !(ids && ids.length === snapshot.vertexCount &&
				ids.every((id, v) => id === v))) strandsMoved = true;
			if (!snapshot || prim.getMode() !== TRIANGLES || !hasTopologyData(prim)) continue;
			const where = `mesh ${JSON.stringify(mesh.getName())} primitive ${p}`;
			if (meshopt && prim.getIndices()) {
				const rotated = indexCodec ? meshoptRotated(prim.getIndices().getArray()) : null;
				if (!rotated) {
					dropTopologyData(mesh, prim);
					logger.warn(`@baker/gltf-transform: ${where}: ${MESHOPT}'s index codec may rotate triangles and no ` +
						'codec was given (setMeshoptIndexCodec); its edge data is dropped');
					continue;
				}
				if (rotated !== prim.getIndices().getArray()) {
					const old = prim.getIndices();
					prim.setIndices(document.createAccessor(old.getName()).setType('SCALAR').setArray(rotated)
						.setBuffer(old.getBuffer()));
					disposeIfUnused(old);
				}
			}
			const indices = triangleIndices(prim);
			const unchanged = ids && ids.every((id, v) => id === v) && ids.length === snapshot.vertexCount &&
				sameArray(indices, snapshot.indices);
			if (!unchanged) {
				const problem = remapPrimitive(document, prim, snapshot, ids, indices);
				if (problem) {
					dropTopologyData(mesh, prim);
					logger.warn(`@baker/gltf-transform: ${where}: ${problem}; its edge data (BAKER_edges, ` +
						`${EDGE_VISIBILITY}) is dropped, re-run baker bake to rebuild it`);
					continue;
				}
				SNAPSHOTS.set(prim, { indices, vertexCount: prim.getAttribute('POSITION').getCount() });
			}
			if (draco && prim.getIndices()) {
				if (!dracoDecoder) {
					dropTopologyData(mesh, prim);
					logger.warn(`@baker/gltf-transform: ${where}: ${DRACO} renumbers vertices and triangles inside its ` +
						'stream and no decoder was given (setDracoDecoder); its edge data is dropped');
					continue;
				}
				// the ids Draco carries (losslessly: integers) say where each decoded vertex came from (settleDraco)
				const position = prim.getAttribute('POSITION');
				const count = position.getCount();
				const Ids = count < 0xffff ? Uint16Array : Uint32Array;
				const semantic = `${DRACO_ID}_${serial++}`;
				prim.setAttribute(semantic, document.createAccessor(semantic).setType('SCALAR')
					.setArray(Ids.from({ length: count }, (_, i) => i)).setBuffer(position.getBuffer()));
				DRACO_IDS.set(prim, semantic);
			}
		}
		if (strandsMoved) {
			for (const prim of mesh.listPrimitives()) {
				const property = prim.getExtension(HAIR);
				if (!property) continue;
				const accessors = property.listRefPaths().map((path) => property.getAccessor(path)).filter(Boolean);
				prim.setExtension(HAIR, null);
				property.dispose();
				for (const accessor of accessors) disposeIfUnused(accessor);
			}
			logger.warn(`@baker/gltf-transform: mesh ${JSON.stringify(mesh.getName())}: a step changed the vertex ` +
				`order of its strands; ${HAIR} is dropped, re-run baker hair to rebuild it`);
		}
	}
}

/** Prewrite hook of the classes holding topology data (the first one settles everything: the ids are gone after).
 * The ids are not put back: write a document once per read. */
export function prewriteTopology(extension, context, propertyType) {
	if (propertyType === PropertyType.BUFFER) {
		settleDraco(extension.document, context);
		return;
	}
	settleUnits(extension.document);
	settleTopology(extension.document);
}

function dropTopologyData(mesh, prim) {
	const edges = prim.getExtension(EDGES);
	if (edges) {
		for (const fin of mesh.listPrimitives()) {
			if (fin !== prim && fin.getExtension(EDGES)?.getPrimitive('finsOf') === prim) {
				mesh.removePrimitive(fin);
				const attributes = fin.listAttributes();
				const finIndices = fin.getIndices();
				fin.dispose();
				for (const accessor of [...attributes, finIndices]) disposeIfUnused(accessor);
			}
		}
	}
	for (const name of [EDGES, EDGE_VISIBILITY]) {
		const property = prim.getExtension(name);
		if (!property) continue;
		const accessors = property.listRefPaths().map((path) => property.getAccessor(path)).filter(Boolean);
		prim.setExtension(name, null);
		property.dispose();
		for (const accessor of accessors) disposeIfUnused(accessor);
	}
}

function replaceAccessor(document, property, path, array) {
	const old = property.getAccessor(path);
	const accessor = document.createAccessor(old.getName()).setType(old.getType()).setArray(array)
		.setBuffer(old.getBuffer()).setSparse(old.getSparse());
	property.setAccessor(path, accessor);
	disposeIfUnused(old);
}

/** Unsigned array type holding vertex indices below `vertexCount` and its maximum as the "no vertex" sentinel. */
function indexArrayType(vertexCount, oldArray) {
	if (oldArray instanceof Uint8Array && vertexCount < 0xff) return Uint8Array;
	if (!(oldArray instanceof Uint32Array) && vertexCount < 0xffff) return Uint16Array;
	return Uint32Array;
}

const SENTINEL = (array) => (array instanceof Uint8Array ? 0xff : array instanceof Uint16Array ? 0xffff : 0xffffffff);

/** Remap the primitive's topology data from the snapshot's vertex and triangle order to the current one; returns
 * the problem (a phrase) when it cannot. */
function remapPrimitive(document, prim, snapshot, ids, indices, inPlace = false) {
	if (!ids) return 'its vertex ids were quantized';
	const oldCount = snapshot.vertexCount;
	const newCount = ids.length;
	const newOf = new Int32Array(oldCount).fill(-1);
	for (let v = 0; v < newCount; v++) {
		const id = ids[v];
		if (!Number.isInteger(id) || id < 0 || id >= oldCount) return 'its vertex ids were changed';
		if (newOf[id] < 0) newOf[id] = v;
	}
	// the triangle edge (corner k of triangle t -> corner k+1) each directed old-id pair comes from
	const oldTris = snapshot.indices;
	const halfEdge = new Map();
	for (let h = 0; h < oldTris.length; h++) {
		const t = Math.floor(h / 3), k = h % 3;
		halfEdge.set(oldTris[h] * oldCount + oldTris[t * 3 + ((k + 1) % 3)], h);
	}
	const source = new Int32Array(indices.length); // new triangle edge -> old triangle edge
	for (let h = 0; h < indices.length; h++) {
		const t = Math.floor(h / 3), k = h % 3;
		const key = ids[indices[h]] * oldCount + ids[indices[t * 3 + ((k + 1) % 3)]];
		const old = halfEdge.get(key);
		if (old === undefined) return 'its triangles changed (a triangle edge that was not in the baked mesh)';
		source[h] = old;
	}
	const mapVertex = (array, sentinel) => {
		const out = new (indexArrayType(newCount, array))(array.length);
		const outSentinel = SENTINEL(out);
		for (let i = 0; i < array.length; i++) {
			if (array[i] === sentinel) out[i] = outSentinel;
			else if (array[i] >= oldCount || newOf[array[i]] < 0) return null;
			else out[i] = newOf[array[i]];
		}
		return out;
	};

	const edges = prim.getExtension(EDGES);
	const updates = [];
	if (edges) {
		for (const path of ['edges', 'oppositeVertices']) {
			const accessor = edges.getAccessor(path);
			if (!accessor) continue;
			const out = mapVertex(accessor.getArray(), path === 'edges' ? undefined : SENTINEL(accessor.getArray()));
			if (!out) return `its ${path} name a vertex that is gone`;
			updates.push([edges, path, out]);
		}
		const mask = edges.getAccessor('wireframeMask');
		if (mask) {
			const old = mask.getArray();
			const out = new Uint8Array(indices.length / 3);
			for (let h = 0; h < indices.length; h++) {
				const o = source[h];
				if ((old[Math.floor(o / 3)] >> (o % 3)) & 1) out[Math.floor(h / 3)] |= 1 << (h % 3);
			}
			updates.push([edges, 'wireframeMask', out]);
		}
	}
	const visibility = prim.getExtension(EDGE_VISIBILITY);
	if (visibility) {
		const bitsAccessor = visibility.getAccessor('visibility');
		if (bitsAccessor) {
			const old = bitsAccessor.getArray();
			const code = (h) => (old[(2 * h) >> 3] >> ((2 * h) & 7)) & 3;
			const out = new Uint8Array(Math.ceil((6 * indices.length) / 3 / 8));
			for (let h = 0; h < indices.length; h++) out[(2 * h) >> 3] |= code(source[h]) << ((2 * h) & 7);
			updates.push([visibility, 'visibility', out]);
			const matesAccessor = visibility.getAccessor('silhouetteMates');
			if (matesAccessor) {
				// one mate per silhouette (1) triangle edge, in triangle edge order
				const mates = matesAccessor.getArray();
				const mateOf = new Map();
				for (let h = 0, j = 0; h < oldTris.length; h++) if (code(h) === 1) mateOf.set(h, mates[j++]);
				const list = [];
				for (let h = 0; h < indices.length; h++) if (code(source[h]) === 1) list.push(mateOf.get(source[h]));
				const out = mapVertex(list, undefined);
				if (!out) return 'its silhouette mates name a vertex that is gone';
				updates.push([visibility, 'silhouetteMates', out]);
			}
		}
		for (const path of visibility.listRefPaths().filter((p) => /^lineStrings\/\d+\/indices$/.test(p))) {
			const accessor = visibility.getAccessor(path);
			if (!accessor) continue;
			const out = mapVertex(accessor.getArray(), SENTINEL(accessor.getArray()));
			if (!out) return 'its line strings name a vertex that is gone';
			updates.push([visibility, path, out]);
		}
	}
	for (const [property, path, array] of updates) {
		// after the accessor prewrite phase no new accessor is written: the buffer phase sets the arrays in place
		if (inPlace) property.getAccessor(path).setArray(array);
		else replaceAccessor(document, property, path, array);
	}
	return null;
}

/** The decoded triangles and the decoded vertices' ids of a Draco stream. */
function decodeDraco(data, idAttribute) {
	const d = dracoDecoder;
	const decoder = new d.Decoder();
	const buffer = new d.DecoderBuffer();
	const mesh = new d.Mesh();
	try {
		buffer.Init(new Int8Array(data.buffer, data.byteOffset, data.byteLength), data.byteLength);
		if (!decoder.DecodeBufferToMesh(buffer, mesh).ok() || mesh.ptr === 0) return null;
		const numIndices = mesh.num_faces() * 3;
		let ptr = d._malloc(numIndices * 4);
		decoder.GetTrianglesUInt32Array(mesh, numIndices * 4, ptr);
		const indices = new Uint32Array(d.HEAPU32.buffer, ptr, numIndices).slice();
		d._free(ptr);
		const attribute = decoder.GetAttributeByUniqueId(mesh, idAttribute);
		const count = mesh.num_points();
		ptr = d._malloc(count * 4);
		decoder.GetAttributeDataArrayForAllPoints(mesh, attribute, d.DT_UINT32, count * 4, ptr);
		const ids = new Uint32Array(d.HEAPU32.buffer, ptr, count).slice();
		d._free(ptr);
		return { indices, ids };
	} finally {
		d.destroy(mesh);
		d.destroy(buffer);
		d.destroy(decoder);
	}
}

/** Buffer prewrite phase, after KHR_draco_mesh_compression encoded its primitives (accessor phase): remap the edge
 * data of each to the vertex and triangle order of its stream, and leave its id attribute out of the file. */
export function settleDraco(document, context) {
	const logger = document.getLogger();
	const encoding = context.extensionData?.[DRACO];
	for (const mesh of document.getRoot().listMeshes()) {
		for (const [p, prim] of mesh.listPrimitives().entries()) {
			const semantic = DRACO_IDS.get(prim);
			if (!semantic) continue;
			DRACO_IDS.delete(prim);
			const hash = encoding?.primitiveHashMap.get(prim);
			const encoded = hash && encoding.primitiveEncodingMap.get(hash);
			const idAttribute = prim.getAttribute(semantic);
			prim.setAttribute(semantic, null);
			if (idAttribute.listParents().every((q) => q.propertyType === PropertyType.ROOT)) idAttribute.dispose();
			if (!encoded) continue; // not compressed (Draco skipped it): the data stands in the order it was settled in
			const id = encoded.attributeIDs[semantic];
			delete encoded.attributeIDs[semantic]; // not a glTF attribute of the primitive
			const decoded = id === undefined ? null : decodeDraco(encoded.data, id);
			const snapshot = { indices: triangleIndices(prim), vertexCount: prim.getAttribute('POSITION').getCount() };
			const problem = decoded ? remapPrimitive(document, prim, snapshot, Array.from(decoded.ids), decoded.indices, true)
				: 'its Draco stream could not be read back';
			if (problem) {
				dropTopologyData(mesh, prim);
				logger.warn(`@baker/gltf-transform: mesh ${JSON.stringify(mesh.getName())} primitive ${p}: ${problem} ` +
					`(${DRACO}); its edge data (BAKER_edges, ${EDGE_VISIBILITY}) is dropped, re-run baker bake to rebuild it`);
			}
		}
	}
}

/** The class of an extension whose data is indexed by vertex order (edge visibility, hair strands): `Base` with
 * every primitive's vertices marked on read and the data remapped (or dropped) before write. */
export function tracksVertexOrder(Base) {
	return class extends Base {
		prewriteTypes = [PropertyType.ACCESSOR, PropertyType.BUFFER];

		read(context) {
			super.read(context);
			rememberUnits(this.document);
			for (const mesh of this.document.getRoot().listMeshes()) {
				for (const prim of mesh.listPrimitives()) markVertices(this.document, prim);
			}
			return this;
		}

		prewrite(context, propertyType) {
			prewriteTopology(this, context, propertyType);
			return this;
		}
	};
}
