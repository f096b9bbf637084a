// BAKER_normal_blur: the diffuse term shaded with per-channel blurred normal maps, the specular term with the
// material's own normalMap (RTR4 14.6.2; runtime-shaders/baker_normal_blur.glsl).
import * as THREE from 'three';
import { requireShader, textureOf } from './common.js';
import { surfacePlugin } from './surface.js';

/**
 * GLTFLoader plugin for BAKER_normal_blur. The three maps are the loader's textures (the file's sampler), read at
 * the normal map's UV (vNormalMapUv) through the normal map's tangent frame (tbn: vertex tangents, or three's
 * derivative frame, for which GLTFLoader negates normalScale.y; the maps follow the same sign). With BAKER_skin_lut
 * on the same material, the skin LUT is read with the per-channel N.L (baker_skin_diffuse_normals).
 */
export const BakerNormalBlurPlugin = surfacePlugin('normalBlur', async function (ext, object, material) {
	if (!material.normalMap || !Array.isArray(ext.diffuseNormalTextures) || ext.diffuseNormalTextures.length !== 3) return null;
	const maps = await Promise.all(ext.diffuseNormalTextures.map((info) => textureOf(this.parser, info)));
	if (maps.some((t) => !t)) return null;
	for (const map of maps) map.colorSpace = THREE.NoColorSpace;  // normals are data
	const flipY = Math.sign(material.normalScale.y) * Math.sign(material.normalScale.x) || 1;
	return {
		glsl: requireShader(this.shaders, 'normalBlur'),
		uniforms: {
			u_bakerNormalBlurRed: { value: maps[0] },
			u_bakerNormalBlurGreen: { value: maps[1] },
			u_bakerNormalBlurBlue: { value: maps[2] },
			u_bakerNormalBlurFlipY: { value: flipY },
		},
		types: { u_bakerNormalBlurRed: 'sampler2D', u_bakerNormalBlurGreen: 'sampler2D', u_bakerNormalBlurBlue: 'sampler2D' },
	};
});

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerNormalBlurPlugin];
