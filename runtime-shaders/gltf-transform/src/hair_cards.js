// BAKER_hair_cards (material, and the cards primitive): the atlas's data and flow textures; the card regions and
// first indices (accessors).
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const HAIR_CARDS = 'BAKER_hair_cards';

/** BAKER_hair_cards on a material: the data and flow textures of the strand atlas, depth range, layout. */
export const HairCardsMaterial = defineProperty(HAIR_CARDS, 'BakerHairCardsMaterial', PropertyType.MATERIAL);

/** BAKER_hair_cards on the cards primitive: card count, regions and first indices (accessors), groom counts. */
export const HairCards = defineProperty(HAIR_CARDS, 'BakerHairCards', PropertyType.PRIMITIVE);

export class BakerHairCards extends BakerExtension {
	static EXTENSION_NAME = HAIR_CARDS;
	static PROPERTIES = [HairCardsMaterial, HairCards];
	extensionName = HAIR_CARDS;
}
