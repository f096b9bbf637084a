// glTF-Transform extensions for baker's BAKER_* glTF extensions (and EXT_mesh_primitive_edge_visibility).
//
// glTF-Transform drops extensions it has no class for when it writes a document, so a pipeline running
// `optimize`, `prune` or `dedup` on a baked asset would lose the baked data. Register these classes (next to
// KHRONOS_EXTENSIONS, which carries KHR_materials_volume's thickness texture) and the data survives:
//
//   import { NodeIO } from '@gltf-transform/core';
//   import { KHRONOS_EXTENSIONS } from '@gltf-transform/extensions';
//   import { BAKER_EXTENSIONS } from '@baker/gltf-transform';
//   const io = new NodeIO().registerExtensions([...KHRONOS_EXTENSIONS, ...BAKER_EXTENSIONS]);
//
// Every extension keeps its JSON as is (`getParams()`), except the references, which become graph edges:
// - accessors (BAKER_edges' edge list, BAKER_hair's ribbon indices, the glyph tables, ...) -> Accessor properties,
//   so `prune` keeps them and the writer gives them their new index;
// - textures (`{index, texCoord}` texture infos, or a bare texture index such as a font's atlas) -> Texture +
//   TextureInfo (sampler and texCoord), so `prune` keeps the images, `dedup` may merge them and `prune`'s TEXCOORD
//   bookkeeping sees the UV sets the textures read;
// - primitives of the same mesh (`finsOf`, BAKER_hair's `guides.primitive`) -> Primitive properties; the back
//   references (`BAKER_edges.fins`, `BAKER_fur.fins` on the material) are derived from them when writing, so the
//   graph has no cycles.
// Custom vertex attributes (`_THICKNESS`, `_CURVATURE`, `_FIN_V0`, ...) need nothing: glTF-Transform keeps them
// (`prune` removes only unused NORMAL, TANGENT, TEXCOORD_n and COLOR_n).
import { Extension, ExtensionProperty, PropertyType, RefMap, TextureInfo } from '@gltf-transform/core';

// ------------------------------------------------------------------------------------------- JSON paths
// A reference is named by its path in the extension's JSON ("levels/0/textures/1"); patterns use '*' for any
// array index.

function expand(value, segments, prefix = []) {
	if (!segments.length) return value === undefined || value === null ? [] : [prefix];
	if (value === null || typeof value !== 'object') return [];
	const [head, ...rest] = segments;
	if (head === '*') {
		return Array.isArray(value) ? value.flatMap((item, i) => expand(item, rest, [...prefix, i])) : [];
	}
	return head in value ? expand(value[head], rest, [...prefix, head]) : [];
}

function parsePath(key) {
	return key.split('/').map((s) => (/^\d+$/.test(s) ? Number(s) : s));
}

function getAt(object, path) {
	return path.reduce((value, segment) => (value == null ? undefined : value[segment]), object);
}

function setAt(object, path, value) {
	const parent = getAt(object, path.slice(0, -1));
	if (parent != null) parent[path[path.length - 1]] = value;
}

/** Remove the values at `paths`; array elements are spliced out, last first, so earlier indices stay valid. */
function removeAt(object, paths) {
	const compare = (a, b) => {
		for (let i = 0; i < Math.min(a.length, b.length); i++) {
			if (a[i] === b[i]) continue;
			return typeof a[i] === 'number' && typeof b[i] === 'number' ? a[i] - b[i] : String(a[i]) < String(b[i]) ? -1 : 1;
		}
		return a.length - b.length;
	};
	for (const path of [...paths].sort(compare).reverse()) {
		const parent = getAt(object, path.slice(0, -1));
		if (parent == null) continue;
		const last = path[path.length - 1];
		if (Array.isArray(parent) && typeof last === 'number') parent.splice(last, 1);
		else delete parent[last];
	}
}

const clone = (value) => JSON.parse(JSON.stringify(value));

// ------------------------------------------------------------------------------------------- base property
/**
 * One BAKER_* extension object on a material, primitive, node or the root. `getParams()` is its JSON; references
 * listed by the subclass's static `REFS` (`[pattern, kind, options]`, kind `accessor`, `texture`, `primitive` or
 * `material`) are graph edges, read back with `getAccessor(path)`, `getTexture(path)`, `getTextureInfo(path)`,
 * `getPrimitive(path)`, `getMaterial(path)`.
 */
