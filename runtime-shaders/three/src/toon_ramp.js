// BAKER_toon_ramp: the Lambert term through the baked ramp or X-Toon map.
import { dataTexture, descriptorUniforms, requireShader, textureOf } from './common.js';
import { surfacePlugin } from './surface.js';

/** GLTFLoader plugin for BAKER_toon_ramp: the Lambert term through the baked ramp (or X-Toon map). */
export const BakerToonRampPlugin = surfacePlugin('toon', async function (ext) {
	const ramp = await textureOf(this.parser, ext.rampTexture);
	if (!ramp) return null;
	const { uniforms, types } = descriptorUniforms('toon_ramp', ext);
	return {
		glsl: requireShader(this.shaders, 'toon'),
		uniforms: { ...uniforms, u_bakerToonRamp: { value: dataTexture(ramp.clone()) } },
		types: { ...types, u_bakerToonRamp: 'sampler2D' },
	};
});

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerToonRampPlugin];
