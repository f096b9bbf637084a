// BAKER_hair_cards: alpha-tested hair cards (RTR4 14.7.1; runtime-shaders/baker_hair_cards.glsl). Babylon's loader
// already draws them as the file says (base colour + alpha test at alphaCutoff, double-sided); this extension swaps
// the base colour for its coverage-preserving mip chain when the file has one (coverageMips, Castaño 2010: the
// loader's own alpha test then keeps the cards' coverage with distance) and shades them Kajiya-Kay along the strands'
// flow texture, with the data texture's root-to-tip and per-strand random values.
import { coverageMipsOf } from '@baker/shared';
import { BAKER_HAIR_CARDS, coverageMipsTexture, dataTexture, partModule } from './common.js';
import { surfaceExtension } from './surface.js';

/**
 * Replace the material's albedoTexture (the atlas PNG, mipmapped by a box filter) with the chain of the glTF
 * material's baseColorTexture: its levels as the mips, decoded from sRGB in the shader (gammaSpace) like the PNG, its
 * alpha the one the alpha test reads. Keeps the PNG when there is no readable chain.
 */
async function useCoverageMips(loader, ext, primitive, material) {
	const json = loader.gltf.materials?.[primitive.material];
	const chain = material.albedoTexture && coverageMipsOf(ext, json?.pbrMetallicRoughness?.baseColorTexture);
	const texture = chain && await coverageMipsTexture(loader, chain);
	if (!texture) return;
	texture.gammaSpace = true;
	texture.hasAlpha = true;
	texture.coordinatesIndex = material.albedoTexture.coordinatesIndex;
	material.albedoTexture = texture;
}

/** Loader extension for BAKER_hair_cards (switch `cards`). */
export const BakerHairCardsExtension = surfaceExtension('cards', BAKER_HAIR_CARDS, async function (ext, mesh, primitive, material) {
	const [data, flow] = await Promise.all([dataTexture(this.loader, ext.dataTexture), dataTexture(this.loader, ext.flowTexture)]);
	if (!data || !flow) return null;
	await useCoverageMips(this.loader, ext, primitive, material);
	return {
		...partModule(this, 'cards', material),
		samplers: { u_bakerCardsData: data, u_bakerCardsFlow: flow },
	};
});

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_HAIR_CARDS]: BakerHairCardsExtension };