export class BakerProperty extends ExtensionProperty {
	static REFS = [];

	getDefaults() {
		return Object.assign(super.getDefaults(), {
			params: {},
			refKinds: {},
			accessors: new RefMap(),
			textures: new RefMap(),
			// "<name>Info" next to "<name>": how glTF-Transform's prune/shiftTexCoords pair textures with their infos
			texturesInfo: new RefMap(),
			primitives: new RefMap(),
			materials: new RefMap(),
		});
	}

	/** The extension's JSON properties as baker wrote them (reference values are those of the file read). */
	getParams() {
		return clone(this.get('params'));
	}

	setParams(params) {
		return this.set('params', clone(params));
	}

	listRefPaths() {
		return Object.keys(this.get('refKinds'));
	}

	getAccessor(path) {
		return this.getRefMap('accessors', path);
	}

	setAccessor(path, accessor) {
		this._kind(path, 'accessor');
		return this.setRefMap('accessors', path, accessor, { usage: 'OTHER' });
	}

	getTexture(path) {
		return this.getRefMap('textures', path);
	}

	getTextureInfo(path) {
		return this.getRefMap('textures', path) ? this.getRefMap('texturesInfo', path) : null;
	}

	setTexture(path, texture) {
		this._kind(path, 'texture');
		this.setRefMap('textures', path, texture);
		if (texture && !this.getRefMap('texturesInfo', path)) {
			this.setRefMap('texturesInfo', path, new TextureInfo(this.graph, 'texturesInfo'));
		}
		return this;
	}

	getPrimitive(path) {
		return this.getRefMap('primitives', path);
	}

	setPrimitive(path, primitive) {
		this._kind(path, 'primitive');
		return this.setRefMap('primitives', path, primitive);
	}

	getMaterial(path) {
		return this.getRefMap('materials', path);
	}

	setMaterial(path, material) {
		this._kind(path, 'material');
		return this.setRefMap('materials', path, material);
	}

	_kind(path, kind) {
		const kinds = this.get('refKinds');
		if (kinds[path] !== kind) this.set('refKinds', { ...kinds, [path]: kind });
	}
}

// ------------------------------------------------------------------------------------------- base extension
const PARENTS = {
	[PropertyType.MATERIAL]: 'materials',
	[PropertyType.PRIMITIVE]: 'primitives',
	[PropertyType.NODE]: 'nodes',
	[PropertyType.ROOT]: 'root',
};

/**
 * Reads and writes one BAKER_* extension wherever it may sit (static `PROPERTIES`: property classes, each with one
 * parent type). Subclasses add derived fields in `finish(out, owner, context)`.
 */
export class BakerExtension extends Extension {
	static PROPERTIES = [];

	/** Creates the property class for `parentType` (PropertyType.MATERIAL, PRIMITIVE, NODE or ROOT). */
	createProperty(parentType = this.constructor.PROPERTIES[0].PARENT) {
		const Property = this.constructor.PROPERTIES.find((P) => P.PARENT === parentType);
		if (!Property) throw new Error(`${this.extensionName}: no property on ${parentType}`);
		return new Property(this.document.getGraph());
	}

	/** [owner, its JSON definition] for every place this extension may be read from. */
	*_readPlaces(context) {
		const json = context.jsonDoc.json;
		for (const Property of this.constructor.PROPERTIES) {
			const kind = PARENTS[Property.PARENT];
			if (kind === 'materials') {
				for (const [i, def] of (json.materials || []).entries()) yield [Property, context.materials[i], def, null];
			} else if (kind === 'primitives') {
				for (const [m, meshDef] of (json.meshes || []).entries()) {
					const prims = context.meshes[m].listPrimitives();
					for (const [p, def] of (meshDef.primitives || []).entries()) yield [Property, prims[p], def, context.meshes[m]];
				}
			} else if (kind === 'nodes') {
				for (const [i, def] of (json.nodes || []).entries()) yield [Property, context.nodes[i], def, null];
			} else if (kind === 'root') {
				yield [Property, this.document.getRoot(), json, null];
			}
		}
	}

