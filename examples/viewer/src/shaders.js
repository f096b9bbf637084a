// The runtime-shaders/ modules as text (esbuild's text loader at build time): both engines inject these very files.
import translucency from '../../../runtime-shaders/baker_translucency.glsl';
import skin from '../../../runtime-shaders/baker_skin.glsl';
import toon from '../../../runtime-shaders/baker_toon.glsl';
import hatching from '../../../runtime-shaders/baker_hatching.glsl';
import edges from '../../../runtime-shaders/baker_edges.glsl';
import fur from '../../../runtime-shaders/baker_fur.glsl';
import hair from '../../../runtime-shaders/baker_hair.glsl';
import text from '../../../runtime-shaders/baker_text.glsl';
import caustics from '../../../runtime-shaders/baker_caustics.glsl';
import cards from '../../../runtime-shaders/baker_hair_cards.glsl';
import normalBlur from '../../../runtime-shaders/baker_normal_blur.glsl';

export const shaders = { translucency, skin, toon, hatching, edges, fur, hair, text, caustics, cards, normalBlur };
