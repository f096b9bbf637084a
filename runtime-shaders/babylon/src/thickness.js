// BAKER_thickness: back-lit translucency from the baked per-vertex thickness (GDC 2011 form of RTR4 eq. 14.30).
import { thicknessParameters } from '@baker/shared';
import { descriptorUniforms, firstComponent, partModule, setAttribute, BAKER_THICKNESS } from './common.js';
import { surfaceExtension } from './surface.js';

// the extension's parameters with defaults are engine-neutral (@baker/shared)
export { thicknessParameters };

/** Loader extension for BAKER_thickness; options.thickness overrides the parameters ({ power, scale, ... }). */
export const BakerThicknessExtension = surfaceExtension('translucency', BAKER_THICKNESS, async function (ext, mesh, primitive, material) {
	const params = { ...thicknessParameters(ext), ...(this.options.thickness || {}) };
	if (!params.attribute) return null; // texture-only thickness: not drawn by this extension
	const size = await setAttribute(this.loader, mesh, primitive, params.attribute, 'bakerThickness');
	if (!size) return null;
	return {
		...partModule(this, 'translucency', material),
		attributes: [['bakerThickness', size]],
		thickness: firstComponent('v_bakerThickness', size),
		// options.thickness overrides the extension's properties of the same names
		...descriptorUniforms('thickness', { ...ext, ...(this.options.thickness || {}) }),
	};
});

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_THICKNESS]: BakerThicknessExtension };
