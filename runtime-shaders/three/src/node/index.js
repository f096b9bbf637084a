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
// fur shells and fins, hair ribbons, MSDF text), ShaderMaterials of the shared stages on WebGLRenderer, become
// MeshBasicNodeMaterials with positionNode / vertexNode and fragmentNode (./geometry.js).
import { registerBakerPlugins } from '../index.js';
import { BakerModules } from './modules.js';
import { geometryNodeMaterial } from './geometry.js';
import { surfaceNodeMaterial } from './surface.js';

export { BakerModules, isWgslBuilder, wgslSignature } from './modules.js';
export { surfaceNodeMaterial, surfaceNodes } from './surface.js';
export { geometryNodeMaterial, stageOf } from './geometry.js';

/**
 * Every mesh material with a BakerSurface becomes its node material (./surface.js), every ShaderMaterial of a
 * geometry technique its node material (./geometry.js). A mesh whose material was a ShaderMaterial keeps mapping:
 * the plugins' switches assign the ShaderMaterial again (MSDF text swaps it with glTF's fallback), and the node
 * material is what gets drawn. A ShaderMaterial that is none of the shared stages is left out (its mesh removed)
 * and listed in gltf.userData.baker.unsupported.
 */
export function bakerNodeMaterials(gltf, options = {}) {
	const modules = new BakerModules(options.wgsl || {}, options.shaders || {});
	const converted = new Map();
	const unsupported = new Set();
	const detached = new Set();
	const nodeOf = (material) => {
		if (!material || material.isNodeMaterial) return material;
		if (!converted.has(material)) {
			converted.set(material, material.isShaderMaterial ? geometryNodeMaterial(material, modules)
				: material.userData?.bakerSurface ? surfaceNodeMaterial(material, modules) : material);
		}
		return converted.get(material);
	};
	gltf.scene.traverse((object) => {
		if (!object.material) return;
		const list = Array.isArray(object.material) ? object.material : [object.material];
		if (list.some((material) => material.isShaderMaterial && !nodeOf(material))) {
			for (const material of list) if (material.isShaderMaterial && !nodeOf(material)) unsupported.add(material.name || 'ShaderMaterial');
			detached.add(object);
			return;
		}
		const mapped = (value) => (Array.isArray(value) ? value.map(nodeOf) : nodeOf(value));
		if (list.some((material) => material.isShaderMaterial)) {
			// the switches set `material` to the ShaderMaterial again: map it on assignment
			let current = mapped(object.material);
			Object.defineProperty(object, 'material', {
				configurable: true, enumerable: true,
				get: () => current,
				set: (value) => { current = mapped(value); },
			});
		} else {
			object.material = mapped(object.material);
		}
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