	read(context) {
		const json = context.jsonDoc.json;
		for (const [Property, owner, def, mesh] of this._readPlaces(context)) {
			const ext = def && def.extensions && def.extensions[this.extensionName];
			if (!ext || typeof ext !== 'object' || Array.isArray(ext) || !owner) continue;
			if (!Property.accepts(ext)) continue;
			const { extras, ...params } = ext;
			const property = new Property(this.document.getGraph()).setParams(params);
			if (extras) property.setExtras(extras);
			for (const [pattern, kind, options = {}] of Property.REFS) {
				for (const path of expand(params, pattern.split('/'))) {
					const key = path.join('/');
					const value = getAt(params, path);
					if (kind === 'accessor') {
						if (Number.isInteger(value) && context.accessors[value]) property.setAccessor(key, context.accessors[value]);
					} else if (kind === 'texture') {
						const infoDef = options.bare ? { index: value } : { ...value };
						if (options.texCoordFrom) infoDef.texCoord = params[options.texCoordFrom] ?? 0;
						const textureDef = (json.textures || [])[infoDef.index];
						const texture = textureDef && context.textures[textureDef.source];
						if (!texture) continue;
						property.setTexture(key, texture);
						context.setTextureInfo(property.getTextureInfo(key), infoDef);
					} else if (kind === 'primitive') {
						const target = mesh && Number.isInteger(value) ? mesh.listPrimitives()[value] : null;
						if (target) property.setPrimitive(key, target);
					} else if (kind === 'material') {
						if (Number.isInteger(value) && context.materials[value]) property.setMaterial(key, context.materials[value]);
					}
				}
			}
			owner.setExtension(this.extensionName, property);
		}
		return this;
	}

	/** [owner, its JSON definition, its mesh] for every owner of this extension in the document being written. */
	*_writePlaces(context) {
		const root = this.document.getRoot();
		const json = context.jsonDoc.json;
		const types = new Set(this.constructor.PROPERTIES.map((P) => P.PARENT));
		if (types.has(PropertyType.MATERIAL)) {
			for (const material of root.listMaterials()) {
				yield [material, json.materials[context.materialIndexMap.get(material)], null];
			}
		}
		if (types.has(PropertyType.PRIMITIVE)) {
			for (const mesh of root.listMeshes()) {
				const meshDef = json.meshes[context.meshIndexMap.get(mesh)];
				for (const [p, prim] of mesh.listPrimitives().entries()) yield [prim, meshDef.primitives[p], mesh];
			}
		}
		if (types.has(PropertyType.NODE)) {
			for (const node of root.listNodes()) yield [node, json.nodes[context.nodeIndexMap.get(node)], null];
		}
		if (types.has(PropertyType.ROOT)) yield [root, json, null];
	}

	write(context) {
		for (const [owner, def, mesh] of this._writePlaces(context)) {
			const property = owner.getExtension(this.extensionName);
			if (!property || !def) continue;
			const out = property.getParams();
			const missing = [];
			for (const key of property.listRefPaths()) {
				const path = parsePath(key);
				const kind = property.get('refKinds')[key];
				const options = (property.constructor.REFS.find(([pattern]) => matches(pattern, path)) || [])[2] || {};
				let value;
				if (kind === 'accessor') {
					const accessor = property.getAccessor(key);
					if (accessor) value = context.accessorIndexMap.get(accessor);
				} else if (kind === 'texture') {
					const texture = property.getTexture(key);
					if (texture) {
						const infoDef = context.createTextureInfoDef(texture, property.getTextureInfo(key));
						if (options.bare) value = infoDef.index;
						else {
							const { index, texCoord, ...rest } = getAt(out, path) || {};
							value = { ...rest, index: infoDef.index };
							if (options.texCoordFrom) {
								const texCoord = infoDef.texCoord ?? 0;
								if (texCoord !== 0 || options.texCoordFrom in out) out[options.texCoordFrom] = texCoord;
							} else if (infoDef.texCoord) value.texCoord = infoDef.texCoord;
							if (infoDef.extras) value.extras = infoDef.extras;
						}
					}
				} else if (kind === 'primitive') {
					const target = property.getPrimitive(key);
					const index = mesh && target ? mesh.listPrimitives().indexOf(target) : -1;
					if (index >= 0) value = index;
				} else if (kind === 'material') {
					const material = property.getMaterial(key);
					if (material) value = context.materialIndexMap.get(material);
				}
				if (value === undefined) missing.push(path);
				else setAt(out, path, value);
			}
			removeAt(out, missing);
			this.finish(out, owner, context, mesh);
			const extras = property.getExtras();
			if (extras && Object.keys(extras).length) out.extras = extras;
			def.extensions = def.extensions || {};
			def.extensions[this.extensionName] = out;
		}
		return this;
	}

