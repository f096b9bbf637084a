// three.js GLTFLoader plugins for baker's BAKER_* extensions.
//
//   import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
//   import { registerBakerPlugins } from '@baker/three';
//   import translucency from '@baker/runtime-shaders/baker_translucency.glsl';  // text (e.g. Vite '?raw')
//   const loader = registerBakerPlugins(new GLTFLoader(), { shaders: { translucency } });
//
// The GLSL comes from runtime-shaders/ as text: the plugin injects the very module the reference renders use, it
// does not carry a copy. Each plugin reads its extension from the parser's JSON after the scene is built and
// augments the three.js material that GLTFLoader made (MeshStandardMaterial / MeshPhysicalMaterial) through
// onBeforeCompile, so everything three.js already does (PBR, shadows, tone mapping) stays.

export const BAKER_THICKNESS = 'BAKER_thickness';

/** Translucency parameters of a material's BAKER_thickness, with the extension's defaults filled in. */
export function thicknessParameters(ext) {
	const color = ext.subsurfaceColor ?? [1, 1, 1];
	return {
		attenuationDistance: ext.attenuationDistance ?? ext.meanThickness ?? 1,
		distortion: ext.distortion ?? 0.2,
		power: ext.power ?? 4,
		scale: ext.scale ?? 1,
		ambient: ext.ambient ?? 0,
		subsurfaceColor: color.slice(0, 3),
		attribute: ext.attribute ?? null,
	};
}

/**
 * Add back-lit translucency (RTR4 eq. 14.30, GDC 2011 variant) to a three.js lit material, per directional light,
 * reading the per-vertex thickness attribute. `glsl` is runtime-shaders/baker_translucency.glsl.
 */
export function applyTranslucency(material, params, glsl) {
	const attribute = (params.attribute || '_THICKNESS').toLowerCase(); // GLTFLoader lowercases custom names
	material.userData.bakerThickness = params;
	const uniforms = {
		u_bakerThickness: {
			value: {
				attenuationDistance: params.attenuationDistance,
				distortion: params.distortion,
				power: params.power,
				scale: params.scale,
				ambient: params.ambient,
				subsurfaceColor: { x: params.subsurfaceColor[0], y: params.subsurfaceColor[1], z: params.subsurfaceColor[2] },
			},
		},
		u_bakerTranslucencyEnabled: { value: 1 },
	};
	material.userData.bakerUniforms = uniforms;
	const previous = material.onBeforeCompile;
	material.onBeforeCompile = (shader, renderer) => {
		if (previous) previous(shader, renderer);
		Object.assign(shader.uniforms, uniforms);
		shader.vertexShader = shader.vertexShader
			.replace('#include <common>', `#include <common>\nattribute float ${attribute};\nvarying float vBakerThickness;`)
			.replace('#include <begin_vertex>', `#include <begin_vertex>\nvBakerThickness = ${attribute};`);
		shader.fragmentShader = shader.fragmentShader
			.replace('#include <common>', `#include <common>\n${glsl}\nuniform BakerThickness u_bakerThickness;\n` +
				'uniform float u_bakerTranslucencyEnabled;\nvarying float vBakerThickness;')
			.replace('#include <lights_fragment_end>', `#include <lights_fragment_end>
#if NUM_DIR_LIGHTS > 0
	for (int i = 0; i < NUM_DIR_LIGHTS; i++) {
		vec3 bakerL = directionalLights[i].direction;  // view space, towards the light
		reflectedLight.directDiffuse += u_bakerTranslucencyEnabled * diffuseColor.rgb * directionalLights[i].color *
			baker_translucency(u_bakerThickness, normal, normalize(vViewPosition), bakerL, vBakerThickness);
	}
#endif`);
	};
	material.customProgramCacheKey = () => `baker-translucency-${attribute}`;
	material.needsUpdate = true;
	return material;
}

/** GLTFLoader plugin for BAKER_thickness. */
export class BakerThicknessPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_THICKNESS;
		this.shaders = options.shaders || {};
	}

	afterRoot(result) {
		const json = this.parser.json;
		const materials = json.materials || [];
		const done = new Set();
		result.scene.traverse((object) => {
			if (!object.isMesh) return;
			for (const material of Array.isArray(object.material) ? object.material : [object.material]) {
				const association = this.parser.associations.get(material);
				const index = association && association.materials;
				const ext = index !== undefined && materials[index]?.extensions?.[BAKER_THICKNESS];
				if (!ext || done.has(material)) continue;
				done.add(material);
				const params = thicknessParameters(ext);
				const hasAttribute = params.attribute && object.geometry.getAttribute(params.attribute.toLowerCase());
				if (hasAttribute && this.shaders.translucency) applyTranslucency(material, params, this.shaders.translucency);
			}
		});
		return null;
	}
}

/** Register every baker plugin on a GLTFLoader. `options.shaders` holds the runtime-shaders/ modules as text. */
export function registerBakerPlugins(loader, options = {}) {
	loader.register((parser) => new BakerThicknessPlugin(parser, options));
	return loader;
}
