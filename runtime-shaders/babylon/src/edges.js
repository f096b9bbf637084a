// BAKER_edges: fins (McGuire & Hughes 2004), shell outline (RTR4 15.2.2) and wireframe (Baerentzen et al. 2006);
// EXT_mesh_primitive_edge_visibility: the wireframe's mask when BAKER_edges has none. The stages are
// runtime-shaders/hosts/web/edges_*.glsl and solid.frag.glsl.
import { Constants } from '@babylonjs/core/Engines/constants.js';
import { runtime, wireframeCorners } from '@baker/shared';
import { BAKER_EDGES, EXT_EDGE_VISIBILITY, GLTF_FRONT, controls, loadedPrimitives, readAccessor, engineModule, stageMaterial } from './common.js';
import { bakerMesh, premultiplied, primitiveAttributes, primitiveIndices } from './geometry.js';

/**
 * The triangles as a non-indexed list with per-corner barycentrics and the triangle's wireframe mask (Baerentzen
 * et al. 2006 need one vertex per corner). positions: 3 floats per vertex; mask: one value per triangle (or null: all).
 */
export function wireframeArrays(positions, indices, mask) {
	const count = indices.length;
	const flat = new Float32Array(count * 3);
	for (let v = 0; v < count; v++) flat.set(positions.subarray(indices[v] * 3, indices[v] * 3 + 3), v * 3);
	return { positions: flat, ...wireframeCorners(count, mask) };
}

/** EXT_mesh_primitive_edge_visibility (2 bits per edge v0:v1, v1:v2, v2:v0, LSB first) -> wireframe mask: bit k set when edge k is not hidden. */
export function maskFromVisibility(bytes, triangleCount) {
	const mask = new Uint8Array(triangleCount);
	for (let t = 0; t < triangleCount; t++) {
		for (let k = 0; k < 3; k++) {
			const bit = 2 * (3 * t + k);
			if ((bytes[bit >> 3] >> (bit & 7)) & 3) mask[t] |= 1 << k;
		}
	}
	return mask;
}

/** True when some _OUTLINE_NORMAL (3 floats per vertex) is zero: BAKER_edges pins the shell to zero on boundary and non-manifold edges. */
export function hasOpenRim(normals) {
	for (let i = 0; i + 2 < normals.length; i += 3) {
		if (normals[i] * normals[i] + normals[i + 1] * normals[i + 1] + normals[i + 2] * normals[i + 2] < 0.25) return true;
	}
	return false;
}

/** Loader extension for BAKER_edges. options.edges overrides the line style ({ color, finWidth, outlineWidth, wireframeWidth, wireframeColor, classes }). */
export class BakerEdgesExtension {
	constructor(loader, options = {}) {
		this.name = BAKER_EDGES;
		this.enabled = true;
		this.order = 210;
		this.loader = loader;
		this.shaders = options.shaders || {};
		this.options = options;
		this.style = { ...runtime('edges').options, ...(options.edges || {}) };
	}
	dispose() { this.loader = null; }

