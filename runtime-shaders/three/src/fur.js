// BAKER_fur: Lengyel et al. 2001 shells (one blended pass per shell texture) and fins.
import * as THREE from 'three';
import { coverageMipsOf } from '@baker/shared';
import { BAKER_EDGES, BAKER_FUR, controls, coverageMipsTexture, DIRECTIONAL_DIFFUSE, litShaderMaterial, primitiveOf, requireShader, textureOf } from './common.js';

const FUR_SHELL_VERTEX = `
uniform float u_shell;
uniform float u_shellCount;
uniform float u_shellSpacing;
uniform float u_tiling;
varying vec2 vUvFur;
varying vec3 vNormalView;
void main() {
	vec3 p = baker_fur_shell_position(position, normal, u_shell, u_shellSpacing, u_shellCount, vec3(0.0));
	vUvFur = baker_fur_shell_uv(uv, u_tiling);
	vNormalView = normalize(normalMatrix * normal);
	gl_Position = projectionMatrix * modelViewMatrix * vec4(p, 1.0);
}`;

const FUR_SHELL_FRAGMENT = `
uniform sampler2D u_texture;
uniform float u_shell;
uniform float u_shellCount;
uniform float u_alphaCutoff;
uniform float u_alphaTest;
varying vec2 vUvFur;
varying vec3 vNormalView;
void main() {
	vec4 texel = texture(u_texture, vUvFur);
	if (texel.a < u_alphaCutoff) discard;
	vec4 shaded = baker_fur_shell_shade(texel, baker_fur_shell_height(u_shell, u_shellCount), 0.35);
	vec3 light = ambientLightColor + baker_directional_diffuse(normalize(vNormalView)) * 0.5;
	gl_FragColor = vec4(shaded.rgb * light, mix(shaded.a, 1.0, u_alphaTest));
}`;

const FUR_FIN_VERTEX = `
attribute vec3 _fin_v0;
attribute vec3 _fin_v1;
attribute vec3 _fin_v2;
attribute vec3 _fin_v3;
attribute float _fin_corner;
attribute vec3 _fur_fin_normal;
attribute vec2 _fur_fin_uv;
uniform float u_length;
uniform float u_threshold;
varying vec2 vUvFin;
varying float vWeight;
varying vec3 vNormalView;
void main() {
	vec3 p = baker_fur_fin_position(_fin_v0, _fin_v1, _fur_fin_normal, _fin_corner, u_length);
	vec3 n0;
	vec3 n1;
	baker_fur_fin_face_normals(_fin_v0, _fin_v1, _fin_v2, _fin_v3, n0, n1);
	vec3 eye = (inverse(modelMatrix) * vec4(cameraPosition, 1.0)).xyz;
	vWeight = baker_fur_fin_weight(n0, n1, normalize(eye - p), u_threshold);
	vUvFin = _fur_fin_uv;
	vNormalView = normalize(normalMatrix * _fur_fin_normal);
	gl_Position = projectionMatrix * modelViewMatrix * vec4(p, 1.0);
}`;

const FUR_FIN_FRAGMENT = `
uniform sampler2D u_texture;
uniform float u_alphaCutoff;
uniform float u_alphaTest;
varying vec2 vUvFin;
varying float vWeight;
varying vec3 vNormalView;
void main() {
	vec4 texel = texture(u_texture, vUvFin);
	if (texel.a < u_alphaCutoff) discard;
	float a = mix(texel.a, 1.0, u_alphaTest) * vWeight;
	if (a < 0.01) discard;
	vec3 light = ambientLightColor + baker_directional_diffuse(normalize(vNormalView)) * 0.5;
	gl_FragColor = vec4(texel.rgb * light, a);
}`;

/**
 * GLTFLoader plugin for BAKER_fur: shells and fins (Lengyel et al. 2001). A texture with a coverage-preserving mip
 * chain (coverageMips, Castaño 2010) is drawn from the chain and alpha-tested at its alphaCutoff: shells opaque with
 * depth writes, fins blended only by their silhouette fade. Without chains (older files) shells are blended.
 */
