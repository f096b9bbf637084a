// BAKER_hair (LINES primitive): per-strand widths, ribbon indices, and for children the guide interpolation.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const HAIR = 'BAKER_hair';

/** BAKER_hair on a LINES primitive: `widthScale`, `ribbonIndices`, and for children `guides` (`primitive`: the
 * guide Primitive of the same mesh; `ids`, `weights`: accessors; `interpolation`), `lods` (plain JSON) and, from
 * `baker guides --scalp`, `rootBinding` (`primitives`, `triangles`, `barycentrics`: accessors; `mesh`: an index
 * kept as written). */
export const Hair = defineProperty(HAIR, 'BakerHair', PropertyType.PRIMITIVE);

export class BakerHair extends BakerExtension {
	static EXTENSION_NAME = HAIR;
	static PROPERTIES = [Hair];
	extensionName = HAIR;
}
