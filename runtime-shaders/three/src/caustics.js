// BAKER_caustics: the baked, looping caustic frames projected in world space along the refracted sun direction and
// added to the directional (sun) light of the material (RTR4 14.5.3; runtime-shaders/baker_caustics.glsl).
import { causticsClock, causticsFrame, causticsParameters } from '@baker/shared';
import { descriptorUniforms, requireShader, textureOf } from './common.js';
import { surfacePlugin } from './surface.js';

/**
 * GLTFLoader plugin for BAKER_caustics. The frames are the loader's textures (REPEAT, mipmapped, as the file's
 * sampler says; 4x anisotropic); before each draw of the material the two frames of the current time go to the two
 * samplers and their blend weight to a uniform (options.caustics.time: seconds, or a function of none; default the
 * page clock).
 */
export const BakerCausticsPlugin = surfacePlugin('caustics', async function (ext, object, material) {
	const params = causticsParameters(ext);
	if (!params.frameCount) return null;
	const frames = await Promise.all(ext.frameTextures.map((info) => textureOf(this.parser, info)));
	if (frames.some((t) => !t)) return null;
	// the floor is mostly seen at a grazing angle: filtered anisotropically, as Babylon.js does by default (4)
	for (const frame of frames) frame.anisotropy = Math.max(frame.anisotropy, 4);
	const clock = causticsClock(this.options.caustics);
	const part = descriptorUniforms('caustics', ext);
	const uniforms = {
		...part.uniforms,
		u_bakerCausticsFirst: { value: frames[0] },
		u_bakerCausticsNext: { value: frames[Math.min(1, frames.length - 1)] },
	};
	const previous = material.onBeforeRender;
	material.onBeforeRender = function (...args) {
		const { first, blend, next } = causticsFrame(clock(), params.period, params.frameCount);
		uniforms.u_bakerCausticsFirst.value = frames[first];
		uniforms.u_bakerCausticsNext.value = frames[next];
		uniforms.u_bakerCausticsBlend.value = blend;
		previous.apply(this, args);
	};
	return {
		glsl: requireShader(this.shaders, 'caustics'),
		worldPosition: true,
		uniforms,
		types: { ...part.types, u_bakerCausticsFirst: 'sampler2D', u_bakerCausticsNext: 'sampler2D' },
	};
});

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerCausticsPlugin];
