// BAKER_tonal_art_map (material): the TAM levels' textures.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';

const TAM = 'BAKER_tonal_art_map';

/** BAKER_tonal_art_map on a material: every level's textures (`packed`) or texture (`volume`); their UV set is
 * the extension's `texCoord`, kept in each TextureInfo so prune's TEXCOORD bookkeeping renumbers it. */
export const TonalArtMap = defineProperty(TAM, 'BakerTonalArtMap', PropertyType.MATERIAL);

export class BakerTonalArtMap extends BakerExtension {
	static EXTENSION_NAME = TAM;
	static PROPERTIES = [TonalArtMap];
	extensionName = TAM;
}
