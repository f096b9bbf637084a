// BAKER_hair_cards: alpha-tested hair cards (RTR4 14.7.1; runtime-shaders/baker_hair_cards.glsl). GLTFLoader already
// draws them as the file says (base colour + alpha test at alphaCutoff, double-sided); this plugin swaps the base
// colour for its coverage-preserving mip chain when the file has one (coverageMips, Castaño 2010: the loader's own
// alpha test then keeps the cards' coverage with distance) and shades them Kajiya-Kay along the strands' flow
// texture, with the data texture's root-to-tip and per-strand random values.
import * as THREE from 'three';
import { coverageMipsOf } from '@baker/shared';
import { coverageMipsTexture, dataTexture, requireShader, textureOf } from './common.js';
import { surfacePlugin } from './surface.js';

/**
 * Replace `material.map` (the atlas PNG, mipmapped by WebGL's box filter) with the chain of the glTF material's
 * baseColorTexture: its levels as the mips, decoded as sRGB like the PNG. Keeps the PNG when there is no readable chain.
 */
async function useCoverageMips(parser, ext, material) {
	const json = parser.json.materials?.[parser.associations.get(material)?.materials];
	const chain = material.map && coverageMipsOf(ext, json?.pbrMetallicRoughness?.baseColorTexture);
	const texture = chain && await coverageMipsTexture(parser, chain);
	if (!texture) return;
	texture.colorSpace = THREE.SRGBColorSpace; // base colour (the chain's alpha stays linear: SRGB8_ALPHA8)
	texture.channel = material.map.channel;
	material.map = texture;
	material.needsUpdate = true;
}

/** GLTFLoader plugin for BAKER_hair_cards (switch `cards`). */
export const BakerHairCardsPlugin = surfacePlugin('cards', async function (ext, object, material) {
	const [data, flow] = await Promise.all([textureOf(this.parser, ext.dataTexture), textureOf(this.parser, ext.flowTexture)]);
	if (!data || !flow) return null;
	await useCoverageMips(this.parser, ext, material);
	return {
		glsl: requireShader(this.shaders, 'cards'),
		uniforms: { u_bakerCardsData: { value: dataTexture(data) }, u_bakerCardsFlow: { value: dataTexture(flow) } },
		types: { u_bakerCardsData: 'sampler2D', u_bakerCardsFlow: 'sampler2D' },
	};
});

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerHairCardsPlugin];
