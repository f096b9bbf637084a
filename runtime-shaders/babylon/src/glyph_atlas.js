// BAKER_glyph_atlas: the fonts' distance-field atlases, loaded for BAKER_text.
import { BAKER_GLYPH_ATLAS, dataTexture } from './common.js';

/** The atlas texture (linear data, no mipmaps) and the font entry of BAKER_glyph_atlas.fonts[index], or null. */
export async function glyphAtlasFont(loader, index) {
	const font = loader.gltf.extensions?.[BAKER_GLYPH_ATLAS]?.fonts?.[index];
	if (!font) return null;
	const texture = await dataTexture(loader, font.texture);
	return texture && { font, texture };
}

/** Loader extension for BAKER_glyph_atlas: nothing to draw by itself (BAKER_text draws with its atlases). */
export class BakerGlyphAtlasExtension {
	constructor(loader) {
		this.name = BAKER_GLYPH_ATLAS;
		this.enabled = true;
		this.loader = loader;
	}
	dispose() { this.loader = null; }
}
