// BAKER_curvature: a false-colour view of the baked mean curvature (a debug view, off by default).
import { BAKER_CURVATURE, descriptorUniforms, firstComponent, setAttribute } from './common.js';
import { surfaceExtension } from './surface.js';

/** Loader extension for BAKER_curvature: blue concave, white flat, red convex. */
export const BakerCurvatureExtension = surfaceExtension('curvature', BAKER_CURVATURE, async function (ext, mesh, primitive) {
	const size = ext.attribute ? await setAttribute(this.loader, mesh, primitive, ext.attribute, 'bakerCurvature') : 0;
	if (!size) return null;
	return {
		attributes: [['bakerCurvature', size]],
		value: firstComponent('v_bakerCurvature', size),
		...descriptorUniforms('curvature', ext),
	};
});

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_CURVATURE]: BakerCurvatureExtension };