	/** Hook for fields derived from the graph when writing (e.g. back references). */
	finish(_out, _owner, _context, _mesh) {}
}

function matches(pattern, path) {
	const segments = pattern.split('/');
	return segments.length === path.length && segments.every((s, i) => s === '*' ? typeof path[i] === 'number' : s === String(path[i]));
}

function defineProperty(extensionName, propertyType, parent, refs = [], accepts = () => true) {
	const Property = class extends BakerProperty {
		static EXTENSION_NAME = extensionName;
		static PARENT = parent;
		static REFS = refs;
		static accepts = accepts;
		init() {
			this.extensionName = extensionName;
			this.propertyType = propertyType;
			this.parentTypes = [parent];
		}
	};
	Object.defineProperty(Property, 'name', { value: propertyType });
	return Property;
}

/** Primitives of `mesh` (other than `self`) whose `name` extension's `finsOf` points at `self`. */
function finsOfPrimitive(mesh, self, name) {
	return mesh.listPrimitives().filter((prim) => {
		const ext = prim !== self ? prim.getExtension(name) : null;
		return ext && ext.getPrimitive('finsOf') === self;
	});
}

// ------------------------------------------------------------------------------------------- BAKER_thickness
const THICKNESS = 'BAKER_thickness';

/** BAKER_thickness on a material: bake settings and translucency parameters (schemas/BAKER_thickness). The
 * thickness texture itself is KHR_materials_volume's, carried by KHRONOS_EXTENSIONS. */
export class Thickness extends defineProperty(THICKNESS, 'BakerThickness', PropertyType.MATERIAL) {
	/** Name of the per-vertex attribute holding thickness in mesh units, or null. */
	getAttribute() {
		return this.get('params').attribute ?? null;
	}
}

export class BakerThickness extends BakerExtension {
	static EXTENSION_NAME = THICKNESS;
	static PROPERTIES = [Thickness];
	extensionName = THICKNESS;

	createThickness() {
		return this.createProperty(PropertyType.MATERIAL);
	}
}

// ------------------------------------------------------------------------------------------- BAKER_curvature
const CURVATURE = 'BAKER_curvature';

/** BAKER_curvature on a material: settings, attribute names and the optional `curvatureTexture`. */
export const Curvature = defineProperty(CURVATURE, 'BakerCurvature', PropertyType.MATERIAL,
	[['curvatureTexture', 'texture']]);

export class BakerCurvature extends BakerExtension {
	static EXTENSION_NAME = CURVATURE;
	static PROPERTIES = [Curvature];
	extensionName = CURVATURE;
}

// ------------------------------------------------------------------------------------------- BAKER_skin_lut
const SKIN = 'BAKER_skin_lut';

/** BAKER_skin_lut on a material: the LUT and penumbra textures, the optional curvature texture, parameters. */
export const SkinLut = defineProperty(SKIN, 'BakerSkinLut', PropertyType.MATERIAL,
	[['lutTexture', 'texture'], ['penumbraTexture', 'texture'], ['curvatureTexture', 'texture']]);

export class BakerSkinLut extends BakerExtension {
	static EXTENSION_NAME = SKIN;
	static PROPERTIES = [SkinLut];
	extensionName = SKIN;
}

// ------------------------------------------------------------------------------------------- BAKER_tonal_art_map
const TAM = 'BAKER_tonal_art_map';

