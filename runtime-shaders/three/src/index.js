// three.js GLTFLoader plugins for baker's BAKER_* extensions.
//
//   import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
//   import { registerBakerPlugins } from '@baker/three';
//   import translucency from '@baker/runtime-shaders/baker_translucency.glsl';  // text (e.g. Vite '?raw')
//   const loader = registerBakerPlugins(new GLTFLoader(), { shaders: { translucency, skin, edges, ... } });
//   const gltf = await loader.loadAsync('asset.glb');
//   gltf.userData.baker.setEnabled('toon', false);   // one switch per technique found (gltf.userData.baker.techniques)
//
// The GLSL comes from runtime-shaders/ as text: the plugins inject the very modules the reference renders use, they
// do not carry a copy. One plugin per extension, each in its own module (BAKER_<name> -> <name>.js: thickness.js,
// skin_lut.js, toon_ramp.js, tonal_art_map.js, curvature.js, edges.js, fur.js, hair.js, glyph_atlas.js, text.js,
// caustics.js, hair_cards.js, normal_blur.js);
// common.js holds what several use and surface.js the material composition. This module re-exports them and
// registers them. Surface techniques (translucency, pre-integrated skin, toon ramp, hatching, curvature view, caustics,
// hair cards, blurred diffuse normals)
// augment the material GLTFLoader made (MeshStandardMaterial / MeshPhysicalMaterial) through onBeforeCompile, so
// PBR, lights and tone mapping stay; each is gated by a uniform, so a switch costs no recompile. Geometry
// techniques (fins, shell outline, wireframe, fur shells and fins, hair ribbons, MSDF text) add or replace meshes
// with ShaderMaterials that include the matching module, lit by the scene's lights (lights: true).
export {
	BAKER_THICKNESS, BAKER_CURVATURE, BAKER_SKIN_LUT, BAKER_EDGES, BAKER_TONAL_ART_MAP, BAKER_TOON_RAMP,
	BAKER_GLYPH_ATLAS, BAKER_TEXT, BAKER_HAIR, BAKER_FUR, BAKER_CAUSTICS, BAKER_HAIR_CARDS, BAKER_NORMAL_BLUR, TECHNIQUES,
} from './common.js';
import { RUNTIMES } from '@baker/shared';
import { controls } from './common.js';
export { thicknessParameters } from './thickness.js';
export { tamTextures } from './tonal_art_map.js';
export { wireframeGeometry } from './edges.js';
export { ribbonGeometry, setHairLod } from './hair.js';
export { BakerGlyphAtlasPlugin } from './glyph_atlas.js';
// the plugin classes by name, as earlier releases exported them; a technique needs none here (PLUGINS has it)
export { BakerThicknessPlugin } from './thickness.js';
export { BakerCurvaturePlugin } from './curvature.js';
export { BakerSkinLutPlugin } from './skin_lut.js';
export { BakerToonRampPlugin } from './toon_ramp.js';
export { BakerTonalArtMapPlugin } from './tonal_art_map.js';
export { BakerEdgesPlugin } from './edges.js';
export { BakerFurPlugin } from './fur.js';
export { BakerHairPlugin } from './hair.js';
export { BakerTextPlugin } from './text.js';
export { BakerCausticsPlugin } from './caustics.js';
export { BakerHairCardsPlugin } from './hair_cards.js';
export { BakerNormalBlurPlugin } from './normal_blur.js';

// Every technique's plugins, from its host module <descriptor name>.js (its GLTF_LOADER_PLUGINS), in the
// descriptors' order: a new technique is registered by its descriptor and its module, not by a line here. A
// bundler includes every ./*.js the template can name (esbuild's glob import, Vite's dynamic-import-vars).
const HOST_MODULES = await Promise.all(RUNTIMES.map((r) => import(`./${r.name}.js`)));
export const PLUGINS = HOST_MODULES.flatMap((module) => module.GLTF_LOADER_PLUGINS);

// ------------------------------------------------------------------------------------------------ registration
/** Publishes the switches of every technique found as gltf.userData.baker (runs after every other plugin). */
class BakerControlsPlugin {
	constructor(parser) {
		this.parser = parser;
		this.name = 'BAKER_controls';
	}
	afterRoot(result) {
		result.userData ??= {};
		const c = controls(this.parser);
		result.userData.baker = c;
		result.scene.userData.baker = c;
		return null;
	}
}

/**
 * Register every baker plugin on a GLTFLoader. `options.shaders` holds the runtime-shaders/ modules as text:
 * { translucency, skin, toon, hatching, edges, fur, hair, text, caustics, cards, normalBlur } (baker_<name>.glsl;
 * cards: baker_hair_cards.glsl, normalBlur: baker_normal_blur.glsl). `options.edges` overrides
 * the line style ({ color, finWidth, outlineWidth, wireframeWidth, wireframeColor } in pixels / linear RGB);
 * `options.caustics.time` fixes the caustic animation's clock (seconds, or a function returning seconds).
 */
export function registerBakerPlugins(loader, options = {}) {
	for (const Plugin of PLUGINS) loader.register((parser) => new Plugin(parser, options));
	// GLTFLoader runs afterRoot hooks concurrently; this one only publishes the shared object the others fill
	loader.register((parser) => new BakerControlsPlugin(parser));
	return loader;
}
