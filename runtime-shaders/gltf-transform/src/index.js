// glTF-Transform extensions for baker's BAKER_* glTF extensions.
//
// glTF-Transform drops extensions it has no class for when it writes a document, so a pipeline running
// `optimize`, `prune` or `dedup` on a baked asset would lose the baked data. Register these classes (next to
// KHRONOS_EXTENSIONS, which carries KHR_materials_volume's thickness texture) and the data survives:
//
//   import { NodeIO } from '@gltf-transform/core';
//   import { KHRONOS_EXTENSIONS } from '@gltf-transform/extensions';
//   import { BAKER_EXTENSIONS } from '@baker/gltf-transform';
//   const io = new NodeIO().registerExtensions([...KHRONOS_EXTENSIONS, ...BAKER_EXTENSIONS]);
//
// Custom vertex attributes (`_THICKNESS`, ...) are kept by glTF-Transform itself: `prune` only removes unused
// NORMAL, TANGENT, TEXCOORD_n and COLOR_n (n > 0).
import { Extension, ExtensionProperty, PropertyType } from '@gltf-transform/core';

// ------------------------------------------------------------------------------------------- BAKER_thickness
const THICKNESS = 'BAKER_thickness';

/** BAKER_thickness on a material: bake settings and translucency parameters (schemas/BAKER_thickness). */
export class Thickness extends ExtensionProperty {
	static EXTENSION_NAME = THICKNESS;

	init() {
		this.extensionName = THICKNESS;
		this.propertyType = 'BakerThickness';
		this.parentTypes = [PropertyType.MATERIAL];
	}

	getDefaults() {
		return Object.assign(super.getDefaults(), { params: {} });
	}

	/** The extension's JSON properties, as written by baker (rays, maxDistance, attenuationDistance, ...). */
	getParams() {
		return { ...this.get('params') };
	}

	setParams(params) {
		return this.set('params', { ...params });
	}

	/** Name of the per-vertex attribute holding thickness in mesh units, or null. */
	getAttribute() {
		return this.get('params').attribute ?? null;
	}
}

export class BakerThickness extends Extension {
	static EXTENSION_NAME = THICKNESS;
	extensionName = THICKNESS;

	createThickness() {
		return new Thickness(this.document.getGraph());
	}

	read(context) {
		const materials = context.jsonDoc.json.materials || [];
		materials.forEach((def, index) => {
			const params = def.extensions && def.extensions[THICKNESS];
			if (!params) return;
			const { extensions, extras, ...rest } = params;
			const thickness = this.createThickness().setParams(rest);
			if (extras) thickness.setExtras(extras);
			context.materials[index].setExtension(THICKNESS, thickness);
		});
		return this;
	}

	write(context) {
		const json = context.jsonDoc.json;
		for (const material of this.document.getRoot().listMaterials()) {
			const thickness = material.getExtension(THICKNESS);
			if (!thickness) continue;
			const index = context.materialIndexMap.get(material);
			const def = json.materials[index];
			def.extensions = def.extensions || {};
			const out = thickness.getParams();
			const extras = thickness.getExtras();
			if (extras && Object.keys(extras).length) out.extras = extras;
			def.extensions[THICKNESS] = out;
		}
		return this;
	}
}

/** Every BAKER_* extension class, for `io.registerExtensions([...KHRONOS_EXTENSIONS, ...BAKER_EXTENSIONS])`. */
export const BAKER_EXTENSIONS = [BakerThickness];
