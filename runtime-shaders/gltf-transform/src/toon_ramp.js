// BAKER_toon_ramp (material): the ramp or X-Toon texture.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const TOON = 'BAKER_toon_ramp';

/** BAKER_toon_ramp on a material: the ramp (or X-Toon map) texture and the band parameters. */
export const ToonRamp = defineProperty(TOON, 'BakerToonRamp', PropertyType.MATERIAL);

export class BakerToonRamp extends BakerExtension {
	static EXTENSION_NAME = TOON;
	static PROPERTIES = [ToonRamp];
	extensionName = TOON;
}
