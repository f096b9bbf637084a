// BAKER_edges: fins (McGuire & Hughes 2004), shell outline (RTR4 15.2.2) and wireframe (Baerentzen et al. 2006);
// EXT_mesh_primitive_edge_visibility: the wireframe's mask when BAKER_edges has none.
import { Constants } from '@babylonjs/core/Engines/constants.js';
import { wireframeCorners } from '@baker/shared';
import { BAKER_EDGES, EXT_EDGE_VISIBILITY, GLTF_FRONT, bakerShaderMaterial, controls, loadedPrimitives, readAccessor, requireShader } from './common.js';
import { asComponents, bakerMesh, premultiplied, primitiveAttributes, primitiveIndices } from './geometry.js';

const FIN_VERTEX = (decl, a) => `
${decl}
uniform mat4 world;
uniform mat4 viewProjection;
uniform vec3 u_eye;
uniform vec2 u_viewport;
uniform float u_width;
uniform float u_creaseCos;
uniform int u_classes;
void main() {
	vec3 v0 = ${a('bakerFinV0', 3)}, v1 = ${a('bakerFinV1', 3)}, v2 = ${a('bakerFinV2', 3)}, v3 = ${a('bakerFinV3', 3)};
	vec3 eye = (inverse(world) * vec4(u_eye, 1.0)).xyz;  // object space
	int c = baker_fin_classify(v0, v1, v2, v3, ${a('bakerFinFlags', 1)}, eye, u_creaseCos);
	vec4 clip0 = viewProjection * world * vec4(v0, 1.0);
	vec4 clip1 = viewProjection * world * vec4(v1, 1.0);
	if ((c & u_classes) == 0 || clip0.w <= 0.0 || clip1.w <= 0.0) {
		gl_Position = baker_fin_culled();
		return;
	}
	gl_Position = baker_fin_position(clip0, clip1, ${a('bakerFinCorner', 1)}, u_width, u_viewport);
	gl_Position.z -= 1e-4 * gl_Position.w;  // over the surface it outlines
}`;

const SOLID_FRAGMENT = `
uniform vec3 u_color;
void main() { gl_FragColor = vec4(u_color, 1.0); }`;

const OUTLINE_VERTEX = (decl, a) => `
attribute vec3 position;
${decl}
uniform mat4 world;
uniform mat4 viewProjection;
uniform mat4 projection;
uniform vec2 u_viewport;
uniform float u_width;
void main() {
	vec4 clip = viewProjection * world * vec4(position, 1.0);
	vec3 p = baker_shell_position(position, ${a('bakerOutlineNormal', 3)}, clip.w, u_width, u_viewport.y, projection[1][1]);
	gl_Position = viewProjection * world * vec4(p, 1.0);
}`;

const WIREFRAME_VERTEX = `
attribute vec3 position;
attribute vec3 bakerBary;
attribute float bakerMask;
uniform mat4 worldViewProjection;
varying vec3 vBary;
flat varying int vMask;
void main() {
	vBary = bakerBary;
	vMask = int(bakerMask + 0.5);
	gl_Position = worldViewProjection * vec4(position, 1.0);
}`;

const WIREFRAME_FRAGMENT = `
uniform vec3 u_color;
uniform float u_width;
varying vec3 vBary;
flat varying int vMask;
void main() {
	vec2 cov = baker_wireframe(vBary, fwidth(vBary), vMask, u_width, 0.0);
	if (cov.x <= 0.0) discard;
	gl_FragColor = vec4(u_color * cov.x, cov.x);  // premultiplied
}`;

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

