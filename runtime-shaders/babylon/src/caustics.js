// BAKER_caustics: the baked, looping caustic frames projected in world space along the refracted sun direction and
// added to the directional (sun) light of the material (RTR4 14.5.3; runtime-shaders/baker_caustics.glsl).
import { causticsClock, causticsFrame, causticsParameters } from '@baker/shared';
import { BAKER_CAUSTICS, dataTexture, descriptorUniforms, partModule } from './common.js';
import { surfaceExtension } from './surface.js';

/**
 * Loader extension for BAKER_caustics. At every bind the two frames of the current time go to the two samplers and
 * their blend weight to a uniform (options.caustics.time: seconds, or a function of none; default the page clock).
 */
export const BakerCausticsExtension = surfaceExtension('caustics', BAKER_CAUSTICS, async function (ext, mesh, primitive, material) {
	const params = causticsParameters(ext);
	if (!params.frameCount) return null;
	const frames = await Promise.all(ext.frameTextures.map((info) => dataTexture(this.loader, info, { repeat: true, mipmaps: true })));
	if (frames.some((t) => !t)) return null;
	const clock = causticsClock(this.options.caustics);
	const samplers = { u_bakerCausticsFirst: frames[0], u_bakerCausticsNext: frames[Math.min(1, frames.length - 1)] };
	const { uniforms } = descriptorUniforms('caustics', ext);
	return {
		...partModule(this, 'caustics', material),
		samplers,
		uniforms,
		textures: frames,
		update() {
			const { first, blend, next } = causticsFrame(clock(), params.period, params.frameCount);
			samplers.u_bakerCausticsFirst = frames[first];
			samplers.u_bakerCausticsNext = frames[next];
			uniforms.u_bakerCausticsBlend.value = blend;
		},
	};
});

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_CAUSTICS]: BakerCausticsExtension };
