// The base classes of @baker/gltf-transform: BakerProperty keeps an extension's JSON and holds its references as
// graph edges, BakerExtension reads and writes it wherever it may sit; defineProperty makes the property class of
// one extension on one glTF object with the references listed in references.js (derived from the schemas).
import { Extension, ExtensionProperty, PropertyType, RefMap, TextureInfo } from '@gltf-transform/core';
import { REFERENCES } from './references.js';

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
		let written = false;
		for (const [owner, def, mesh] of this._writePlaces(context)) {
			const property = owner.getExtension(this.extensionName);
			if (!property || !def) continue;
			written = true;
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
		// the writer lists the extensions used before the prewrite hooks run, and a hook may drop the last use
		// (topology.js drops edge data a step cannot keep): an extension nothing carries is not listed
		if (!written) {
			const json = context.jsonDoc.json;
			for (const key of ['extensionsUsed', 'extensionsRequired']) {
				if (!json[key]) continue;
				json[key] = json[key].filter((name) => name !== this.extensionName);
				if (!json[key].length) delete json[key];
			}
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

// The glTF object each property class sits on, as the schema files name it (<object>.<EXT>.schema.json).
const PLACES = {
	[PropertyType.MATERIAL]: 'material',
	[PropertyType.PRIMITIVE]: 'mesh.primitive',
	[PropertyType.NODE]: 'node',
	[PropertyType.ROOT]: 'glTF',
};
const KINDS = new Set(['accessor', 'texture', 'primitive', 'material']);

/**
 * The references of `extensionName` on `parent` as REFS entries (`[pattern, kind, options]`), from REFERENCES
 * (references.js, derived from the schemas). `derived`: patterns the extension class recomputes when writing (back
 * references), which are not read as graph edges. Throws on a reference kind the base classes cannot hold, so a
 * schema with a new kind of reference fails here instead of being written back with stale indices.
 */
export function referencesOf(extensionName, parent, derived = []) {
	const place = PLACES[parent];
	const refs = REFERENCES[extensionName]?.[place];
	if (!refs) throw new Error(`@baker/gltf-transform: references.js has no ${place}.${extensionName} (run tools/references.mjs)`);
	for (const pattern of derived) {
		if (!refs.some(([p]) => p === pattern)) throw new Error(`${extensionName}: derived reference ${pattern} is not in references.js`);
	}
	return refs.filter(([pattern]) => !derived.includes(pattern)).map(([pattern, kind, options = {}]) => {
		if (kind === 'texture-index') return [pattern, 'texture', { ...options, bare: true }];
		if (!KINDS.has(kind)) throw new Error(`${extensionName}: ${kind} reference at ${pattern} is not handled`);
		return [pattern, kind, options];
	});
}

/** The property class of `extensionName` on `parent` (one PropertyType); its REFS come from references.js. */
export function defineProperty(extensionName, propertyType, parent, { derived = [], accepts = () => true } = {}) {
	const Property = class extends BakerProperty {
		static EXTENSION_NAME = extensionName;
		static PARENT = parent;
		static REFS = referencesOf(extensionName, parent, derived);
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
export function finsOfPrimitive(mesh, self, name) {
	return mesh.listPrimitives().filter((prim) => {
		const ext = prim !== self ? prim.getExtension(name) : null;
		return ext && ext.getPrimitive('finsOf') === self;
	});
}

const PARENT_OF = Object.fromEntries(Object.entries(PLACES).map(([parent, place]) => [place, parent]));
const OBJECT_NAMES = { material: 'Material', 'mesh.primitive': 'Primitive', node: 'Node', glTF: 'Root' };
const pascal = (words) => words.split('_').map((w) => w.charAt(0).toUpperCase() + w.slice(1)).join('');

/**
 * The class of an extension that needs nothing but its JSON and its references (an extension with no derived back
 * references and no accessors of its own): one property per glTF object its schemas put it on (references.js), so
 * a new extension is carried by its schema alone. Named as the hand-written ones are: BAKER_skin_lut ->
 * BakerSkinLut (property and extension); on several objects, each property gets the object's kind appended.
 */
export function plainExtension(extensionName) {
	const places = Object.keys(REFERENCES[extensionName] ?? {});
	if (!places.length) throw new Error(`@baker/gltf-transform: references.js has no ${extensionName} (run tools/references.mjs)`);
	const name = `Baker${pascal(extensionName.replace(/^BAKER_/, ''))}`;
	const properties = places.map((place) => defineProperty(extensionName,
		places.length > 1 ? `${name}${OBJECT_NAMES[place]}` : name, PARENT_OF[place]));
	const Plain = class extends BakerExtension {
		static EXTENSION_NAME = extensionName;
		static PROPERTIES = properties;
		extensionName = extensionName;
	};
	Object.defineProperty(Plain, 'name', { value: name });
	return Plain;
}
