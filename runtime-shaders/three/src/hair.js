// BAKER_hair: view-facing ribbons extruded in the vertex shader, shaded as hair fibres where the material has
// BAKER_hair_shading (runtime-shaders/baker_hair_shading.glsl: Chiang et al. 2016 from the baked tables + Zinke et
// al. 2008's dual scattering; stages hair_ribbon.vert + hair_fibre.frag), else (or with options.hair.shading =
// 'kajiyaKay') Kajiya-Kay (hair_ribbon.frag). The stages are runtime-shaders/hosts/web/*.glsl.
import * as THREE from 'three';
import { hairShadingChoice, hairShadingGlsl, hairShadingOf, hairTableTexels, runtime } from '@baker/shared';
import { BAKER_HAIR, controls, primitiveOf, requireShader, stageMaterial, trackViewport } from './common.js';

/**
 * The three tables of a resolved BAKER_hair_shading as half-float RGBA DataTextures (linear, clamped, no mips), the
 * accessors' UNSIGNED_SHORT elements uploaded as they are (the halves' bits).
 */
export async function hairShadingTextures(parser, shading) {
	const upload = async (table) => {
		const accessor = await parser.getDependency('accessor', table.accessor); // UNSIGNED_SHORT: Uint16Array of halves
		const texture = new THREE.DataTexture(hairTableTexels(table, accessor.array), table.width, table.height, THREE.RGBAFormat, THREE.HalfFloatType);
		texture.colorSpace = THREE.NoColorSpace;
		texture.wrapS = texture.wrapT = THREE.ClampToEdgeWrapping;
		texture.magFilter = texture.minFilter = THREE.LinearFilter;
		texture.generateMipmaps = false;
		texture.flipY = false;
		texture.needsUpdate = true;
		return texture;
	};
	const t = shading.tables;
	const [longitudinal, azimuthal, dual] = await Promise.all([upload(t.longitudinal), upload(t.azimuthal), upload(t.dualScattering)]);
	return { longitudinal, azimuthal, dual };
}

/** The uniforms of hair_fibre.frag / hair_ribbon.vert (BAKER_HAIR_SHADING) for a resolved BAKER_hair_shading. */
export function hairShadingUniforms(shading, textures) {
	return {
		u_hairLongitudinal: { value: textures.longitudinal }, u_hairAzimuthal: { value: textures.azimuthal },
		u_hairDual: { value: textures.dual },
		u_hairVariances: { value: new THREE.Vector4(...shading.variances) }, u_hairParams: { value: new THREE.Vector4(...shading.params) },
		u_hairSigmaA: { value: new THREE.Vector3(...shading.sigmaA) },
		u_hairMelaninPerVertex: { value: shading.melaninAttribute ? 1 : 0 },
	};
}

/**
 * Ribbon geometry of a BAKER_hair primitive: ribbon vertex r is line vertex r / 2 on side r % 2 (the extension's
 * ribbonIndices index them), with the strand's widthScale per vertex.
 */
export function ribbonGeometry(line, ribbonIndices, widthScale, verticesPerStrand, attributes, fibre = null) {
	const count = line.attributes.position.count;
	const double = (attribute, size, fill = 0) => {
		const out = new Float32Array(count * 2 * size);
		for (let v = 0; v < count; v++) {
			for (let k = 0; k < size; k++) {
				const x = attribute ? attribute.getComponent(v, k) : fill;
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
	if (fibre) { // BAKER_hair_shading's strand attributes (x of a wider one); absent: open, no fibres, the material's melanin
		const of = (name) => (name ? line.getAttribute(name.toLowerCase()) : undefined);
		const melanin = double(of(fibre.melaninAttribute), 2).array;
		const occlusion = double(of(fibre.occlusionAttribute), 1, 1).array;
		const packed = new Float32Array(occlusion.length * 3); // eumelanin, pheomelanin, occlusion
		for (let r = 0; r < occlusion.length; r++) packed.set([melanin[2 * r], melanin[2 * r + 1], occlusion[r]], 3 * r);
		geometry.setAttribute('baker_fibre', new THREE.BufferAttribute(packed, 3));
		geometry.setAttribute('baker_fibresPos', double(of(fibre.fibresPositive), 3));
		geometry.setAttribute('baker_fibresNeg', double(of(fibre.fibresNegative), 3));
	}
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

/**
 * GLTFLoader plugin for BAKER_hair: view-facing ribbons extruded in the vertex shader, shaded as fibres
 * (BAKER_hair_shading) or Kajiya-Kay. options.hair: { shading: 'fibre' | 'kajiyaKay', specular, exponent }.
 */
export class BakerHairPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_HAIR;
		this.shaders = options.shaders || {};
		this.lod = options.hairLod ?? runtime('hair').options.lod; // level of `lods` drawn at load (setHairLod changes it later)
		this.style = { ...runtime('hair').options, ...(options.hair || {}) };
		this.shading = hairShadingChoice(options);
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
			const primitive = primitiveOf(this.parser, object);
			const fibre = this.shading === 'fibre' ? hairShadingOf(this.parser.json, primitive.material) : null;
			const geometry = ribbonGeometry(object.geometry, indices.array, widths && widths.array, ext.verticesPerStrand,
				{ tangent: (ext.tangentAttribute ?? '_STRAND_TANGENT').toLowerCase(), param: (ext.paramAttribute ?? '_STRAND_PARAM').toLowerCase() }, fibre);
			const base = object.material.color ? object.material.color.clone() : new THREE.Color(0.18, 0.11, 0.06);
			const uniforms = {
				u_rootWidth: { value: ext.rootWidth }, u_tipWidth: { value: ext.tipWidth }, u_lodWidthScale: { value: 1 },
				u_viewport: { value: new THREE.Vector2(1, 1) },
				u_color: { value: new THREE.Vector3(base.r, base.g, base.b) },
				u_specular: { value: new THREE.Vector3(...this.style.specular) }, u_exponent: { value: this.style.exponent },
				...(fibre ? hairShadingUniforms(fibre, await hairShadingTextures(this.parser, fibre)) : {}),
			};
			const glsl = requireShader(this.shaders, 'hair') + (fibre ? hairShadingGlsl(requireShader(this.shaders, 'hairShading')) : '');
			const ribbons = new THREE.Mesh(geometry, stageMaterial({
				name: 'baker hair ribbons', uniforms, glsl, vertex: 'hair_ribbon.vert', fragment: fibre ? 'hair_fibre.frag' : 'hair_ribbon.frag',
				lit: true, transparent: true, side: THREE.DoubleSide, defines: fibre ? { BAKER_HAIR_SHADING: '' } : {},
			}));
			ribbons.name = 'baker hair ribbons';
			ribbons.frustumCulled = false;
			ribbons.userData.bakerHair = { lods: ext.lods ?? [], verticesPerStrand: ext.verticesPerStrand, level: 0,
				shading: fibre ? 'fibre' : 'kajiyaKay' };
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
