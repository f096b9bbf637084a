// BAKER_fur: Lengyel et al. 2001 shells (one blended pass per shell texture) and fins; the stages are
// runtime-shaders/hosts/web/fur_*.glsl.
import * as THREE from 'three';
import { coverageMipsOf, runtime } from '@baker/shared';
import { BAKER_EDGES, BAKER_FUR, controls, coverageMipsTexture, primitiveOf, requireShader, stageMaterial, textureOf } from './common.js';

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
		this.finThreshold = options.fur?.finThreshold ?? runtime('fur').options.finThreshold;
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
				object.material = stageMaterial({
					name: 'baker fur fins', uniforms, glsl: glsl(), vertex: 'fur_fin.vert', fragment: 'fur_fin.frag', lit: true,
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
				const shell = new THREE.Mesh(object.geometry, stageMaterial({
					name: `baker fur shell ${i}`, uniforms, glsl: glsl(), vertex: 'fur_shell.vert', fragment: 'fur_shell.frag', lit: true,
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

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerFurPlugin];
