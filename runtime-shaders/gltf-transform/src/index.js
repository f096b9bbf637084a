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
// Every extension of REFERENCES (references.js, generated from baker's schemas by tools/references.mjs: which
// fields of each extension are references, on which glTF objects) gets a class: a plain one from base.js's
// plainExtension, or a module of its own where it needs more (BAKER_<name> -> <name>.js: derived back references,
// accessors, property names of its own; EXT_mesh_primitive_edge_visibility -> edge_visibility.js). So a new
// extension that needs nothing more is carried by its schema alone, with no file here.
export { BakerProperty, BakerExtension } from './base.js';
export { REFERENCES } from './references.js';
import { REFERENCES } from './references.js';
import { plainExtension } from './base.js';
import { BakerThickness } from './thickness.js';
import { BakerEdges } from './edges.js';
import { EXTMeshPrimitiveEdgeVisibility } from './edge_visibility.js';
import { BakerFur } from './fur.js';
import { BakerHairCards } from './hair_cards.js';
import { BakerHair } from './hair.js';
export { Thickness, BakerThickness } from './thickness.js';
export { Edges, BakerEdges } from './edges.js';
export { EdgeVisibility, EXTMeshPrimitiveEdgeVisibility } from './edge_visibility.js';
export { Fur, FurFins, BakerFur } from './fur.js';
export { HairCardsMaterial, HairCards, BakerHairCards } from './hair_cards.js';

const HAND_WRITTEN = [BakerThickness, BakerEdges, EXTMeshPrimitiveEdgeVisibility, BakerFur, BakerHairCards, BakerHair];

/** Every class, for `io.registerExtensions([...KHRONOS_EXTENSIONS, ...BAKER_EXTENSIONS])`. */
export const BAKER_EXTENSIONS = Object.keys(REFERENCES).map((name) =>
	HAND_WRITTEN.find((E) => E.EXTENSION_NAME === name) ?? plainExtension(name));

// the plain classes and their properties by name, as earlier releases exported them; an extension needs none here
const plain = (name) => BAKER_EXTENSIONS.find((E) => E.EXTENSION_NAME === name);
export const BakerCurvature = plain('BAKER_curvature');
export const BakerSkinLut = plain('BAKER_skin_lut');
export const BakerTonalArtMap = plain('BAKER_tonal_art_map');
export const BakerToonRamp = plain('BAKER_toon_ramp');
export { BakerHair };
export const BakerGlyphAtlas = plain('BAKER_glyph_atlas');
export const BakerText = plain('BAKER_text');
export const BakerCaustics = plain('BAKER_caustics');
export const BakerNormalBlur = plain('BAKER_normal_blur');
export const [Curvature] = BakerCurvature.PROPERTIES;
export const [SkinLut] = BakerSkinLut.PROPERTIES;
export const [TonalArtMap] = BakerTonalArtMap.PROPERTIES;
export const [ToonRamp] = BakerToonRamp.PROPERTIES;
export const [Hair] = BakerHair.PROPERTIES;
export const [GlyphAtlas] = BakerGlyphAtlas.PROPERTIES;
export const [Text] = BakerText.PROPERTIES;
export const [Caustics] = BakerCaustics.PROPERTIES;
export const [NormalBlur] = BakerNormalBlur.PROPERTIES;
