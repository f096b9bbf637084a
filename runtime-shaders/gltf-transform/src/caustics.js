// BAKER_caustics (material): the frame textures of a looping caustic sequence.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const CAUSTICS = 'BAKER_caustics';

/** BAKER_caustics on a material: the frames of one loop (textures) and how to project and animate them. */
export const Caustics = defineProperty(CAUSTICS, 'BakerCaustics', PropertyType.MATERIAL);

export class BakerCaustics extends BakerExtension {
	static EXTENSION_NAME = CAUSTICS;
	static PROPERTIES = [Caustics];
	extensionName = CAUSTICS;
}
