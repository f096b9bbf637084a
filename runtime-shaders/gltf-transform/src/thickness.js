// BAKER_thickness (material): bake settings, translucency parameters and the thickness texture (a graph edge).
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const THICKNESS = 'BAKER_thickness';

/** BAKER_thickness on a material: bake settings, translucency parameters and `thicknessTexture`
 * (schemas/BAKER_thickness). On single-sided materials the same texture is KHR_materials_volume's too, carried by
 * KHRONOS_EXTENSIONS. */
export class Thickness extends defineProperty(THICKNESS, 'BakerThickness', PropertyType.MATERIAL) {
	/** Name of the per-vertex attribute holding thickness in mesh units, or null. */
	getAttribute() {
		return this.get('params').attribute ?? null;
	}
}

export class BakerThickness extends BakerExtension {
	static EXTENSION_NAME = THICKNESS;
	static PROPERTIES = [Thickness];
	extensionName = THICKNESS;

	createThickness() {
		return this.createProperty(PropertyType.MATERIAL);
	}
}
