// BAKER_curvature (material): settings, attribute names and the optional curvature texture.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const CURVATURE = 'BAKER_curvature';

/** BAKER_curvature on a material: settings, attribute names and the optional `curvatureTexture`. */
export const Curvature = defineProperty(CURVATURE, 'BakerCurvature', PropertyType.MATERIAL);

export class BakerCurvature extends BakerExtension {
	static EXTENSION_NAME = CURVATURE;
	static PROPERTIES = [Curvature];
	extensionName = CURVATURE;
}
