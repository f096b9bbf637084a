// BAKER_text (node): a label; no references to glTF objects.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const TEXT = 'BAKER_text';

/** BAKER_text on a node: string, font (index into BAKER_glyph_atlas.fonts, which no transform reorders), size,
 * alignment, colours. */
export const Text = defineProperty(TEXT, 'BakerText', PropertyType.NODE);

export class BakerText extends BakerExtension {
	static EXTENSION_NAME = TEXT;
	static PROPERTIES = [Text];
	extensionName = TEXT;
}
