// BAKER_hair_cards: alpha-tested hair cards (RTR4 14.7.1; runtime-shaders/baker_hair_cards.glsl). Babylon's loader
// already draws them as the file says (base colour + alpha test at alphaCutoff, double-sided); this extension shades
// them Kajiya-Kay along the strands' flow texture, with the data texture's root-to-tip and per-strand random values.
import { BAKER_HAIR_CARDS, dataTexture, requireShader } from './common.js';
import { surfaceExtension } from './surface.js';

/** Loader extension for BAKER_hair_cards (switch `cards`). */
export const BakerHairCardsExtension = surfaceExtension('cards', BAKER_HAIR_CARDS, async function (ext) {
	const [data, flow] = await Promise.all([dataTexture(this.loader, ext.dataTexture), dataTexture(this.loader, ext.flowTexture)]);
	if (!data || !flow) return null;
	return {
		glsl: requireShader(this.shaders, 'cards'),
		samplers: { u_bakerCardsData: data, u_bakerCardsFlow: flow },
	};
});
