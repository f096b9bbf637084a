// @baker/three on three.js's WebGPURenderer (both backends: WebGPU, and WebGL2 with `forceWebGL: true` or no
// adapter). WebGPURenderer draws node materials and never calls onBeforeCompile, so the WebGL plugins' material
// patches do nothing there; this entry point registers the same GLTFLoader plugins (they gather each technique's
// textures, uniforms and attributes, and the switches) and, once the asset is loaded, replaces every material that
// has surface techniques by a node material drawing them in TSL with the runtime-shaders/ modules (./surface.js):
//
//   import { WebGPURenderer } from 'three/webgpu';
//   import { registerBakerNodePlugins } from '@baker/three/node';
//   const loader = registerBakerNodePlugins(new GLTFLoader(), { shaders: { translucency, ... },   // GLSL text
//                                                               wgsl: { translucency, ... } });   // WGSL text
//   const gltf = await loader.loadAsync('asset.glb');
//   gltf.userData.baker.setEnabled('toon', false);
//
// options.wgsl holds the WGSL twins (runtime-shaders/baker_<name>.wgsl) under the same keys as options.shaders: the
// WebGPU backend pastes the WGSL, the WebGL2 backend the GLSL. The geometry techniques (fins, outline, wireframe,
// fur, hair ribbons, text) are ShaderMaterials that WebGPURenderer cannot draw: on this renderer their meshes are
// left out (removed from the scene) and listed in gltf.userData.baker.unsupported; their switches stay.
import { registerBakerPlugins } from '../index.js';
import { BakerModules } from './modules.js';
import { surfaceNodeMaterial } from './surface.js';

export { BakerModules, isWgslBuilder, wgslSignature } from './modules.js';
export { surfaceNodeMaterial, surfaceNodes } from './surface.js';

/** Every mesh material with a BakerSurface becomes its node material; ShaderMaterial meshes are removed. */
export function bakerNodeMaterials(gltf, options = {}) {
	const modules = new BakerModules(options.wgsl || {}, options.shaders || {});
	const converted = new Map();
	const unsupported = new Set();
	const detached = new Set();
	gltf.scene.traverse((object) => {
		if (!object.material) return;
		const list = Array.isArray(object.material) ? object.material : [object.material];
		const replaced = list.map((material) => {
			if (material.isShaderMaterial) {
				unsupported.add(material.name || object.name || 'ShaderMaterial');
				detached.add(object);
				return material;
			}
			if (!material.userData?.bakerSurface) return material;
			if (!converted.has(material)) converted.set(material, surfaceNodeMaterial(material, modules));
			return converted.get(material);
		});
		object.material = Array.isArray(object.material) ? replaced : replaced[0];
	});
	// removed, not hidden: the switches' handlers set `visible` on them
	for (const object of detached) object.removeFromParent();
	const baker = gltf.userData?.baker;
	if (baker) baker.unsupported = [...unsupported];
	return gltf;
}

/**
 * Register every baker plugin on a GLTFLoader for WebGPURenderer: the WebGL plugins, then, when a load finishes,
 * bakerNodeMaterials (GLTFLoader's afterRoot hooks run concurrently, so the conversion waits for the parse's end).
 */
export function registerBakerNodePlugins(loader, options = {}) {
	registerBakerPlugins(loader, options);
	const parse = loader.parse.bind(loader);
	loader.parse = (data, path, onLoad, onError) => parse(data, path, (gltf) => {
		try {
			onLoad(bakerNodeMaterials(gltf, options));
		} catch (e) {
			if (onError) onError(e); else throw e;
		}
	}, onError);
	return loader;
}
