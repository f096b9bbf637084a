// EXT_mesh_primitive_edge_visibility (Bentley; primitive): written by baker next to BAKER_edges.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty } from './base.js';
import { markVertices, prewriteTopology } from './topology.js';

const EDGE_VISIBILITY = 'EXT_mesh_primitive_edge_visibility';

/** EXT_mesh_primitive_edge_visibility (Bentley) on a triangle primitive: `visibility` (2 bits per triangle edge)
 * and `silhouetteMates` accessors, and `lineStrings` (index accessors and materials). */
export const EdgeVisibility = defineProperty(EDGE_VISIBILITY, 'EdgeVisibility', PropertyType.PRIMITIVE);

export class EXTMeshPrimitiveEdgeVisibility extends BakerExtension {
	static EXTENSION_NAME = EDGE_VISIBILITY;
	static PROPERTIES = [EdgeVisibility];
	extensionName = EDGE_VISIBILITY;
	prewriteTypes = [PropertyType.ACCESSOR];

	read(context) {
		super.read(context);
		for (const mesh of this.document.getRoot().listMeshes()) {
			for (const prim of mesh.listPrimitives()) markVertices(this.document, prim);
		}
		return this;
	}

	prewrite(_context, _propertyType) {
		prewriteTopology(this);
		return this;
	}
}
