// BAKER_normal_blur (material): per-channel diffuse normal maps, Penner's smoothed map, the UV stretch map.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const NORMAL_BLUR = 'BAKER_normal_blur';

/** BAKER_normal_blur on a material: the three diffuse normal maps, the smoothed map, the stretch map, kernels. */
export const NormalBlur = defineProperty(NORMAL_BLUR, 'BakerNormalBlur', PropertyType.MATERIAL);

export class BakerNormalBlur extends BakerExtension {
	static EXTENSION_NAME = NORMAL_BLUR;
	static PROPERTIES = [NormalBlur];
	extensionName = NORMAL_BLUR;
}
