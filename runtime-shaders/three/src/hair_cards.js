// BAKER_hair_cards: alpha-tested hair cards (RTR4 14.7.1; runtime-shaders/baker_hair_cards.glsl). GLTFLoader already
// draws them as the file says (base colour + alpha test at alphaCutoff, double-sided); this plugin shades them
// Kajiya-Kay along the strands' flow texture, with the data texture's root-to-tip and per-strand random values.
import { dataTexture, requireShader, textureOf } from './common.js';
import { surfacePlugin } from './surface.js';

/** GLTFLoader plugin for BAKER_hair_cards (switch `cards`). */
export const BakerHairCardsPlugin = surfacePlugin('cards', async function (ext) {
	const [data, flow] = await Promise.all([textureOf(this.parser, ext.dataTexture), textureOf(this.parser, ext.flowTexture)]);
	if (!data || !flow) return null;
	return {
		glsl: requireShader(this.shaders, 'cards'),
		uniforms: { u_bakerCardsData: { value: dataTexture(data) }, u_bakerCardsFlow: { value: dataTexture(flow) } },
		types: { u_bakerCardsData: 'sampler2D', u_bakerCardsFlow: 'sampler2D' },
	};
});
