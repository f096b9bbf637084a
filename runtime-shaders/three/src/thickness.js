// BAKER_thickness: back-lit translucency from the baked per-vertex thickness.
import { thicknessParameters } from '@baker/shared';
import { descriptorUniforms, geometryHas, requireShader } from './common.js';
import { surfacePlugin } from './surface.js';

// the extension's parameters with defaults are engine-neutral (@baker/shared)
export { thicknessParameters };

/** GLTFLoader plugin for BAKER_thickness: back-lit translucency (GDC 2011 form of RTR4 eq. 14.30) per directional light. */
export const BakerThicknessPlugin = surfacePlugin('translucency', function (ext, object, material) {
	const params = thicknessParameters(ext);
	if (!geometryHas(object, params.attribute)) return null; // texture-only thickness: not drawn by this plugin
	material.userData.bakerThickness = params;
	return {
		glsl: requireShader(this.shaders, 'translucency'),
		attributes: [[params.attribute.toLowerCase(), 'float']],
		attribute: params.attribute.toLowerCase(),
		...descriptorUniforms('thickness', ext),
	};
});

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerThicknessPlugin];
