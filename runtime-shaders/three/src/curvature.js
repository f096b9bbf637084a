// BAKER_curvature: a false-colour view of the baked mean curvature (a debug view, off by default).
import { geometryHas } from './common.js';
import { surfacePlugin } from './surface.js';

/** GLTFLoader plugin for BAKER_curvature: a diverging false-colour view of the baked mean curvature (off by default). */
export const BakerCurvaturePlugin = surfacePlugin('curvature', function (ext, object) {
	if (!geometryHas(object, ext.attribute)) return null;
	const range = ext.range ?? [-1, 1];
	return {
		attributes: [[ext.attribute.toLowerCase(), 'float']],
		attribute: ext.attribute.toLowerCase(),
		uniforms: { u_bakerCurvatureScale: { value: Math.max(Math.abs(ext.meanCurvature ?? 0) * 4, Math.abs(range[1]) * 0.5, 1e-6) } },
	};
});
