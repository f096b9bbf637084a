// BAKER_curvature: a false-colour view of the baked mean curvature (a debug view, off by default).
import { BAKER_CURVATURE, firstComponent, setAttribute } from './common.js';
import { surfaceExtension } from './surface.js';

/** Loader extension for BAKER_curvature: blue concave, white flat, red convex. */
export const BakerCurvatureExtension = surfaceExtension('curvature', BAKER_CURVATURE, async function (ext, mesh, primitive) {
	const size = ext.attribute ? await setAttribute(this.loader, mesh, primitive, ext.attribute, 'bakerCurvature') : 0;
	if (!size) return null;
	const range = ext.range ?? [-1, 1];
	return {
		attributes: [['bakerCurvature', size]],
		value: firstComponent('v_bakerCurvature', size),
		uniforms: {
			u_bakerCurvatureScale: { type: 'float', value: Math.max(Math.abs(ext.meanCurvature ?? 0) * 4, Math.abs(range[1]) * 0.5, 1e-6) },
		},
	};
});
