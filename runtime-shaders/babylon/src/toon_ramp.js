// BAKER_toon_ramp: the per-light Lambert term through the baked ramp or X-Toon map (RTR4 15.1; Barla et al. 2006).
import { BAKER_TOON_RAMP, dataTexture, descriptorUniforms, partModule } from './common.js';
import { surfaceExtension } from './surface.js';

/** Loader extension for BAKER_toon_ramp. */
export const BakerToonRampExtension = surfaceExtension('toon', BAKER_TOON_RAMP, async function (ext, mesh, primitive, material) {
	const ramp = await dataTexture(this.loader, ext.rampTexture);
	if (!ramp) return null;
	return {
		...partModule(this, 'toon', material),
		samplers: { u_bakerToonRamp: ramp },
		...descriptorUniforms('toon_ramp', ext),
	};
});

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_TOON_RAMP]: BakerToonRampExtension };
