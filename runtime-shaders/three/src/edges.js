// BAKER_edges: fins (McGuire & Hughes 2004), shell outline (RTR4 15.2.2) and wireframe (Baerentzen et al. 2006); the
// stages are runtime-shaders/hosts/web/edges_*.glsl and solid.frag.glsl.
import * as THREE from 'three';
import { runtime, wireframeCorners } from '@baker/shared';
import { BAKER_EDGES, controls, geometryHas, primitiveOf, requireShader, stageMaterial, trackViewport, trackWorldScale } from './common.js';

/**
 * Triangles of an indexed geometry as a non-indexed one with per-corner barycentrics and the triangle's wireframe
 * mask (Baerentzen et al. 2006 need one vertex per corner).
 */
export function wireframeGeometry(geometry, mask) {
	const flat = geometry.index ? geometry.toNonIndexed() : geometry.clone();
	const { bary, masks } = wireframeCorners(flat.attributes.position.count, mask);
	const out = new THREE.BufferGeometry();
	out.setAttribute('position', flat.attributes.position);
	out.setAttribute('baker_bary', new THREE.BufferAttribute(bary, 3));
	out.setAttribute('baker_mask', new THREE.BufferAttribute(masks, 1));
	return out;
}

/** True when some _OUTLINE_NORMAL is zero: BAKER_edges pins the shell to zero on boundary and non-manifold edges. */
export function hasOpenRim(normals) {
	for (let i = 0; i < normals.count; i++) {
		const x = normals.getX(i), y = normals.getY(i), z = normals.getZ(i);
		if (x * x + y * y + z * z < 0.25) return true;
	}
	return false;
}

/** GLTFLoader plugin for BAKER_edges: fins (McGuire & Hughes 2004), shell outline (RTR4 15.2.2), wireframe (Baerentzen 2006). */
export class BakerEdgesPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_EDGES;
		this.shaders = options.shaders || {};
		this.style = { ...runtime('edges').options, ...(options.edges || {}) };
	}

	async afterRoot(result) {
		const glsl = () => requireShader(this.shaders, 'edges');
		const c = controls(this.parser);
		const meshes = [];
		result.scene.traverse((o) => o.isMesh && meshes.push(o));
		for (const object of meshes) {
			const ext = primitiveOf(this.parser, object)?.extensions?.[BAKER_EDGES];
			if (!ext) continue;
			if (ext.finsOf !== undefined) {
				// the fin primitive: degenerate quads the vertex shader opens where the edge is wanted
				const source = this.parser.json.meshes[this.parser.associations.get(object).meshes].primitives[ext.finsOf];
				const crease = source?.extensions?.[BAKER_EDGES]?.creaseAngle ?? Math.PI / 3;
				const uniforms = {
					u_viewport: { value: new THREE.Vector2(1, 1) }, u_width: { value: this.style.finWidth },
					u_creaseCos: { value: Math.cos(crease) }, u_classes: { value: this.style.classes },
					u_color: { value: new THREE.Color(...this.style.color) },
				};
				object.material = stageMaterial({
					name: 'baker fins', uniforms, glsl: glsl(), vertex: 'edges_fin.vert', fragment: 'solid.frag',
					side: THREE.DoubleSide,
				});
				object.frustumCulled = false;
				object.renderOrder = 2;
				trackViewport(object, uniforms);
				c.add('fins', (on) => { object.visible = on; });
				continue;
			}
			const outline = ext.outlineNormal ?? '_OUTLINE_NORMAL';
			if (geometryHas(object, outline)) {
				const uniforms = {
					u_viewport: { value: new THREE.Vector2(1, 1) }, u_width: { value: this.style.outlineWidth },
					u_color: { value: new THREE.Color(...this.style.color) },
				};
				const geometry = new THREE.BufferGeometry();
				geometry.setIndex(object.geometry.index);
				geometry.setAttribute('position', object.geometry.attributes.position);
				geometry.setAttribute('_outline_normal', object.geometry.getAttribute(outline.toLowerCase()));
				const shell = new THREE.Mesh(geometry, stageMaterial({
					name: 'baker shell outline', uniforms, glsl: glsl(), vertex: 'edges_outline.vert', fragment: 'solid.frag',
					side: THREE.BackSide,
				}));
				shell.name = 'baker outline';
				shell.frustumCulled = false;
				trackViewport(shell, uniforms);
				trackWorldScale(shell, uniforms.u_width, this.style.outlineWidth); // pixels -> world units, not node units
				object.add(shell);
				const parts = [shell];
				if (hasOpenRim(geometry.attributes._outline_normal) && object.material.side !== THREE.DoubleSide) {
					// an open single-sided primitive (the bake zeroes _OUTLINE_NORMAL on its rims): through an opening
					// the inflated back faces would show (RTR4 15.2.2: the shell needs a closed mesh). Its back faces
					// go into depth first, colour untouched, after the scene's opaque objects and before the shell.
					const inside = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({ side: THREE.BackSide, colorWrite: false }));
					inside.name = 'baker outline occluder';
					inside.frustumCulled = false;
					inside.renderOrder = 0.5;
					shell.renderOrder = 0.75;
					object.add(inside);
					parts.push(inside);
				}
				c.add('outline', (on) => { for (const part of parts) part.visible = on; });
			}
			if (ext.wireframeMask !== undefined || ext.wireframeHides) {
				const mask = ext.wireframeMask !== undefined ? (await this.parser.getDependency('accessor', ext.wireframeMask)).array : null;
				const uniforms = { u_width: { value: this.style.wireframeWidth }, u_color: { value: new THREE.Color(...this.style.wireframeColor) } };
				const wire = new THREE.Mesh(wireframeGeometry(object.geometry, mask), stageMaterial({
					name: 'baker wireframe', uniforms, glsl: glsl(), vertex: 'edges_wireframe.vert', fragment: 'edges_wireframe.frag',
					transparent: true, depthWrite: false, side: THREE.FrontSide,
					blending: THREE.CustomBlending, blendSrc: THREE.OneFactor, blendDst: THREE.OneMinusSrcAlphaFactor,
					polygonOffset: true, polygonOffsetFactor: -1, polygonOffsetUnits: -4,
				}));
				wire.name = 'baker wireframe';
				wire.renderOrder = 1;
				object.add(wire);
				c.add('wireframe', (on) => { wire.visible = on; });
			}
		}
		return null;
	}
}

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerEdgesPlugin];
