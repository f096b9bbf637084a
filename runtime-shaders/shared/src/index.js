// Engine-neutral parts of baker's web runtimes (@baker/three, @baker/babylon): the extension names, the techniques
// (switch names) and the per-load registry of their on/off handlers, and the lookup of a runtime-shaders module in
// the options. No engine import here: each runtime adds what its engine needs in its own common.js.

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
export const BAKER_CAUSTICS = 'BAKER_caustics';
export const BAKER_HAIR_CARDS = 'BAKER_hair_cards';
export const BAKER_NORMAL_BLUR = 'BAKER_normal_blur';

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
	caustics: { extension: BAKER_CAUSTICS, label: 'caustics' },
	cards: { extension: BAKER_HAIR_CARDS, label: 'hair cards (Kajiya-Kay)' },
	normalBlur: { extension: BAKER_NORMAL_BLUR, label: 'blurred diffuse normals' },
	curvature: { extension: BAKER_CURVATURE, label: 'curvature view', defaultOff: true },
};

const GLSL_NAMES = {
	translucency: 'baker_translucency.glsl', skin: 'baker_skin.glsl', toon: 'baker_toon.glsl',
	hatching: 'baker_hatching.glsl', edges: 'baker_edges.glsl', fur: 'baker_fur.glsl', hair: 'baker_hair.glsl',
	text: 'baker_text.glsl', caustics: 'baker_caustics.glsl', cards: 'baker_hair_cards.glsl',
	normalBlur: 'baker_normal_blur.glsl',
};

/** The runtime-shaders module `key` of options.shaders, as given; throws a message naming the file when missing. */
export function shaderText(shaders, key, packageName) {
	const glsl = shaders[key];
	if (!glsl) throw new Error(`${packageName}: options.shaders.${key} (runtime-shaders/${GLSL_NAMES[key]} as text) is missing`);
	return glsl;
}

// ------------------------------------------------------------------------------------------------ switches
/**
 * One per loaded asset: every plugin/extension adds its technique's on/off handler; the runtime publishes it
 * (three: gltf.userData.baker, Babylon: the root node's metadata).
 */
export class BakerControls {
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
/** The BakerControls of one load, keyed by the loader's per-asset object (three: parser, Babylon: loader). */
export function controls(owner) {
	if (!controlsOf.has(owner)) controlsOf.set(owner, new BakerControls());
	return controlsOf.get(owner);
}

export { thicknessParameters } from './thickness.js';
export { textFieldType, textShadowOffset, textStyle } from './text.js';
export { wireframeCorners } from './edges.js';
export { causticsClock, causticsFrame, causticsParameters } from './caustics.js';
export { coverageMipsOf, parseKtx2Rgba8 } from './coverage_mips.js';
