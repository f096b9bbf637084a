// BAKER_curvature: a false-colour view of the baked mean curvature (a debug view, off by default).
import { descriptorUniforms, geometryHas } from './common.js';
import { surfacePlugin } from './surface.js';

/** GLTFLoader plugin for BAKER_curvature: a diverging false-colour view of the baked mean curvature (off by default). */
export const BakerCurvaturePlugin = surfacePlugin('curvature', function (ext, object) {
	if (!geometryHas(object, ext.attribute)) return null;
	return {
		attributes: [[ext.attribute.toLowerCase(), 'float']],
		attribute: ext.attribute.toLowerCase(),
		...descriptorUniforms('curvature', ext),
	};
});

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerCurvaturePlugin];
