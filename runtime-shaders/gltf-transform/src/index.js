// glTF-Transform extensions for baker's BAKER_* glTF extensions (and EXT_mesh_primitive_edge_visibility).
//
// glTF-Transform drops extensions it has no class for when it writes a document, so a pipeline running
// `optimize`, `prune` or `dedup` on a baked asset would lose the baked data. Register these classes (next to
// KHRONOS_EXTENSIONS, which carries KHR_materials_volume on single-sided materials) and the data survives:
//
//   import { NodeIO } from '@gltf-transform/core';
//   import { KHRONOS_EXTENSIONS } from '@gltf-transform/extensions';
//   import { BAKER_EXTENSIONS } from '@baker/gltf-transform';
//   const io = new NodeIO().registerExtensions([...KHRONOS_EXTENSIONS, ...BAKER_EXTENSIONS]);
//
// Every extension keeps its JSON as is (`getParams()`), except the references, which become graph edges:
// - accessors (BAKER_edges' edge list, BAKER_hair's ribbon indices, the glyph tables, ...) -> Accessor properties,
//   so `prune` keeps them and the writer gives them their new index;
// - textures (`{index, texCoord}` texture infos, or a bare texture index such as a font's atlas) -> Texture +
//   TextureInfo (sampler and texCoord), so `prune` keeps the images, `dedup` may merge them and `prune`'s TEXCOORD
//   bookkeeping sees the UV sets the textures read;
// - primitives of the same mesh (`finsOf`, BAKER_hair's `guides.primitive`) -> Primitive properties; the back
//   references (`BAKER_edges.fins`, `BAKER_fur.fins` on the material) are derived from them when writing, so the
//   graph has no cycles.
// Custom vertex attributes (`_THICKNESS`, `_CURVATURE`, `_FIN_V0`, ...) need nothing: glTF-Transform keeps them
// (`prune` removes only unused NORMAL, TANGENT, TEXCOORD_n and COLOR_n).
//
// One module per extension (BAKER_<name> -> <name>.js, EXT_mesh_primitive_edge_visibility -> edge_visibility.js);
// base.js holds the base classes. Which fields of each extension are references is not written in the classes: it
// is REFERENCES (references.js), generated from baker's schemas by tools/references.mjs.
export { BakerProperty, BakerExtension } from './base.js';
export { REFERENCES } from './references.js';
import { BakerThickness } from './thickness.js';
import { BakerCurvature } from './curvature.js';
import { BakerSkinLut } from './skin_lut.js';
import { BakerTonalArtMap } from './tonal_art_map.js';
import { BakerToonRamp } from './toon_ramp.js';
import { BakerEdges } from './edges.js';
import { EXTMeshPrimitiveEdgeVisibility } from './edge_visibility.js';
import { BakerHair } from './hair.js';
import { BakerFur } from './fur.js';
import { BakerGlyphAtlas } from './glyph_atlas.js';
import { BakerText } from './text.js';
import { BakerCaustics } from './caustics.js';
import { BakerHairCards } from './hair_cards.js';
import { BakerNormalBlur } from './normal_blur.js';
export { Thickness, BakerThickness } from './thickness.js';
export { Curvature, BakerCurvature } from './curvature.js';
export { SkinLut, BakerSkinLut } from './skin_lut.js';
export { TonalArtMap, BakerTonalArtMap } from './tonal_art_map.js';
export { ToonRamp, BakerToonRamp } from './toon_ramp.js';
export { Edges, BakerEdges } from './edges.js';
export { EdgeVisibility, EXTMeshPrimitiveEdgeVisibility } from './edge_visibility.js';
export { Hair, BakerHair } from './hair.js';
export { Fur, FurFins, BakerFur } from './fur.js';
export { GlyphAtlas, BakerGlyphAtlas } from './glyph_atlas.js';
export { Text, BakerText } from './text.js';
export { Caustics, BakerCaustics } from './caustics.js';
export { HairCardsMaterial, HairCards, BakerHairCards } from './hair_cards.js';
export { NormalBlur, BakerNormalBlur } from './normal_blur.js';

/** Every class, for `io.registerExtensions([...KHRONOS_EXTENSIONS, ...BAKER_EXTENSIONS])`. */
export const BAKER_EXTENSIONS = [
	BakerThickness,
	BakerCurvature,
	BakerSkinLut,
	BakerTonalArtMap,
	BakerToonRamp,
	BakerEdges,
	EXTMeshPrimitiveEdgeVisibility,
	BakerHair,
	BakerFur,
	BakerGlyphAtlas,
	BakerText,
	BakerCaustics,
	BakerHairCards,
	BakerNormalBlur,
];
