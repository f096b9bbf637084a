// BAKER_thickness: back-lit translucency from the baked per-vertex thickness.
import * as THREE from 'three';
import { geometryHas, requireShader } from './common.js';
import { surfacePlugin } from './surface.js';

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

/** GLTFLoader plugin for BAKER_thickness: back-lit translucency (GDC 2011 form of RTR4 eq. 14.30) per directional light. */
export const BakerThicknessPlugin = surfacePlugin('translucency', function (ext, object, material) {
	const params = thicknessParameters(ext);
	if (!geometryHas(object, params.attribute)) return null; // texture-only thickness: not drawn by this plugin
	material.userData.bakerThickness = params;
	const c = params.subsurfaceColor;
	return {
		glsl: requireShader(this.shaders, 'translucency'),
		attributes: [[params.attribute.toLowerCase(), 'float']],
		attribute: params.attribute.toLowerCase(),
		uniforms: {
			u_bakerThickness: {
				value: {
					attenuationDistance: params.attenuationDistance, distortion: params.distortion, power: params.power,
					scale: params.scale, ambient: params.ambient, subsurfaceColor: new THREE.Vector3(c[0], c[1], c[2]),
				},
			},
		},
		types: { u_bakerThickness: 'BakerThickness' },
	};
});
