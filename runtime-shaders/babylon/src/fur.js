// BAKER_fur: Lengyel et al. 2001 shells (one blended pass per shell texture) and fins.
import { coverageMipsOf } from '@baker/shared';
import { BAKER_EDGES, BAKER_FUR, GLTF_FRONT, LIGHTS_GLSL, bakerShaderMaterial, controls, coverageMipsTexture, dataTexture, loadedPrimitives, readAccessor, requireShader } from './common.js';
import { asComponents, bakerMesh, primitiveAttributes, primitiveIndices } from './geometry.js';

const SHELL_VERTEX = `
attribute vec3 position;
attribute vec3 normal;
attribute vec2 uv;
uniform mat4 world;
uniform mat4 viewProjection;
uniform float u_shell;
uniform float u_shellCount;
uniform float u_shellSpacing;
uniform float u_tiling;
varying vec2 vUvFur;
varying vec3 vNormalW;
void main() {
	vec3 p = baker_fur_shell_position(position, normal, u_shell, u_shellSpacing, u_shellCount, vec3(0.0));
	vUvFur = baker_fur_shell_uv(uv, u_tiling);
	vNormalW = normalize(mat3(world) * normal);
	gl_Position = viewProjection * world * vec4(p, 1.0);
}`;

const SHELL_FRAGMENT = `
uniform sampler2D u_texture;
uniform float u_shell;
uniform float u_shellCount;
uniform float u_alphaCutoff;
uniform float u_alphaTest;
varying vec2 vUvFur;
varying vec3 vNormalW;
void main() {
	vec4 texel = texture(u_texture, vUvFur);
	if (texel.a < u_alphaCutoff) discard;
	vec4 shaded = baker_fur_shell_shade(texel, baker_fur_shell_height(u_shell, u_shellCount), 0.35);
	vec3 light = u_ambientLight + baker_directional_diffuse(normalize(vNormalW)) * 0.5;
	gl_FragColor = vec4(shaded.rgb * light, mix(shaded.a, 1.0, u_alphaTest));
}`;

const FIN_VERTEX = (decl, a) => `
${decl}
uniform mat4 world;
uniform mat4 viewProjection;
uniform vec3 u_eye;
uniform float u_length;
uniform float u_threshold;
varying vec2 vUvFin;
varying float vWeight;
varying vec3 vNormalW;
void main() {
	vec3 v0 = ${a('bakerFinV0', 3)}, v1 = ${a('bakerFinV1', 3)}, v2 = ${a('bakerFinV2', 3)}, v3 = ${a('bakerFinV3', 3)};
	vec3 finNormal = ${a('bakerFurFinNormal', 3)};
	vec3 p = baker_fur_fin_position(v0, v1, finNormal, ${a('bakerFinCorner', 1)}, u_length);
	vec3 n0;
	vec3 n1;
	baker_fur_fin_face_normals(v0, v1, v2, v3, n0, n1);
	vec3 eye = (inverse(world) * vec4(u_eye, 1.0)).xyz;
	vWeight = baker_fur_fin_weight(n0, n1, normalize(eye - p), u_threshold);
	vUvFin = ${a('bakerFurFinUv', 2)};
	vNormalW = normalize(mat3(world) * finNormal);
	gl_Position = viewProjection * world * vec4(p, 1.0);
}`;

const FIN_FRAGMENT = `
uniform sampler2D u_texture;
uniform float u_alphaCutoff;
uniform float u_alphaTest;
varying vec2 vUvFin;
varying float vWeight;
varying vec3 vNormalW;
void main() {
	vec4 texel = texture(u_texture, vUvFin);
	if (texel.a < u_alphaCutoff) discard;
	float a = mix(texel.a, 1.0, u_alphaTest) * vWeight;
	if (a < 0.01) discard;
	vec3 light = u_ambientLight + baker_directional_diffuse(normalize(vNormalW)) * 0.5;
	gl_FragColor = vec4(texel.rgb * light, a);
}`;

/**
 * Loader extension for BAKER_fur: shells and fins (Lengyel et al. 2001). options.fur.finThreshold: |N.V| where fins
 * fade out. A texture with a coverage-preserving mip chain (coverageMips, Castaño 2010) is drawn from the chain and
 * alpha-tested at its alphaCutoff: shells opaque with depth writes, fins blended only by their silhouette fade.
 * Without chains (older files) shells are blended.
 */
export class BakerFurExtension {
	constructor(loader, options = {}) {
		this.name = BAKER_FUR;
		this.enabled = true;
		this.order = 220;
		this.loader = loader;
		this.shaders = options.shaders || {};
		this.finThreshold = options.fur?.finThreshold ?? 0.4;
	}
	dispose() { this.loader = null; }