/** BAKER_tonal_art_map on a material: every level's textures (`packed`) or texture (`volume`); their UV set is
 * the extension's `texCoord`, kept in each TextureInfo so prune's TEXCOORD bookkeeping renumbers it. */
export const TonalArtMap = defineProperty(TAM, 'BakerTonalArtMap', PropertyType.MATERIAL, [
	['levels/*/textures/*', 'texture', { texCoordFrom: 'texCoord' }],
	['levels/*/texture', 'texture', { texCoordFrom: 'texCoord' }],
]);

export class BakerTonalArtMap extends BakerExtension {
	static EXTENSION_NAME = TAM;
	static PROPERTIES = [TonalArtMap];
	extensionName = TAM;
}

// ------------------------------------------------------------------------------------------- BAKER_toon_ramp
const TOON = 'BAKER_toon_ramp';

/** BAKER_toon_ramp on a material: the ramp (or X-Toon map) texture and the band parameters. */
export const ToonRamp = defineProperty(TOON, 'BakerToonRamp', PropertyType.MATERIAL, [['rampTexture', 'texture']]);

export class BakerToonRamp extends BakerExtension {
	static EXTENSION_NAME = TOON;
	static PROPERTIES = [ToonRamp];
	extensionName = TOON;
}

// ------------------------------------------------------------------------------------------- BAKER_edges
const EDGES = 'BAKER_edges';
const EDGE_ACCESSORS = ['edges', 'oppositeVertices', 'flags', 'dihedralAngles', 'wireframeMask'];

/** BAKER_edges on a triangle primitive (the per-edge accessors) or on its fin primitive (`finsOf`, a Primitive
 * of the same mesh). The source's `fins` is derived from the fin primitive's `finsOf` when writing. */
export const Edges = defineProperty(EDGES, 'BakerEdges', PropertyType.PRIMITIVE, [
	...EDGE_ACCESSORS.map((key) => [key, 'accessor']),
	['finsOf', 'primitive'],
]);

export class BakerEdges extends BakerExtension {
	static EXTENSION_NAME = EDGES;
	static PROPERTIES = [Edges];
	extensionName = EDGES;

	read(context) {
		super.read(context);
		// `fins` is a back reference: drop it, finish() derives it from the fin primitive's `finsOf`
		for (const mesh of this.document.getRoot().listMeshes()) {
			for (const prim of mesh.listPrimitives()) {
				const ext = prim.getExtension(EDGES);
				if (ext && 'fins' in ext.get('params')) {
					const { fins, ...rest } = ext.get('params');
					ext.set('params', { ...rest, fins: null });
				}
			}
		}
		return this;
	}

	finish(out, owner, _context, mesh) {
		if (!('fins' in out)) return;
		const fins = mesh ? finsOfPrimitive(mesh, owner, EDGES) : [];
		if (fins.length) out.fins = mesh.listPrimitives().indexOf(fins[0]);
		else delete out.fins;
	}
}

// ------------------------------------------------------------------------------------------- EXT_mesh_primitive_edge_visibility
const EDGE_VISIBILITY = 'EXT_mesh_primitive_edge_visibility';

/** EXT_mesh_primitive_edge_visibility (Bentley) on a triangle primitive: `visibility` (2 bits per triangle edge)
 * and `silhouetteMates` accessors, and `lineStrings` (index accessors and materials). */
export const EdgeVisibility = defineProperty(EDGE_VISIBILITY, 'EdgeVisibility', PropertyType.PRIMITIVE, [
	['visibility', 'accessor'],
	['silhouetteMates', 'accessor'],
	['lineStrings/*/indices', 'accessor'],
	['lineStrings/*/material', 'material'],
]);

export class EXTMeshPrimitiveEdgeVisibility extends BakerExtension {
	static EXTENSION_NAME = EDGE_VISIBILITY;
	static PROPERTIES = [EdgeVisibility];
	extensionName = EDGE_VISIBILITY;
}

// ------------------------------------------------------------------------------------------- BAKER_hair
const HAIR = 'BAKER_hair';

/** BAKER_hair on a LINES primitive: `widthScale`, `ribbonIndices`, and for children `guides` (`primitive`: the
 * guide Primitive of the same mesh; `ids`, `weights`: accessors). */
