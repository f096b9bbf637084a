// Babylon.js glTF loader extensions for baker's BAKER_* extensions (and EXT_mesh_primitive_edge_visibility).
//
//   import '@babylonjs/loaders/glTF/2.0/glTFLoader.js';
//   import { registerBakerExtensions } from '@baker/babylon';
//   import translucency from '@baker/runtime-shaders/baker_translucency.glsl';  // text (e.g. Vite '?raw')
//   registerBakerExtensions({ shaders: { translucency, skin, toon, hatching, edges, fur, hair, text, caustics, cards } });
//   const result = await ImportMeshAsync('asset.glb', scene);
//   const baker = bakerControls(result.meshes[0]);   // the __root__ node
//   baker.setEnabled('toon', false);                // one switch per technique found (baker.techniques)
//
// On WebGPUEngine the same extensions draw WGSL: options.wgsl passes runtime-shaders/baker_*.wgsl as text.
// The GLSL comes from runtime-shaders/ as text: the extensions inject the very modules the reference renders and
// @baker/three use, they do not carry a copy. One extension per module (BAKER_<name> -> <name>.js). Surface
// techniques (translucency, pre-integrated skin, toon ramp, hatching, curvature view, caustics, hair cards) add a MaterialPluginBase to
// the PBRMaterial the loader made, so Babylon's PBR, lights and image processing stay; geometry techniques (fins,
// shell outline, wireframe, fur shells and fins, hair ribbons, MSDF text) add or replace meshes with ShaderMaterials
// that include the matching module, lit by the scene's directional lights. Every extension does its work in
// onReady, when the loader has built the whole scene, and reads custom attributes from their accessors.
import { registerGLTFExtension, unregisterGLTFExtension } from '@babylonjs/loaders/glTF/2.0/glTFLoaderExtensionRegistry.js';
import { RUNTIMES } from '@baker/shared';
import { controls } from './common.js';

export {
	BAKER_CAUSTICS, BAKER_CURVATURE, BAKER_EDGES, BAKER_FUR, BAKER_GLYPH_ATLAS, BAKER_HAIR, BAKER_HAIR_CARDS,
	BAKER_NORMAL_BLUR, BAKER_SKIN_LUT, BAKER_TEXT, BAKER_THICKNESS, BAKER_TONAL_ART_MAP, BAKER_TOON_RAMP,
	EXT_EDGE_VISIBILITY, TECHNIQUES, BakerControls, readAccessor,
} from './common.js';
export { BakerSurfacePlugin } from './surface.js';
export { thicknessParameters } from './thickness.js';
export { tamTextures } from './tonal_art_map.js';
export { wireframeArrays, maskFromVisibility } from './edges.js';
export { ribbonArrays } from './hair.js';
export { textStyle } from './text.js';
// the extension classes by name, as earlier releases exported them; a technique needs none here (EXTENSIONS has it)
export { BakerThicknessExtension } from './thickness.js';
export { BakerCurvatureExtension } from './curvature.js';
export { BakerSkinLutExtension } from './skin_lut.js';
export { BakerToonRampExtension } from './toon_ramp.js';
export { BakerTonalArtMapExtension } from './tonal_art_map.js';
export { BakerEdgesExtension, EdgeVisibilityExtension } from './edges.js';
export { BakerFurExtension } from './fur.js';
export { BakerHairExtension } from './hair.js';
export { BakerGlyphAtlasExtension } from './glyph_atlas.js';
export { BakerTextExtension } from './text.js';
export { BakerCausticsExtension } from './caustics.js';
export { BakerHairCardsExtension } from './hair_cards.js';
export { BakerNormalBlurExtension } from './normal_blur.js';

// Every technique's loader extensions, from its host module <descriptor name>.js (its LOADER_EXTENSIONS: extension
// name -> class, the extensions it uses included), in the descriptors' order: a new technique is registered by its
// descriptor and its module, not by a line here. A bundler includes every ./*.js the template can name (esbuild's
// glob import, Vite's dynamic-import-vars).
const HOST_MODULES = await Promise.all(RUNTIMES.map((r) => import(`./${r.name}.js`)));

/** extension name -> loader extension class (each a glTF extension: used only by files that list it). */
export const EXTENSIONS = Object.assign({}, ...HOST_MODULES.map((module) => module.LOADER_EXTENSIONS));

const CONTROLS = 'BAKER_controls';

/** Publishes the switches of every technique found on the root node (metadata.baker); runs after the others. */
class BakerControlsExtension {
	constructor(loader) {
		this.name = CONTROLS;
		this.enabled = true;
		this.order = 1000;
		this.loader = loader;
	}
	dispose() { this.loader = null; }
	onReady() {
		const root = this.loader.rootBabylonMesh;
		if (root) root.metadata = { ...(root.metadata || {}), baker: controls(this.loader) };
	}
}

// a failure names the extension (Babylon's loader reports only the message)
function named(extension) {
	const onReady = extension.onReady;
	if (onReady) {
		extension.onReady = async function () {
			try {
				return await onReady.call(this);
			} catch (e) {
				throw new Error(`@baker/babylon ${extension.name}: ${e.message}\n${e.stack}`);
			}
		};
	}
	return extension;
}

/**
 * Register every baker loader extension with Babylon's glTF loader (global registry). `options.shaders` holds the
 * runtime-shaders/ modules as text: { translucency, skin, toon, hatching, edges, fur, hair, text, caustics,
 * normalBlur }; `options.wgsl` their WGSL twins (baker_*.wgsl) under the same keys, what a WebGPUEngine draws
 * with (each engine needs only its own language's). Per technique:
 * options.thickness ({ power, scale, distortion, ambient, attenuationDistance, subsurfaceColor } overrides),
 * options.edges ({ color, finWidth, outlineWidth, wireframeWidth, wireframeColor, classes }), options.fur
 * ({ finThreshold }), options.hair ({ specular, exponent }), options.caustics ({ time }: seconds, or a function
 * returning seconds, for the caustic animation's clock). `options.disabled`: extension names not to register
 * (the asset then renders as glTF's standard PBR for them).
 */
export function registerBakerExtensions(options = {}) {
	const disabled = new Set(options.disabled || []);
	for (const [name, Extension] of Object.entries(EXTENSIONS)) {
		unregisterGLTFExtension(name);
		if (!disabled.has(name)) registerGLTFExtension(name, true, (loader) => named(new Extension(loader, options)));
	}
	unregisterGLTFExtension(CONTROLS);
	registerGLTFExtension(CONTROLS, false, (loader) => new BakerControlsExtension(loader));
}

/** Unregister them all (Babylon's loader then ignores the BAKER_* extensions: standard PBR). */
export function unregisterBakerExtensions() {
	for (const name of [...Object.keys(EXTENSIONS), CONTROLS]) unregisterGLTFExtension(name);
}

/** The switches of a loaded asset: bakerControls(root) with the loader's root node (result.meshes[0]). */
export function bakerControls(root) {
	return root?.metadata?.baker ?? null;
}
