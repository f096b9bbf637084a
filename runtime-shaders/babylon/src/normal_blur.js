// BAKER_normal_blur: the diffuse term shaded with per-channel blurred normal maps, the specular term with the
// material's own bump texture (RTR4 14.6.2; runtime-shaders/baker_normal_blur.glsl).
import { BAKER_NORMAL_BLUR, dataTexture, partModule } from './common.js';
import { surfaceExtension } from './surface.js';

/**
 * Loader extension for BAKER_normal_blur. The three maps are read at the bump texture's UV (vBumpUV) through the
 * frame Babylon built for it (TBN: vertex tangents, or its cotangent frame with the loader's tangent-space signs),
 * so the blurred normals sit where the material's own normal does. With BAKER_skin_lut on the same material the
 * LUT is read with the per-channel N.L (baker_skin_diffuse_normals).
 */
export const BakerNormalBlurExtension = surfaceExtension('normalBlur', BAKER_NORMAL_BLUR, async function (ext, mesh, primitive, material) {
	if (!material.bumpTexture || !Array.isArray(ext.diffuseNormalTextures) || ext.diffuseNormalTextures.length !== 3) return null;
	const maps = await Promise.all(ext.diffuseNormalTextures.map((info) => dataTexture(this.loader, info, { repeat: true, mipmaps: true })));
	if (maps.some((t) => !t)) return null;
	return {
		...partModule(this, 'normalBlur', material),
		samplers: { u_bakerNormalBlurRed: maps[0], u_bakerNormalBlurGreen: maps[1], u_bakerNormalBlurBlue: maps[2] },
		uniforms: {},
	};
});

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_NORMAL_BLUR]: BakerNormalBlurExtension };
