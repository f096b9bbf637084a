// BAKER_toon_ramp: the per-light Lambert term through the baked ramp or X-Toon map (RTR4 15.1; Barla et al. 2006).
import { BAKER_TOON_RAMP, dataTexture, requireShader } from './common.js';
import { surfaceExtension } from './surface.js';

/** Loader extension for BAKER_toon_ramp. */
export const BakerToonRampExtension = surfaceExtension('toon', BAKER_TOON_RAMP, async function (ext) {
	const ramp = await dataTexture(this.loader, ext.rampTexture);
	if (!ramp) return null;
	return {
		glsl: requireShader(this.shaders, 'toon'),
		samplers: { u_bakerToonRamp: ramp },
		uniforms: {
			// a float: an int in the uniform block would differ in precision between the stages
			u_bakerToonXtoon: { type: 'float', value: { none: 0, depth: 1, orientation: 2 }[ext.xtoon ?? 'none'] ?? 0 },
			u_bakerToonDepthRange: { type: 'vec2', value: (ext.depthRange ?? [1, 100]).slice() },
			u_bakerToonOrientationPower: { type: 'float', value: ext.orientationPower ?? 1 },
		},
	};
});
