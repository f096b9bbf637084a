// BAKER_skin_lut (+ BAKER_curvature's attribute): Penner's pre-integrated skin diffuse (RTR4 14.6.3).
import { BAKER_SKIN_LUT, dataTexture, firstComponent, requireShader, setAttribute } from './common.js';
import { surfaceExtension } from './surface.js';

/** Loader extension for BAKER_skin_lut: the per-light diffuse through the LUT by N.L and curvature. */
export const BakerSkinLutExtension = surfaceExtension('skin', BAKER_SKIN_LUT, async function (ext, mesh, primitive) {
	const lut = await dataTexture(this.loader, ext.lutTexture);
	if (!lut) return null;
	if (ext.encoding === 'srgb') lut.gammaSpace = true;
	const size = ext.curvatureAttribute ? await setAttribute(this.loader, mesh, primitive, ext.curvatureAttribute, 'bakerSkinCurvature') : 0;
	const v = (a, d) => (a ?? d).slice();
	return {
		glsl: requireShader(this.shaders, 'skin'),
		attributes: size ? [['bakerSkinCurvature', size]] : [],
		// without the baked attribute: the per-pixel estimate of RTR4 14.6.3 (screen-space derivatives)
		curvature: size ? firstComponent('v_bakerSkinCurvature', size) : 'baker_skin_curvature_from_derivatives(fwidth(normalW), fwidth(vPositionW))',
		struct: 'BakerSkin(u_bakerSkinCurvatureRange, u_bakerSkinCurvatureScale, u_bakerSkinPenumbraRange, u_bakerSkinNormalBlend, u_bakerSkinWrap, u_bakerSkinScatterWidth, u_bakerSkinScatterColor)',
		samplers: { u_bakerSkinLut: lut },
		uniforms: {
			u_bakerSkinCurvatureRange: { type: 'vec2', value: v(ext.curvatureRange, [0.01, 1]) },
			u_bakerSkinCurvatureScale: { type: 'float', value: ext.curvatureScale ?? 1 },
			u_bakerSkinPenumbraRange: { type: 'vec2', value: v(ext.penumbraWidthRange, [0.01, 1]) },
			u_bakerSkinNormalBlend: { type: 'vec3', value: v(ext.normalBlend, [1, 0.5, 0.25]) },
			u_bakerSkinWrap: { type: 'float', value: ext.wrap ?? 0.5 },
			u_bakerSkinScatterWidth: { type: 'float', value: ext.scatterWidth ?? 0.3 },
			u_bakerSkinScatterColor: { type: 'vec3', value: v(ext.scatterColor, [0.8, 0.25, 0.1]) },
		},
	};
});
