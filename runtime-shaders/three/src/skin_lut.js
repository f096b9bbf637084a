// BAKER_skin_lut (+ BAKER_curvature's attribute): Penner's pre-integrated skin diffuse.
import * as THREE from 'three';
import { dataTexture, geometryHas, requireShader, textureOf } from './common.js';
import { surfacePlugin } from './surface.js';

/** GLTFLoader plugin for BAKER_skin_lut (+ the BAKER_curvature attribute): Penner's pre-integrated skin diffuse. */
export const BakerSkinLutPlugin = surfacePlugin('skin', async function (ext, object, material) {
	const lut = await textureOf(this.parser, ext.lutTexture);
	if (!lut) return null;
	const lutTexture = dataTexture(lut.clone());
	if (ext.encoding === 'srgb') lutTexture.colorSpace = THREE.SRGBColorSpace;
	const attribute = ext.curvatureAttribute && geometryHas(object, ext.curvatureAttribute) ? ext.curvatureAttribute.toLowerCase() : null;
	const v2 = (a, d) => new THREE.Vector2(...(a ?? d));
	const v3 = (a, d) => new THREE.Vector3(...(a ?? d));
	return {
		glsl: requireShader(this.shaders, 'skin'),
		attributes: attribute ? [[attribute, 'float']] : [],
		// without the baked attribute: the per-pixel estimate of RTR4 14.6.3 (screen-space derivatives)
		curvature: attribute ? `vBaker${attribute}` : 'baker_skin_curvature_from_derivatives(fwidth(normal), fwidth(vViewPosition))',
		uniforms: {
			u_bakerSkinLut: { value: lutTexture },
			u_bakerSkin: {
				value: {
					curvatureRange: v2(ext.curvatureRange, [0.01, 1]), curvatureScale: ext.curvatureScale ?? 1,
					penumbraWidthRange: v2(ext.penumbraWidthRange, [0.01, 1]), normalBlend: v3(ext.normalBlend, [1, 0.5, 0.25]),
					wrap: ext.wrap ?? 0.5, scatterWidth: ext.scatterWidth ?? 0.3, scatterColor: v3(ext.scatterColor, [0.8, 0.25, 0.1]),
				},
			},
		},
		types: { u_bakerSkinLut: 'sampler2D', u_bakerSkin: 'BakerSkin' },
	};
});