	async onReady() {
		const loader = this.loader;
		const scene = loader.babylonScene;
		const c = controls(loader);
		const materials = loader.gltf.materials || [];
		const glsl = requireShader(this.shaders, 'fur');
		const all = loadedPrimitives(loader);
		for (const { primitive, mesh, meshIndex } of all) {
			const finOf = primitive.extensions?.[BAKER_FUR]?.finsOf;
			const source = finOf !== undefined ? loader.gltf.meshes[meshIndex].primitives[finOf] : primitive;
			const ext = source?.material !== undefined && materials[source.material]?.extensions?.[BAKER_FUR];
			if (!ext || !mesh) continue;
			if (finOf !== undefined) {
				const chain = coverageMipsOf(ext, ext.finTexture);
				const mipped = chain && await coverageMipsTexture(loader, chain);
				const texture = mipped || await dataTexture(loader, ext.finTexture);
				if (!texture) continue;
				const { attributes, declarations } = await primitiveAttributes(loader, primitive, {
					_FIN_V0: 'bakerFinV0', _FIN_V1: 'bakerFinV1', _FIN_V2: 'bakerFinV2', _FIN_V3: 'bakerFinV3',
					_FIN_CORNER: 'bakerFinCorner', _FUR_FIN_NORMAL: 'bakerFurFinNormal', _FUR_FIN_UV: 'bakerFurFinUv' });
				const a = (kind, want) => asComponents(kind, attributes[kind].size, want);
				for (const [kind, { data, size }] of Object.entries(attributes)) mesh.setVerticesData(kind, data, false, size);
				const material = bakerShaderMaterial('baker fur fins', scene, {
					vertex: glsl + FIN_VERTEX(declarations, a), fragment: `${glsl}${LIGHTS_GLSL}${FIN_FRAGMENT}`,
					attributes: ['position', ...Object.keys(attributes)], uniforms: ['u_length', 'u_threshold', 'u_alphaCutoff', 'u_alphaTest'],
					samplers: ['u_texture'], alpha: true,
				});
				material.setTexture('u_texture', texture);
				material.setFloat('u_alphaCutoff', mipped ? chain.alphaCutoff : 0.0);
				material.setFloat('u_alphaTest', mipped ? 1.0 : 0.0);
				material.setFloat('u_length', ext.length);
				material.setFloat('u_threshold', this.finThreshold);
				material.backFaceCulling = false;
				material.disableDepthWrite = true;
				mesh.material = material;
				mesh.alphaIndex = 3;
				mesh.alwaysSelectAsActiveMesh = true;
				c.add('fur', (on) => mesh.setEnabled(on));
				continue;
			}
			if (primitive.extensions?.[BAKER_EDGES]?.finsOf !== undefined) continue;
			const positions = (await readAccessor(loader, primitive.attributes.POSITION)).data;
			const indices = await primitiveIndices(loader, primitive, positions.length / 3);
			const normals = await readAccessor(loader, primitive.attributes.NORMAL);
			const uvs = await readAccessor(loader, primitive.attributes.TEXCOORD_0);
			const shells = [];
			const shellTextures = ext.shellTextures || [];
			const chains = shellTextures.map((t) => coverageMipsOf(ext, t));
			const mipped = await Promise.all(chains.map((chain) => chain && coverageMipsTexture(loader, chain)));
			const textures = await Promise.all(shellTextures.map((t, i) => mipped[i] || dataTexture(loader, t, { repeat: true, mipmaps: true })));
			textures.forEach((texture, i) => {
				const alphaTested = Boolean(mipped[i]); // the chain keeps the coverage the alpha test draws
				const shell = bakerMesh(`baker fur shell ${i}`, scene, mesh, positions, indices, { normal: normals, uv: uvs });
				const material = bakerShaderMaterial(`baker fur shell ${i}`, scene, {
					vertex: glsl + SHELL_VERTEX, fragment: `${glsl}${LIGHTS_GLSL}${SHELL_FRAGMENT}`,
					attributes: ['position', 'normal', 'uv'],
					uniforms: ['u_shell', 'u_shellCount', 'u_shellSpacing', 'u_tiling', 'u_alphaCutoff', 'u_alphaTest'],
					samplers: ['u_texture'], alpha: !alphaTested,
				});
				material.setTexture('u_texture', texture);
				material.setFloat('u_alphaCutoff', alphaTested ? chains[i].alphaCutoff : 0.01);
				material.setFloat('u_alphaTest', alphaTested ? 1.0 : 0.0);
				material.setFloat('u_shell', i);
				material.setFloat('u_shellCount', ext.shellCount ?? textures.length);
				material.setFloat('u_shellSpacing', ext.shellSpacing ?? ext.length / textures.length);
				material.setFloat('u_tiling', ext.tiling ?? 1);
				material.disableDepthWrite = !alphaTested;
				material.sideOrientation = GLTF_FRONT;
				shell.material = material;
				shell.alphaIndex = 4 + i; // inner to outer
				shells.push(shell);
			});
			c.add('fur', (on) => shells.forEach((s) => s.setEnabled(on)));
		}
	}
}
