// BAKER_toon_ramp: the Lambert term through the baked ramp or X-Toon map.
import * as THREE from 'three';
import { dataTexture, requireShader, textureOf } from './common.js';
import { surfacePlugin } from './surface.js';

/** GLTFLoader plugin for BAKER_toon_ramp: the Lambert term through the baked ramp (or X-Toon map). */
export const BakerToonRampPlugin = surfacePlugin('toon', async function (ext) {
	const ramp = await textureOf(this.parser, ext.rampTexture);
	if (!ramp) return null;
	const xtoon = { none: 0, depth: 1, orientation: 2 }[ext.xtoon ?? 'none'] ?? 0;
	return {
		glsl: requireShader(this.shaders, 'toon'),
		uniforms: {
			u_bakerToonRamp: { value: dataTexture(ramp.clone()) },
			u_bakerToonXtoon: { value: xtoon },
			u_bakerToonDepthRange: { value: new THREE.Vector2(...(ext.depthRange ?? [1, 100])) },
			u_bakerToonOrientationPower: { value: ext.orientationPower ?? 1 },
		},
		types: { u_bakerToonRamp: 'sampler2D', u_bakerToonXtoon: 'int', u_bakerToonDepthRange: 'vec2' },
	};
});
