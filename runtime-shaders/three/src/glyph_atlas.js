// BAKER_glyph_atlas: the fonts' distance-field atlases, loaded for BAKER_text.
import { BAKER_GLYPH_ATLAS, dataTexture, textureOf } from './common.js';

/** GLTFLoader plugin for BAKER_glyph_atlas: loads the fonts' atlases (used by BAKER_text). */
export class BakerGlyphAtlasPlugin {
	constructor(parser) {
		this.parser = parser;
		this.name = BAKER_GLYPH_ATLAS;
	}
	/** The atlas texture and its font entry for BAKER_glyph_atlas.fonts[index]. */
	async font(index) {
		const font = this.parser.json.extensions?.[BAKER_GLYPH_ATLAS]?.fonts?.[index];
		if (!font) return null;
		const texture = await textureOf(this.parser, font.texture);
		return texture && { font, texture: dataTexture(texture.clone()) };
	}
}
