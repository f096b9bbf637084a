// Shared by the plugins of @baker/three: the extension names, the techniques (switches) and the per-asset registry
// of their on/off handlers, and the helpers several plugins use (scene lookups, textures, lit ShaderMaterials, the
// viewport uniform). Not an entry point: import from index.js.
import * as THREE from 'three';

export const BAKER_THICKNESS = 'BAKER_thickness';
export const BAKER_CURVATURE = 'BAKER_curvature';
export const BAKER_SKIN_LUT = 'BAKER_skin_lut';
export const BAKER_EDGES = 'BAKER_edges';
export const BAKER_TONAL_ART_MAP = 'BAKER_tonal_art_map';
export const BAKER_TOON_RAMP = 'BAKER_toon_ramp';
export const BAKER_GLYPH_ATLAS = 'BAKER_glyph_atlas';
export const BAKER_TEXT = 'BAKER_text';
export const BAKER_HAIR = 'BAKER_hair';
export const BAKER_FUR = 'BAKER_fur';

/** Techniques (switch names) and the extension each comes from. Techniques off by default are debug views. */
export const TECHNIQUES = {
	translucency: { extension: BAKER_THICKNESS, label: 'translucency' },
	skin: { extension: BAKER_SKIN_LUT, label: 'pre-integrated skin' },
	toon: { extension: BAKER_TOON_RAMP, label: 'toon ramp' },
	tam: { extension: BAKER_TONAL_ART_MAP, label: 'hatching (TAM)' },
	fins: { extension: BAKER_EDGES, label: 'edge fins' },
	outline: { extension: BAKER_EDGES, label: 'shell outline' },
	wireframe: { extension: BAKER_EDGES, label: 'wireframe', defaultOff: true },
	fur: { extension: BAKER_FUR, label: 'fur shells + fins' },
	hair: { extension: BAKER_HAIR, label: 'hair ribbons' },
	text: { extension: BAKER_TEXT, label: 'MSDF text' },
	curvature: { extension: BAKER_CURVATURE, label: 'curvature view', defaultOff: true },
};

const GLSL_NAMES = {
	translucency: 'baker_translucency.glsl', skin: 'baker_skin.glsl', toon: 'baker_toon.glsl',
	hatching: 'baker_hatching.glsl', edges: 'baker_edges.glsl', fur: 'baker_fur.glsl', hair: 'baker_hair.glsl',
	text: 'baker_text.glsl',
};

// ------------------------------------------------------------------------------------------------ shared state
// One registry per loaded asset (parser): every plugin adds its technique's on/off handler to it; afterRoot of the
// last plugin publishes it as gltf.userData.baker.
class BakerControls {
	constructor() {
		this.found = [];           // names, in discovery order
		this.handlers = new Map(); // name -> [fn(on)]
		this.enabled = new Map();
	}
	add(name, handler) {
		if (!this.handlers.has(name)) {
			this.handlers.set(name, []);
			this.found.push(name);
			this.enabled.set(name, !TECHNIQUES[name]?.defaultOff);
		}
		this.handlers.get(name).push(handler);
		handler(this.enabled.get(name));
	}
	/** The techniques found, in the order of TECHNIQUES (plugins finish in any order). */
	get techniques() {
		const order = Object.keys(TECHNIQUES);
		return [...this.found].sort((a, b) => order.indexOf(a) - order.indexOf(b));
	}
	has(name) { return this.handlers.has(name); }
	isEnabled(name) { return Boolean(this.enabled.get(name)); }
	setEnabled(name, on) {
		if (!this.handlers.has(name)) return;
		this.enabled.set(name, Boolean(on));
		for (const fn of this.handlers.get(name)) fn(Boolean(on));
	}
}

const controlsOf = new WeakMap();
export function controls(parser) {
	if (!controlsOf.has(parser)) controlsOf.set(parser, new BakerControls());
	return controlsOf.get(parser);
}

export function requireShader(shaders, key) {
	const glsl = shaders[key];
	if (!glsl) throw new Error(`@baker/three: options.shaders.${key} (runtime-shaders/${GLSL_NAMES[key]} as text) is missing`);
	return glsl;
}

export function materialsOf(object) {
	return Array.isArray(object.material) ? object.material : [object.material];
}

/** [object, material, materialIndex] for every mesh material of the scene that GLTFLoader built from json.materials. */
export function sceneMaterials(parser, scene) {
	const out = [];
	scene.traverse((object) => {
		if (!object.isMesh) return;
		for (const material of materialsOf(object)) {
			const index = parser.associations.get(material)?.materials;
			if (index !== undefined) out.push([object, material, index]);
		}
	});
	return out;
}

/** The primitive (json) a mesh object was built from, or null. */
export function primitiveOf(parser, object) {
	const a = parser.associations.get(object);
	if (!a || a.meshes === undefined || a.primitives === undefined) return null;
	return parser.json.meshes[a.meshes].primitives[a.primitives];
}

export function textureOf(parser, info) {
	const index = typeof info === 'number' ? info : info?.index;
	return index === undefined ? Promise.resolve(null) : parser.getDependency('texture', index);
}

export function dataTexture(texture, { repeat = false, linear = true } = {}) {
	texture.colorSpace = THREE.NoColorSpace; // LUTs, ramps, TAM and distance fields are data, not sRGB colour
	texture.wrapS = texture.wrapT = repeat ? THREE.RepeatWrapping : THREE.ClampToEdgeWrapping;
	texture.magFilter = linear ? THREE.LinearFilter : THREE.NearestFilter;
	texture.minFilter = THREE.LinearFilter;
	texture.generateMipmaps = false;
	texture.needsUpdate = true;
	return texture;
}

/** A ShaderMaterial lit by the scene's lights (view-space directionalLights[] etc. through lights_pars_begin). */
export function litShaderMaterial(parameters) {
	const uniforms = THREE.UniformsUtils.merge([THREE.UniformsLib.lights]);
	Object.assign(uniforms, parameters.uniforms); // not cloned: textures stay shared
	return new THREE.ShaderMaterial({ ...parameters, uniforms, lights: true });
}

// Diffuse light from the directional lights of the scene, view space: sum of color * max(N.L, 0).
export const DIRECTIONAL_DIFFUSE = `
vec3 baker_directional_diffuse(vec3 N) {
	vec3 sum = vec3(0.0);
#if NUM_DIR_LIGHTS > 0
	for (int i = 0; i < NUM_DIR_LIGHTS; i++) sum += directionalLights[i].color * max(dot(N, directionalLights[i].direction), 0.0);
#endif
	return sum;
}
vec3 baker_key_light(vec3 fallback) {
#if NUM_DIR_LIGHTS > 0
	return directionalLights[0].direction;
#else
	return fallback;
#endif
}`;

const viewportSize = new THREE.Vector2();
/** Keep `u_viewport` of a material in drawing-buffer pixels (fins, outlines, hair need pixel widths). */
export function trackViewport(object, uniforms) {
	const previous = object.onBeforeRender;
	object.onBeforeRender = function (renderer, ...rest) {
		renderer.getDrawingBufferSize(viewportSize);
		uniforms.u_viewport.value.copy(viewportSize);
		previous.call(this, renderer, ...rest);
	};
}

export function geometryHas(object, attribute) {
	return Boolean(attribute && object.geometry.getAttribute(attribute.toLowerCase()));
}
