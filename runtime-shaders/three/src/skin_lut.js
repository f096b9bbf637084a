// BAKER_skin_lut (+ BAKER_curvature's attribute): Penner's pre-integrated skin diffuse.
import * as THREE from 'three';
import { dataTexture, descriptorUniforms, geometryHas, requireShader, textureOf } from './common.js';
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
	const { uniforms, types, struct } = descriptorUniforms('skin_lut', ext);
	return {
		glsl: requireShader(this.shaders, 'skin'),
		// the direction into view space (the space of normal and L) in the vertex stage, its length kept
		attributes: [...(attribute ? [[attribute, 'float']] : []), ...(principal ? [[k, 'vec2'], [d, 'vec3',
			`(mat3(modelViewMatrix) * ${d}) * (length(${d}) / max(length(mat3(modelViewMatrix) * ${d}), 1e-20))`]] : [])],
		// of the surface normal N (not the normal map's) and the light L: along the light from the principal
		// curvatures, else the mean curvature, else the per-pixel estimate of RTR4 14.6.3 (screen-space derivatives)
		curvature: (N, L) => (principal ? `baker_skin_curvature_along_light(vBaker${k}, vBaker${d}, ${N}, ${L})`
			: attribute ? `vBaker${attribute}` : `baker_skin_curvature_from_derivatives(fwidth(${N}), fwidth(vViewPosition))`),
		struct,
		uniforms: { ...uniforms, u_bakerSkinLut: { value: lutTexture } },
		types: { ...types, u_bakerSkinLut: 'sampler2D' },
	};
});

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerSkinLutPlugin];
