// BAKER_skin_lut (+ BAKER_curvature's attribute): Penner's pre-integrated skin diffuse (RTR4 14.6.3).
import { BAKER_SKIN_LUT, dataTexture, descriptorUniforms, firstComponent, partModule, setAttribute } from './common.js';
import { surfaceExtension } from './surface.js';

// WGSL has no mat3x3f(mat4x4f): the linear part of Babylon's vertex-stage world matrix
const WORLD3 = 'mat3x3f(finalWorld[0].xyz, finalWorld[1].xyz, finalWorld[2].xyz)';

/** Loader extension for BAKER_skin_lut: the per-light diffuse through the LUT by N.L and curvature. */
export const BakerSkinLutExtension = surfaceExtension('skin', BAKER_SKIN_LUT, async function (ext, mesh, primitive, material) {
	const lut = await dataTexture(this.loader, ext.lutTexture);
	if (!lut) return null;
	if (ext.encoding === 'srgb') lut.gammaSpace = true;
	const size = ext.curvatureAttribute ? await setAttribute(this.loader, mesh, primitive, ext.curvatureAttribute, 'bakerSkinCurvature') : 0;
	// BAKER_curvature's principal curvatures and direction (baker's names): the curvature along the light
	const hasPrincipal = ['_PRINCIPAL_CURVATURES', '_PRINCIPAL_DIRECTION'].every((name) => primitive.attributes?.[name] !== undefined);
	const kSize = hasPrincipal ? await setAttribute(this.loader, mesh, primitive, '_PRINCIPAL_CURVATURES', 'bakerSkinPrincipal') : 0;
	const dSize = hasPrincipal ? await setAttribute(this.loader, mesh, primitive, '_PRINCIPAL_DIRECTION', 'bakerSkinDirection') : 0;
	const principal = kSize >= 2 && dSize === 3;
	const k = kSize === 2 ? 'v_bakerSkinPrincipal' : 'v_bakerSkinPrincipal.xy';
	return {
		...partModule(this, 'skin', material),
		// the direction into world space (the space of normalW and L) in the vertex stage, its length kept (GLSL, WGSL)
		attributes: [...(size ? [['bakerSkinCurvature', size]] : []), ...(principal ? [['bakerSkinPrincipal', kSize],
			['bakerSkinDirection', 3, '(mat3(finalWorld) * bakerSkinDirection) * (length(bakerSkinDirection) / max(length(mat3(finalWorld) * bakerSkinDirection), 1e-20))',
				`${WORLD3} * vertexInputs.bakerSkinDirection * (length(vertexInputs.bakerSkinDirection) / max(length(${WORLD3} * vertexInputs.bakerSkinDirection), 1e-20))`]] : [])],
		// of the surface normal N (not the bump's) and the light L: along the light from the principal curvatures,
		// else the mean curvature, else the per-pixel estimate of RTR4 14.6.3 (screen-space derivatives)
		curvature: (N, L) => (principal ? `baker_skin_curvature_along_light(${k}, v_bakerSkinDirection, ${N}, ${L})`
			: size ? firstComponent('v_bakerSkinCurvature', size) : `baker_skin_curvature_from_derivatives(fwidth(${N}), fwidth(vPositionW))`),
		samplers: { u_bakerSkinLut: lut },
		...descriptorUniforms('skin_lut', ext),
	};
});

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_SKIN_LUT]: BakerSkinLutExtension };