export class BakerFurPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_FUR;
		this.shaders = options.shaders || {};
		this.finThreshold = options.fur?.finThreshold ?? 0.4;
	}

	async afterRoot(result) {
		const c = controls(this.parser);
		const materials = this.parser.json.materials || [];
		const glsl = () => requireShader(this.shaders, 'fur');
		const objects = [];
		result.scene.traverse((o) => o.isMesh && objects.push(o));
		for (const object of objects) {
			const primitive = primitiveOf(this.parser, object);
			const finOf = primitive?.extensions?.[BAKER_FUR]?.finsOf;
			// a fin primitive has no material of its own (BAKER_fur README): its source primitive's material says
			const source = finOf !== undefined
				? this.parser.json.meshes[this.parser.associations.get(object).meshes]?.primitives?.[finOf] : primitive;
			const ext = materials[source?.material]?.extensions?.[BAKER_FUR];
			if (!ext) continue;
			if (finOf !== undefined) {
				const chain = coverageMipsOf(ext, ext.finTexture);
				const mipped = chain && await coverageMipsTexture(this.parser, chain);
				const texture = mipped || await textureOf(this.parser, ext.finTexture);
				if (!texture) continue;
				const uniforms = {
					u_texture: { value: texture }, u_length: { value: ext.length }, u_threshold: { value: this.finThreshold },
					u_alphaCutoff: { value: mipped ? chain.alphaCutoff : 0.0 }, u_alphaTest: { value: mipped ? 1.0 : 0.0 },
				};
				object.material = litShaderMaterial({
					name: 'baker fur fins', uniforms, vertexShader: glsl() + FUR_FIN_VERTEX,
					fragmentShader: `#include <common>\n#include <lights_pars_begin>\n${glsl()}${DIRECTIONAL_DIFFUSE}${FUR_FIN_FRAGMENT}`,
					transparent: true, depthWrite: false, side: THREE.DoubleSide,
				});
				object.frustumCulled = false;
				object.renderOrder = 3;
				c.add('fur', (on) => { object.visible = on; });
				continue;
			}
			if (primitive?.extensions?.[BAKER_EDGES]?.finsOf !== undefined) continue;
			const shellTextures = ext.shellTextures || [];
			const chains = shellTextures.map((t) => coverageMipsOf(ext, t));
			const mipped = await Promise.all(chains.map((chain) => chain && coverageMipsTexture(this.parser, chain)));
			const textures = await Promise.all(shellTextures.map((t, i) => mipped[i] || textureOf(this.parser, t)));
			const shells = new THREE.Group();
			shells.name = 'baker fur shells';
			textures.forEach((texture, i) => {
				texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
				texture.needsUpdate = true;
				const alphaTested = Boolean(mipped[i]); // the chain keeps the coverage the alpha test draws
				const uniforms = {
					u_texture: { value: texture }, u_shell: { value: i }, u_shellCount: { value: ext.shellCount ?? textures.length },
					u_shellSpacing: { value: ext.shellSpacing ?? (ext.length / textures.length) }, u_tiling: { value: ext.tiling ?? 1 },
					u_alphaCutoff: { value: alphaTested ? chains[i].alphaCutoff : 0.01 }, u_alphaTest: { value: alphaTested ? 1.0 : 0.0 },
				};
				const shell = new THREE.Mesh(object.geometry, litShaderMaterial({
					name: `baker fur shell ${i}`, uniforms, vertexShader: glsl() + FUR_SHELL_VERTEX,
					fragmentShader: `#include <common>\n#include <lights_pars_begin>\n${glsl()}${DIRECTIONAL_DIFFUSE}${FUR_SHELL_FRAGMENT}`,
					transparent: !alphaTested, depthWrite: alphaTested,
				}));
				shell.renderOrder = 4 + i; // inner to outer
				shell.frustumCulled = false;
				shells.add(shell);
			});
			object.add(shells);
			c.add('fur', (on) => { shells.visible = on; });
		}
		return null;
	}
}
