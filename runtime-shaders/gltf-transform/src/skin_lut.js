// BAKER_skin_lut (material): Penner's pre-integrated skin LUT and penumbra LUT, the optional curvature texture.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const SKIN = 'BAKER_skin_lut';

/** BAKER_skin_lut on a material: the LUT and penumbra textures, the optional curvature texture, parameters. */
export const SkinLut = defineProperty(SKIN, 'BakerSkinLut', PropertyType.MATERIAL);

export class BakerSkinLut extends BakerExtension {
	static EXTENSION_NAME = SKIN;
	static PROPERTIES = [SkinLut];
	extensionName = SKIN;
}
