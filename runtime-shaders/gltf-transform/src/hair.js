// BAKER_hair (primitive): the plain class (its JSON and references), plus the vertex-order guard of topology.js:
// its strands are runs of `verticesPerStrand` vertices, so a step that reorders them drops it with a warning.
import { PropertyType } from '@gltf-transform/core';
import { plainExtension } from './base.js';
import { markVertices, prewriteTopology } from './topology.js';

const HAIR = 'BAKER_hair';

export class BakerHair extends plainExtension(HAIR) {
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
