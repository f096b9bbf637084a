// BAKER_hair (primitive): the plain class (its JSON and references), plus the vertex-order guard of topology.js:
// its strands are runs of `verticesPerStrand` vertices, so a step that reorders them drops it with a warning.
import { plainExtension } from './base.js';
import { tracksVertexOrder } from './topology.js';

const HAIR = 'BAKER_hair';

export class BakerHair extends tracksVertexOrder(plainExtension(HAIR)) {}
