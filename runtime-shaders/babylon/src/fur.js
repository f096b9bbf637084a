// BAKER_fur: Lengyel et al. 2001 shells (one blended pass per shell texture) and fins; the stages are
// runtime-shaders/hosts/web/fur_*.glsl.
import { coverageMipsOf, runtime } from '@baker/shared';
import { BAKER_EDGES, BAKER_FUR, GLTF_FRONT, controls, coverageMipsTexture, dataTexture, loadedPrimitives, readAccessor, engineModule, stageMaterial } from './common.js';
import { bakerMesh, primitiveAttributes, primitiveIndices } from './geometry.js';

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
		this.options = options;
		this.finThreshold = options.fur?.finThreshold ?? runtime('fur').options.finThreshold;
	}
	dispose() { this.loader = null; }

	async onReady() {
		const loader = this.loader;
		const scene = loader.babylonScene;
		const c = controls(loader);
		const materials = loader.gltf.materials || [];
		const glsl = engineModule(this, 'fur', scene); // WGSL on WebGPUEngine
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
				const attributes = await primitiveAttributes(loader, primitive,
					['_FIN_V0', '_FIN_V1', '_FIN_V2', '_FIN_V3', '_FIN_CORNER', '_FUR_FIN_NORMAL', '_FUR_FIN_UV']);
				for (const [kind, { data, size }] of Object.entries(attributes)) mesh.setVerticesData(kind, data, false, size);
				const material = stageMaterial('baker fur fins', scene, {
					glsl, vertex: 'fur_fin.vert', fragment: 'fur_fin.frag', lit: true,
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
				const material = stageMaterial(`baker fur shell ${i}`, scene, {
					glsl, vertex: 'fur_shell.vert', fragment: 'fur_shell.frag', lit: true,
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

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_FUR]: BakerFurExtension };
