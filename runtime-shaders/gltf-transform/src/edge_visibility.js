// EXT_mesh_primitive_edge_visibility (Bentley; primitive): written by baker next to BAKER_edges.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';
import { tracksVertexOrder } from './topology.js';

const EDGE_VISIBILITY = 'EXT_mesh_primitive_edge_visibility';

/** EXT_mesh_primitive_edge_visibility (Bentley) on a triangle primitive: `visibility` (2 bits per triangle edge)
 * and `silhouetteMates` accessors, and `lineStrings` (index accessors and materials). */
export const EdgeVisibility = defineProperty(EDGE_VISIBILITY, 'EdgeVisibility', PropertyType.PRIMITIVE);

export class EXTMeshPrimitiveEdgeVisibility extends tracksVertexOrder(BakerExtension) {
	static EXTENSION_NAME = EDGE_VISIBILITY;
	static PROPERTIES = [EdgeVisibility];
	extensionName = EDGE_VISIBILITY;
}
