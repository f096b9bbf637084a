// Engine-neutral parts of baker's web runtimes (@baker/three, @baker/babylon): the runtime descriptors
// (techniques.js) and what is derived from them (extension names, the techniques' switches), the per-load registry
// of the switches' on/off handlers, and the lookup of a runtime-shaders module in the options. No engine import
// here: each runtime adds what its engine needs in its own common.js.

import { RUNTIMES } from './techniques.js';
import { STAGES, STAGES_WGSL } from './stages.js';

export { RUNTIMES, runtime, runtimeOfSwitch } from './techniques.js';
export { structExpression, uniformValue, uniformValues } from './values.js';
export { STAGES, STAGES_WGSL } from './stages.js';
export { BAKER_HAIR_SHADING, HAIR_SHADINGS, hairShadingChoice, hairShadingGlsl, hairShadingOf, hairTableTexels, longitudinalVariances } from './hair_shading.js';

const extensionOf = (name) => RUNTIMES.find((r) => r.name === name).extension;
export const BAKER_THICKNESS = extensionOf('thickness');
export const BAKER_CURVATURE = extensionOf('curvature');
export const BAKER_SKIN_LUT = extensionOf('skin_lut');
export const BAKER_EDGES = extensionOf('edges');
export const BAKER_TONAL_ART_MAP = extensionOf('tonal_art_map');
export const BAKER_TOON_RAMP = extensionOf('toon_ramp');
export const BAKER_GLYPH_ATLAS = 'BAKER_glyph_atlas';
export const BAKER_TEXT = extensionOf('text');
export const BAKER_HAIR = extensionOf('hair');
export const BAKER_FUR = extensionOf('fur');
export const BAKER_CAUSTICS = extensionOf('caustics');
export const BAKER_HAIR_CARDS = extensionOf('hair_cards');
export const BAKER_NORMAL_BLUR = extensionOf('normal_blur');

/**
 * Techniques (switch names) and the extension each comes from, in display order (RUNTIMES' order). Techniques off
 * by default are debug views.
 */
export const TECHNIQUES = Object.fromEntries(RUNTIMES.flatMap((r) => r.switches.map((s) => [s.name,
	{ extension: r.extension, label: s.label, ...(s.defaultOff ? { defaultOff: true } : {}) }])));

// options.shaders key -> runtime-shaders/ file, for the message naming a missing module
const GLSL_NAMES = Object.fromEntries(RUNTIMES.filter((r) => r.modules.key).map((r) => [r.modules.key, r.modules.glsl]));
GLSL_NAMES.hairShading = 'baker_hair_shading.glsl'; // BAKER_hair_shading's module (hair and cards include it)

/** The runtime-shaders module `key` of options.shaders, as given; throws a message naming the file when missing. */
export function shaderText(shaders, key, packageName) {
	const glsl = shaders[key];
	if (!glsl) throw new Error(`${packageName}: options.shaders.${key} (runtime-shaders/${GLSL_NAMES[key]} as text) is missing`);
	return glsl;
}

/**
 * The host-neutral surface parts (a descriptor's `surface`: a stage of hosts/web/) of the techniques among `parts`
 * (an object keyed by switch name) injected at `point`, in the descriptors' order; '' when there is none. The host
 * wraps them in a block defining the point's names (techniques.js).
 */
export function surfaceStages(parts, point, language = 'glsl') {
	const stages = language === 'wgsl' ? STAGES_WGSL : STAGES; // 'wgsl': the stages' WGSL twins (hosts/web/*.wgsl)
	return RUNTIMES.filter((r) => r.surface?.point === point && r.switches.some((s) => parts[s.name]))
		.map((r) => stages[r.surface.stage]).join('\n');
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
export { coverageMipLevels, coverageMipsOf, decodePngRgba8, parseKtx2Rgba8 } from './coverage_mips.js';