export const Hair = defineProperty(HAIR, 'BakerHair', PropertyType.PRIMITIVE, [
	['widthScale', 'accessor'],
	['ribbonIndices', 'accessor'],
	['guides/ids', 'accessor'],
	['guides/weights', 'accessor'],
	['guides/primitive', 'primitive'],
]);

export class BakerHair extends BakerExtension {
	static EXTENSION_NAME = HAIR;
	static PROPERTIES = [Hair];
	extensionName = HAIR;
}

// ------------------------------------------------------------------------------------------- BAKER_fur
const FUR = 'BAKER_fur';

/** BAKER_fur on a material: shell textures, fin texture, parameters. Its `fins` list is derived when writing from
 * the fin primitives whose source primitive uses this material. */
export const Fur = defineProperty(FUR, 'BakerFur', PropertyType.MATERIAL, [
	['shellTextures/*', 'texture'],
	['finTexture', 'texture'],
], (ext) => !('finsOf' in ext));

/** BAKER_fur on a fin primitive: `finsOf`, its source Primitive in the same mesh. */
export const FurFins = defineProperty(FUR, 'BakerFurFins', PropertyType.PRIMITIVE, [['finsOf', 'primitive']]);

export class BakerFur extends BakerExtension {
	static EXTENSION_NAME = FUR;
	static PROPERTIES = [Fur, FurFins];
	extensionName = FUR;

	finish(out, owner, context) {
		if (!('shellTextures' in out) && !('fins' in out)) return; // a fin primitive
		const fins = [];
		for (const mesh of this.document.getRoot().listMeshes()) {
			for (const [p, prim] of mesh.listPrimitives().entries()) {
				const ext = prim.getExtension(FUR);
				const source = ext && ext.getPrimitive('finsOf');
				if (source && source.getMaterial() === owner) {
					fins.push({ mesh: context.meshIndexMap.get(mesh), primitive: p });
				}
			}
		}
		if (fins.length) out.fins = fins;
		else delete out.fins;
	}
}

// ------------------------------------------------------------------------------------------- BAKER_glyph_atlas
const ATLAS = 'BAKER_glyph_atlas';

/** BAKER_glyph_atlas on the root: per font the atlas texture (a bare texture index, its sampler kept) and the
 * glyph and kerning accessors. */
export const GlyphAtlas = defineProperty(ATLAS, 'BakerGlyphAtlas', PropertyType.ROOT, [
	['fonts/*/texture', 'texture', { bare: true }],
	['fonts/*/glyphs/unicode', 'accessor'],
	['fonts/*/glyphs/advance', 'accessor'],
	['fonts/*/glyphs/planeBounds', 'accessor'],
	['fonts/*/glyphs/atlasBounds', 'accessor'],
	['fonts/*/kerning/pairs', 'accessor'],
	['fonts/*/kerning/advance', 'accessor'],
]);

export class BakerGlyphAtlas extends BakerExtension {
	static EXTENSION_NAME = ATLAS;
	static PROPERTIES = [GlyphAtlas];
	extensionName = ATLAS;
}

// ------------------------------------------------------------------------------------------- BAKER_text
const TEXT = 'BAKER_text';

/** BAKER_text on a node: string, font (index into BAKER_glyph_atlas.fonts, which no transform reorders), size,
 * alignment, colours. */
export const Text = defineProperty(TEXT, 'BakerText', PropertyType.NODE);

export class BakerText extends BakerExtension {
	static EXTENSION_NAME = TEXT;
	static PROPERTIES = [Text];
	extensionName = TEXT;
}

/** Every class, for `io.registerExtensions([...KHRONOS_EXTENSIONS, ...BAKER_EXTENSIONS])`. */
export const BAKER_EXTENSIONS = [
	BakerThickness,
	BakerCurvature,
	BakerSkinLut,
	BakerTonalArtMap,
	BakerToonRamp,
	BakerEdges,
	EXTMeshPrimitiveEdgeVisibility,
	BakerHair,
	BakerFur,
	BakerGlyphAtlas,
	BakerText,
];
