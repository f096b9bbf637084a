// BAKER_edges: fins (McGuire & Hughes 2004), shell outline (RTR4 15.2.2) and wireframe (Baerentzen et al. 2006).
import * as THREE from 'three';
import { wireframeCorners } from '@baker/shared';
import { BAKER_EDGES, controls, geometryHas, primitiveOf, requireShader, trackViewport } from './common.js';

const FIN_VERTEX = `
attribute vec3 _fin_v0;
attribute vec3 _fin_v1;
attribute vec3 _fin_v2;
attribute vec3 _fin_v3;
attribute float _fin_corner;
attribute float _fin_flags;
uniform vec2 u_viewport;
uniform float u_width;
uniform float u_creaseCos;
uniform int u_classes;
void main() {
	vec3 eye = (inverse(modelMatrix) * vec4(cameraPosition, 1.0)).xyz;  // object space
	int c = baker_fin_classify(_fin_v0, _fin_v1, _fin_v2, _fin_v3, _fin_flags, eye, u_creaseCos);
	vec4 clip0 = projectionMatrix * modelViewMatrix * vec4(_fin_v0, 1.0);
	vec4 clip1 = projectionMatrix * modelViewMatrix * vec4(_fin_v1, 1.0);
	if ((c & u_classes) == 0 || clip0.w <= 0.0 || clip1.w <= 0.0) {
		gl_Position = baker_fin_culled();
		return;
	}
	gl_Position = baker_fin_position(clip0, clip1, _fin_corner, u_width, u_viewport);
	gl_Position.z -= 1e-4 * gl_Position.w;  // over the surface it outlines
}`;

const SOLID_FRAGMENT = `
uniform vec3 u_color;
void main() { gl_FragColor = vec4(u_color, 1.0); }`;

const OUTLINE_VERTEX = `
attribute vec3 _outline_normal;
uniform vec2 u_viewport;
uniform float u_width;
void main() {
	vec4 clip = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
	vec3 p = baker_shell_position(position, _outline_normal, clip.w, u_width, u_viewport.y, projectionMatrix[1][1]);
	gl_Position = projectionMatrix * modelViewMatrix * vec4(p, 1.0);
}`;

const WIREFRAME_VERTEX = `
attribute vec3 baker_bary;
attribute float baker_mask;
varying vec3 vBary;
flat varying int vMask;
void main() {
	vBary = baker_bary;
	vMask = int(baker_mask + 0.5);
	gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
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

/** GLTFLoader plugin for BAKER_edges: fins (McGuire & Hughes 2004), shell outline (RTR4 15.2.2), wireframe (Baerentzen 2006). */
export class BakerEdgesPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_EDGES;
		this.shaders = options.shaders || {};
		this.style = { color: [0.02, 0.02, 0.03], finWidth: 2.5, outlineWidth: 3, wireframeWidth: 1.25,
			wireframeColor: [0.95, 0.75, 0.2], classes: 1 | 2 | 4 | 8, ...(options.edges || {}) };
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
				object.material = new THREE.ShaderMaterial({
					name: 'baker fins', uniforms, vertexShader: glsl() + FIN_VERTEX, fragmentShader: SOLID_FRAGMENT,
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
				const shell = new THREE.Mesh(geometry, new THREE.ShaderMaterial({
					name: 'baker shell outline', uniforms, vertexShader: glsl() + OUTLINE_VERTEX, fragmentShader: SOLID_FRAGMENT,
					side: THREE.BackSide,
				}));
				shell.name = 'baker outline';
				shell.frustumCulled = false;
				trackViewport(shell, uniforms);
				object.add(shell);
				c.add('outline', (on) => { shell.visible = on; });
			}
			if (ext.wireframeMask !== undefined || ext.wireframeHides) {
				const mask = ext.wireframeMask !== undefined ? (await this.parser.getDependency('accessor', ext.wireframeMask)).array : null;
				const uniforms = { u_width: { value: this.style.wireframeWidth }, u_color: { value: new THREE.Color(...this.style.wireframeColor) } };
				const wire = new THREE.Mesh(wireframeGeometry(object.geometry, mask), new THREE.ShaderMaterial({
					name: 'baker wireframe', uniforms, vertexShader: WIREFRAME_VERTEX, fragmentShader: glsl() + WIREFRAME_FRAGMENT,
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
