// BAKER_skin_lut (+ BAKER_curvature's attribute): Penner's pre-integrated skin diffuse.
import * as THREE from 'three';
import { dataTexture, geometryHas, requireShader, textureOf } from './common.js';
import { surfacePlugin } from './surface.js';

const PRINCIPAL = '_PRINCIPAL_CURVATURES';
const DIRECTION = '_PRINCIPAL_DIRECTION';

/** GLTFLoader plugin for BAKER_skin_lut (+ the BAKER_curvature attribute): Penner's pre-integrated skin diffuse. */
export const BakerSkinLutPlugin = surfacePlugin('skin', async function (ext, object, material) {
	const lut = await textureOf(this.parser, ext.lutTexture);
	if (!lut) return null;
	const lutTexture = dataTexture(lut.clone());
	if (ext.encoding === 'srgb') lutTexture.colorSpace = THREE.SRGBColorSpace;
	const attribute = ext.curvatureAttribute && geometryHas(object, ext.curvatureAttribute) ? ext.curvatureAttribute.toLowerCase() : null;
	// BAKER_curvature's principal curvatures and direction (baker's names): the curvature along the light
	const principal = geometryHas(object, PRINCIPAL) && geometryHas(object, DIRECTION);
	const [k, d] = [PRINCIPAL.toLowerCase(), DIRECTION.toLowerCase()];
	const v2 = (a, d) => new THREE.Vector2(...(a ?? d));
	const v3 = (a, d) => new THREE.Vector3(...(a ?? d));
	return {
		glsl: requireShader(this.shaders, 'skin'),
		// the direction into view space (the space of normal and L) in the vertex stage, its length kept
		attributes: [...(attribute ? [[attribute, 'float']] : []), ...(principal ? [[k, 'vec2'], [d, 'vec3',
			`(mat3(modelViewMatrix) * ${d}) * (length(${d}) / max(length(mat3(modelViewMatrix) * ${d}), 1e-20))`]] : [])],
		// of the surface normal N (not the normal map's) and the light L: along the light from the principal
		// curvatures, else the mean curvature, else the per-pixel estimate of RTR4 14.6.3 (screen-space derivatives)
		curvature: (N, L) => (principal ? `baker_skin_curvature_along_light(vBaker${k}, vBaker${d}, ${N}, ${L})`
			: attribute ? `vBaker${attribute}` : `baker_skin_curvature_from_derivatives(fwidth(${N}), fwidth(vViewPosition))`),
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