/** Loader extension for BAKER_edges. options.edges overrides the line style ({ color, finWidth, outlineWidth, wireframeWidth, wireframeColor, classes }). */
export class BakerEdgesExtension {
	constructor(loader, options = {}) {
		this.name = BAKER_EDGES;
		this.enabled = true;
		this.order = 210;
		this.loader = loader;
		this.shaders = options.shaders || {};
		this.style = { color: [0.02, 0.02, 0.03], finWidth: 2.5, outlineWidth: 3, wireframeWidth: 1.25,
			wireframeColor: [0.95, 0.75, 0.2], classes: 1 | 2 | 4 | 8, ...(options.edges || {}) };
	}
	dispose() { this.loader = null; }

	async onReady() {
		const loader = this.loader;
		const scene = loader.babylonScene;
		const c = controls(loader);
		const glsl = requireShader(this.shaders, 'edges');
		for (const { primitive, mesh, meshIndex } of loadedPrimitives(loader)) {
			const ext = primitive.extensions?.[BAKER_EDGES];
			if (!ext || !mesh) continue;
			if (ext.finsOf !== undefined) {
				const source = loader.gltf.meshes[meshIndex].primitives[ext.finsOf];
				const crease = source?.extensions?.[BAKER_EDGES]?.creaseAngle ?? Math.PI / 3;
				const { attributes, declarations } = await primitiveAttributes(loader, primitive, {
					_FIN_V0: 'bakerFinV0', _FIN_V1: 'bakerFinV1', _FIN_V2: 'bakerFinV2', _FIN_V3: 'bakerFinV3',
					_FIN_CORNER: 'bakerFinCorner', _FIN_FLAGS: 'bakerFinFlags' });
				const a = (kind, want) => asComponents(kind, attributes[kind].size, want);
				for (const [kind, { data, size }] of Object.entries(attributes)) mesh.setVerticesData(kind, data, false, size);
				const material = bakerShaderMaterial('baker fins', scene, {
					vertex: glsl + FIN_VERTEX(declarations, a), fragment: SOLID_FRAGMENT,
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
				const { attributes, declarations } = await primitiveAttributes(loader, primitive, { [outline]: 'bakerOutlineNormal' });
				const a = (kind, want) => asComponents(kind, attributes[kind].size, want);
				const shell = bakerMesh('baker outline', scene, mesh, positions, indices, attributes);
				const material = bakerShaderMaterial('baker shell outline', scene, {
					vertex: glsl + OUTLINE_VERTEX(declarations, a), fragment: SOLID_FRAGMENT,
					attributes: ['position', 'bakerOutlineNormal'], uniforms: ['u_width', 'u_color'],
				});
				material.setFloat('u_width', this.style.outlineWidth);
				material.setVector3('u_color', { x: this.style.color[0], y: this.style.color[1], z: this.style.color[2] });
				// the shell shows its back faces only (RTR4 15.2.2): cull the faces that look at the eye
				material.backFaceCulling = true;
				material.cullBackFaces = false;
				material.sideOrientation = GLTF_FRONT;
				shell.material = material;
				c.add('outline', (on) => shell.setEnabled(on));
			}
			let mask = null;
			if (ext.wireframeMask !== undefined) mask = (await readAccessor(loader, ext.wireframeMask)).data;
			else if (primitive.extensions?.[EXT_EDGE_VISIBILITY]?.visibility !== undefined) {
				mask = maskFromVisibility((await readAccessor(loader, primitive.extensions[EXT_EDGE_VISIBILITY].visibility)).data, indices.length / 3);
			}
			if (mask || ext.wireframeHides) {
				const w = wireframeArrays(positions, indices, mask);
				const wire = bakerMesh('baker wireframe', scene, mesh, w.positions, Uint32Array.from({ length: w.masks.length }, (_, i) => i),
					{ bakerBary: { data: w.bary, size: 3 }, bakerMask: { data: w.masks, size: 1 } });
				const material = premultiplied(bakerShaderMaterial('baker wireframe', scene, {
					vertex: WIREFRAME_VERTEX, fragment: glsl + WIREFRAME_FRAGMENT,
					attributes: ['position', 'bakerBary', 'bakerMask'], uniforms: ['u_width', 'u_color'], alpha: true,
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
