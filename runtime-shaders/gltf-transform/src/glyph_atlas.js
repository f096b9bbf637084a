// BAKER_glyph_atlas (root): per font the atlas texture and the glyph and kerning accessors.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const ATLAS = 'BAKER_glyph_atlas';

/** BAKER_glyph_atlas on the root: per font the atlas texture (a bare texture index, its sampler kept) and the
 * glyph and kerning accessors. */
export const GlyphAtlas = defineProperty(ATLAS, 'BakerGlyphAtlas', PropertyType.ROOT);

export class BakerGlyphAtlas extends BakerExtension {
	static EXTENSION_NAME = ATLAS;
	static PROPERTIES = [GlyphAtlas];
	extensionName = ATLAS;
}
