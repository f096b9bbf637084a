// BAKER_hair: view-facing ribbons extruded in the vertex shader, Kajiya-Kay shading; the stages are
// runtime-shaders/hosts/web/hair_ribbon.*.glsl.
import * as THREE from 'three';
import { runtime } from '@baker/shared';
import { BAKER_HAIR, controls, primitiveOf, requireShader, stageMaterial, trackViewport } from './common.js';

/**
 * Ribbon geometry of a BAKER_hair primitive: ribbon vertex r is line vertex r / 2 on side r % 2 (the extension's
 * ribbonIndices index them), with the strand's widthScale per vertex.
 */
export function ribbonGeometry(line, ribbonIndices, widthScale, verticesPerStrand, attributes) {
	const count = line.attributes.position.count;
	const double = (attribute, size) => {
		const out = new Float32Array(count * 2 * size);
		for (let v = 0; v < count; v++) {
			for (let k = 0; k < size; k++) {
				const x = attribute ? attribute.getComponent(v, k) : 0;
				out[(2 * v) * size + k] = x;
				out[(2 * v + 1) * size + k] = x;
			}
		}
		return new THREE.BufferAttribute(out, size);
	};
	const geometry = new THREE.BufferGeometry();
	geometry.setAttribute('position', double(line.attributes.position, 3));
	geometry.setAttribute('baker_tangent', double(line.getAttribute(attributes.tangent), 3));
	geometry.setAttribute('baker_param', double(line.getAttribute(attributes.param), 1));
	const side = new Float32Array(count * 2);
	const scale = new Float32Array(count * 2);
	for (let r = 0; r < count * 2; r++) {
		side[r] = r % 2;
		scale[r] = widthScale ? widthScale[Math.floor(Math.floor(r / 2) / verticesPerStrand)] : 1;
	}
	geometry.setAttribute('baker_side', new THREE.BufferAttribute(side, 1));
	geometry.setAttribute('baker_widthScale', new THREE.BufferAttribute(scale, 1));
	geometry.setIndex(new THREE.BufferAttribute(ribbonIndices, 1));
	return geometry;
}

/**
 * Draw level `level` of a BAKER_hair primitive's `lods` (written by `baker guides`, order "lodPrefix"): the first
 * lods[level].strandCount strands (a prefix of the ribbon index buffer, 6 indices per segment) with every width
 * times lods[level].widthScale. `ribbons` is the mesh the plugin made (userData.bakerHair holds the lods).
 */
export function setHairLod(ribbons, level) {
	const hair = ribbons.userData.bakerHair;
	if (!hair || !hair.lods.length) return;
	const k = Math.max(0, Math.min(Math.floor(level), hair.lods.length - 1));
	const lod = hair.lods[k];
	ribbons.geometry.setDrawRange(0, lod.strandCount * 6 * (hair.verticesPerStrand - 1));
	ribbons.material.uniforms.u_lodWidthScale.value = lod.widthScale;
	hair.level = k;
}

/** GLTFLoader plugin for BAKER_hair: view-facing ribbons extruded in the vertex shader, Kajiya-Kay shading. */
export class BakerHairPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_HAIR;
		this.shaders = options.shaders || {};
		this.lod = options.hairLod ?? runtime('hair').options.lod; // level of `lods` drawn at load (setHairLod changes it later)
		this.style = { ...runtime('hair').options, ...(options.hair || {}) };
	}

	async afterRoot(result) {
		const c = controls(this.parser);
		const lines = [];
		result.scene.traverse((o) => (o.isLineSegments || o.isLine) && lines.push(o));
		for (const object of lines) {
			const ext = primitiveOf(this.parser, object)?.extensions?.[BAKER_HAIR];
			if (!ext || ext.ribbonIndices === undefined) continue;
			const [indices, widths] = await Promise.all([
				this.parser.getDependency('accessor', ext.ribbonIndices),
				ext.widthScale !== undefined ? this.parser.getDependency('accessor', ext.widthScale) : null,
			]);
			const geometry = ribbonGeometry(object.geometry, indices.array, widths && widths.array, ext.verticesPerStrand,
				{ tangent: (ext.tangentAttribute ?? '_STRAND_TANGENT').toLowerCase(), param: (ext.paramAttribute ?? '_STRAND_PARAM').toLowerCase() });
			const base = object.material.color ? object.material.color.clone() : new THREE.Color(0.18, 0.11, 0.06);
			const uniforms = {
				u_rootWidth: { value: ext.rootWidth }, u_tipWidth: { value: ext.tipWidth }, u_lodWidthScale: { value: 1 },
				u_viewport: { value: new THREE.Vector2(1, 1) },
				u_color: { value: new THREE.Vector3(base.r, base.g, base.b) },
				u_specular: { value: new THREE.Vector3(...this.style.specular) }, u_exponent: { value: this.style.exponent },
			};
			const glsl = requireShader(this.shaders, 'hair');
			const ribbons = new THREE.Mesh(geometry, stageMaterial({
				name: 'baker hair ribbons', uniforms, glsl, vertex: 'hair_ribbon.vert', fragment: 'hair_ribbon.frag', lit: true,
				transparent: true, side: THREE.DoubleSide,
			}));
			ribbons.name = 'baker hair ribbons';
			ribbons.frustumCulled = false;
			ribbons.userData.bakerHair = { lods: ext.lods ?? [], verticesPerStrand: ext.verticesPerStrand, level: 0 };
			setHairLod(ribbons, this.lod);
			trackViewport(ribbons, uniforms);
			object.parent.add(ribbons);
			ribbons.position.copy(object.position);
			ribbons.quaternion.copy(object.quaternion);
			ribbons.scale.copy(object.scale);
			c.add('hair', (on) => { ribbons.visible = on; object.visible = !on; }); // off: the plain lines glTF defines
		}
		return null;
	}
}

/** What index.js registers on a GLTFLoader for this technique (found through the descriptor's name). */
export const GLTF_LOADER_PLUGINS = [BakerHairPlugin];
