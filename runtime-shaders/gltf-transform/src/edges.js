// BAKER_edges (primitive): the per-edge accessors of a triangle primitive, and its fin primitive.
import { PropertyType } from '@gltf-transform/core';
import { BakerExtension, defineProperty, finsOfPrimitive } from './base.js';
import { markVertices, prewriteTopology } from './topology.js';
import { rememberUnits } from './units.js';

const EDGES = 'BAKER_edges';

/** BAKER_edges on a triangle primitive (the per-edge accessors) or on its fin primitive (`finsOf`, a Primitive
 * of the same mesh). The source's `fins` is derived from the fin primitive's `finsOf` when writing. */
export const Edges = defineProperty(EDGES, 'BakerEdges', PropertyType.PRIMITIVE, { derived: ['fins'] });

export class BakerEdges extends BakerExtension {
	static EXTENSION_NAME = EDGES;
	static PROPERTIES = [Edges];
	extensionName = EDGES;
	prewriteTypes = [PropertyType.ACCESSOR, PropertyType.BUFFER];

	read(context) {
		super.read(context);
		rememberUnits(this.document);
		// `fins` is a back reference: drop it, finish() derives it from the fin primitive's `finsOf`
		for (const mesh of this.document.getRoot().listMeshes()) {
			for (const prim of mesh.listPrimitives()) {
				const ext = prim.getExtension(EDGES);
				if (ext && 'fins' in ext.get('params')) {
					const { fins, ...rest } = ext.get('params');
					ext.set('params', { ...rest, fins: null });
				}
				markVertices(this.document, prim);
			}
		}
		return this;
	}

	/** Before any compression step claims the accessors: remap the edge data to the vertex and triangle order the
	 * pipeline left (topology.js). */
	prewrite(context, propertyType) {
		prewriteTopology(this, context, propertyType);
		return this;
	}

	finish(out, owner, _context, mesh) {
		if (!('fins' in out)) return;
		const fins = mesh ? finsOfPrimitive(mesh, owner, EDGES) : [];
		if (fins.length) out.fins = mesh.listPrimitives().indexOf(fins[0]);
		else delete out.fins;
	}
}
