// BAKER_fur (material, and fin primitive): shell and fin textures; the fin primitives' source primitive.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';
import { prewriteTopology } from './topology.js';
import { rememberUnits } from './units.js';

const FUR = 'BAKER_fur';

/** BAKER_fur on a material: shell textures, fin texture, parameters. Its `fins` list is derived when writing from
 * the fin primitives whose source primitive uses this material. */
export const Fur = defineProperty(FUR, 'BakerFur', PropertyType.MATERIAL,
	{ derived: ['fins/*'], accepts: (ext) => !('finsOf' in ext) });

/** BAKER_fur on a fin primitive: `finsOf`, its source Primitive in the same mesh. */
export const FurFins = defineProperty(FUR, 'BakerFurFins', PropertyType.PRIMITIVE);

export class BakerFur extends BakerExtension {
	static EXTENSION_NAME = FUR;
	static PROPERTIES = [Fur, FurFins];
	extensionName = FUR;
	prewriteTypes = [PropertyType.ACCESSOR, PropertyType.BUFFER];

	/** Its lengths and fin positions are in mesh units: units.js follows a step that changes them (quantize). */
	read(context) {
		super.read(context);
		rememberUnits(this.document);
		return this;
	}

	prewrite(context, propertyType) {
		prewriteTopology(this, context, propertyType);
		return this;
	}

	finish(out, owner, context) {
		if (!('shellTextures' in out) && !('fins' in out)) return; // a fin primitive
		const fins = [];
		for (const mesh of this.document.getRoot().listMeshes()) {
			for (const [p, prim] of mesh.listPrimitives().entries()) {
				const ext = prim.getExtension(FUR);
				const source = ext && ext.getPrimitive('finsOf');
				if (source && source.getMaterial() === owner) {
					fins.push({ mesh: context.meshIndexMap.get(mesh), primitive: p });
				}
			}
		}
		if (fins.length) out.fins = fins;
		else delete out.fins;
	}
}