	async onReady() {
		const loader = this.loader;
		const scene = loader.babylonScene;
		const c = controls(loader);
		const glsl = engineModule(this, 'edges', scene); // WGSL on WebGPUEngine
		for (const { primitive, mesh, meshIndex } of loadedPrimitives(loader)) {
			const ext = primitive.extensions?.[BAKER_EDGES];
			if (!ext || !mesh) continue;
			if (ext.finsOf !== undefined) {
				const source = loader.gltf.meshes[meshIndex].primitives[ext.finsOf];
				const crease = source?.extensions?.[BAKER_EDGES]?.creaseAngle ?? Math.PI / 3;
				const attributes = await primitiveAttributes(loader, primitive,
					['_FIN_V0', '_FIN_V1', '_FIN_V2', '_FIN_V3', '_FIN_CORNER', '_FIN_FLAGS']);
				for (const [kind, { data, size }] of Object.entries(attributes)) mesh.setVerticesData(kind, data, false, size);
				const material = stageMaterial('baker fins', scene, {
					glsl, vertex: 'edges_fin.vert', fragment: 'solid.frag',
					attributes: ['position', ...Object.keys(attributes)], uniforms: ['u_width', 'u_creaseCos', 'u_classes', 'u_color'],
				});
				material.backFaceCulling = false;
				material.setFloat('u_width', this.style.finWidth);
				material.setFloat('u_creaseCos', Math.cos(crease));
				material.setInt('u_classes', this.style.classes);
				material.setVector3('u_color', { x: this.style.color[0], y: this.style.color[1], z: this.style.color[2] });
				mesh.material = material;
				mesh.alwaysSelectAsActiveMesh = true;
				c.add('fins', (on) => mesh.setEnabled(on));
				continue;
			}
			const positions = (await readAccessor(loader, primitive.attributes.POSITION)).data;
			const indices = await primitiveIndices(loader, primitive, positions.length / 3);
			const outline = ext.outlineNormal ?? '_OUTLINE_NORMAL';
			if (primitive.attributes[outline] !== undefined) {
				// under the stage's name whatever the extension calls it
				const { [outline.toLowerCase()]: normals } = await primitiveAttributes(loader, primitive, [outline]);
				const parts = [];
				if (hasOpenRim(normals.data) && mesh.material?.backFaceCulling !== false) {
					// an open single-sided primitive (the bake zeroes _OUTLINE_NORMAL on its rims): through an opening
					// the inflated back faces would show (RTR4 15.2.2: the shell needs a closed mesh). Its back faces go
					// into depth first: the shell stage at width 0 with colour writes off, its material made before
					// the shell's (Babylon draws opaque meshes in material creation order)
					const inside = bakerMesh('baker outline occluder', scene, mesh, positions, indices, { _outline_normal: normals });
					const depthOnly = stageMaterial('baker outline occluder', scene, {
						glsl, vertex: 'edges_outline.vert', fragment: 'solid.frag',
						attributes: ['position', '_outline_normal'], uniforms: ['u_width', 'u_color'],
					});
					depthOnly.setFloat('u_width', 0);
					depthOnly.setVector3('u_color', { x: 0, y: 0, z: 0 });
					depthOnly.disableColorWrite = true;
					depthOnly.backFaceCulling = true;
					depthOnly.cullBackFaces = false;
					depthOnly.sideOrientation = GLTF_FRONT;
					inside.material = depthOnly;
					parts.push(inside);
				}
				const shell = bakerMesh('baker outline', scene, mesh, positions, indices, { _outline_normal: normals });
				const material = stageMaterial('baker shell outline', scene, {
					glsl, vertex: 'edges_outline.vert', fragment: 'solid.frag',
					attributes: ['position', '_outline_normal'], uniforms: ['u_width', 'u_color'],
				});
				// the width is in pixels at the shell's depth, so in world units: under a node that scales
				// (KHR_mesh_quantization's dequantization, after gltf-transform quantize) the stage's object-space
				// offset is divided by the world matrix's length scale (cube root of |det|)
				const outlineWidth = this.style.outlineWidth;
				material.setFloat('u_width', outlineWidth);
				shell.onBeforeRenderObservable.add(() => {
					const scale = Math.cbrt(Math.abs(shell.getWorldMatrix().determinant())) || 1;
					material.setFloat('u_width', outlineWidth / scale);
				});
				material.setVector3('u_color', { x: this.style.color[0], y: this.style.color[1], z: this.style.color[2] });
				// the shell shows its back faces only (RTR4 15.2.2): cull the faces that look at the eye
				material.backFaceCulling = true;
				material.cullBackFaces = false;
				material.sideOrientation = GLTF_FRONT;
				shell.material = material;
				parts.push(shell);
				c.add('outline', (on) => { for (const part of parts) part.setEnabled(on); });
			}
			let mask = null;
			if (ext.wireframeMask !== undefined) mask = (await readAccessor(loader, ext.wireframeMask)).data;
			else if (primitive.extensions?.[EXT_EDGE_VISIBILITY]?.visibility !== undefined) {
				mask = maskFromVisibility((await readAccessor(loader, primitive.extensions[EXT_EDGE_VISIBILITY].visibility)).data, indices.length / 3);
			}
			if (mask || ext.wireframeHides) {
				const w = wireframeArrays(positions, indices, mask);
				const wire = bakerMesh('baker wireframe', scene, mesh, w.positions, Uint32Array.from({ length: w.masks.length }, (_, i) => i),
					{ baker_bary: { data: w.bary, size: 3 }, baker_mask: { data: w.masks, size: 1 } });
				const material = premultiplied(stageMaterial('baker wireframe', scene, {
					glsl, vertex: 'edges_wireframe.vert', fragment: 'edges_wireframe.frag',
					attributes: ['position', 'baker_bary', 'baker_mask'], uniforms: ['u_width', 'u_color'], alpha: true,
				}));
				material.setFloat('u_width', this.style.wireframeWidth);
				material.setVector3('u_color', { x: this.style.wireframeColor[0], y: this.style.wireframeColor[1], z: this.style.wireframeColor[2] });
				material.zOffset = -1;
				material.zOffsetUnits = -4;
				material.sideOrientation = GLTF_FRONT;
				wire.material = material;
				wire.alphaIndex = 1;
				c.add('wireframe', (on) => wire.setEnabled(on));
			}
		}
	}
}

/**
 * Loader extension for EXT_mesh_primitive_edge_visibility on its own (no BAKER_edges): its visible edges as the
 * wireframe switch. With BAKER_edges present, BakerEdgesExtension draws the wireframe (from wireframeMask, or from
 * these codes when it has none) and this extension adds nothing.
 */
export class EdgeVisibilityExtension {
	constructor(loader, options = {}) {
		this.name = EXT_EDGE_VISIBILITY;
		this.enabled = true;
		this.order = 211;
		this.loader = loader;
		this.edges = new BakerEdgesExtension(loader, options);
	}
	dispose() { this.loader = null; this.edges = null; }
	async onReady() {
		if ((this.loader.gltf.extensionsUsed || []).includes(BAKER_EDGES)) return;
		const primitives = loadedPrimitives(this.loader).filter(({ primitive }) => primitive.extensions?.[EXT_EDGE_VISIBILITY]);
		for (const { primitive } of primitives) primitive.extensions[BAKER_EDGES] = { wireframeHides: 'none' };
		await this.edges.onReady();
	}
}

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_EDGES]: BakerEdgesExtension, [EXT_EDGE_VISIBILITY]: EdgeVisibilityExtension };
