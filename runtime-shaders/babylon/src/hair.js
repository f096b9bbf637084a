// BAKER_hair: view-facing ribbons extruded in the vertex shader, shaded as hair fibres where the material has
// BAKER_hair_shading (runtime-shaders/baker_hair_shading.glsl, stages hair_ribbon.vert + hair_fibre.frag; on
// WebGPUEngine baker_hair_shading.wgsl and the WGSL stages hair_fibre.vert/.frag), else (or with
// options.hair.shading = 'kajiyaKay') Kajiya-Kay (RTR4 14.7); the stages are runtime-shaders/hosts/web/*.glsl.
import { Constants } from '@babylonjs/core/Engines/constants.js';
import { RawTexture } from '@babylonjs/core/Materials/Textures/rawTexture.js';
import { hairShadingChoice, hairShadingGlsl, hairShadingOf, hairTableTexels, runtime } from '@baker/shared';
import { BAKER_HAIR, controls, loadedPrimitives, readAccessor, engineModule, requireShader, requireWgsl, stageMaterial } from './common.js';

/** The three tables of a resolved BAKER_hair_shading as half-float RGBA RawTextures (bilinear, clamped, no mips). */
export async function hairShadingTextures(loader, shading) {
	const scene = loader.babylonScene;
	const upload = async (table) => {
		const { data } = await readAccessor(loader, table.accessor, { integer: true }); // the halves' bits as numbers
		const texture = new RawTexture(hairTableTexels(table, data), table.width, table.height, Constants.TEXTUREFORMAT_RGBA, scene,
			false, false, Constants.TEXTURE_BILINEAR_SAMPLINGMODE, Constants.TEXTURETYPE_HALF_FLOAT);
		texture.wrapU = texture.wrapV = Constants.TEXTURE_CLAMP_ADDRESSMODE;
		return texture;
	};
	const t = shading.tables;
	const [longitudinal, azimuthal, dual] = await Promise.all([upload(t.longitudinal), upload(t.azimuthal), upload(t.dualScattering)]);
	return { longitudinal, azimuthal, dual };
}

// What hair_ribbon.vert (BAKER_HAIR_SHADING) and hair_fibre.frag add to the Kajiya-Kay stages
const FIBRE_UNIFORMS = ['u_hairVariances', 'u_hairParams', 'u_hairSigmaA', 'u_hairMelaninPerVertex'];
const FIBRE_SAMPLERS = ['u_hairLongitudinal', 'u_hairAzimuthal', 'u_hairDual'];

/** BAKER_hair_shading's strand attributes doubled for the ribbon (x of a wider one); absent: open, no fibres. */
async function fibreAttributes(loader, primitive, shading, count) {
	const read = (name) => (name && primitive.attributes[name] !== undefined ? readAccessor(loader, primitive.attributes[name]) : null);
	const [melanin, occlusion, positive, negative] = await Promise.all([read(shading.melaninAttribute),
		read(shading.occlusionAttribute), read(shading.fibresPositive), read(shading.fibresNegative)]);
	const double = (accessor, size, fill) => {
		const out = new Float32Array(count * 2 * size).fill(fill);
		if (accessor) {
			for (let v = 0; v < count; v++) {
				for (let k = 0; k < size; k++) {
					out[2 * v * size + k] = out[(2 * v + 1) * size + k] = accessor.data[v * accessor.size + k];
				}
			}
		}
		return { data: out, size };
	};
	const m = double(melanin, 2, 0).data;
	const o = double(occlusion, 1, 1).data;
	const packed = new Float32Array(o.length * 3); // eumelanin, pheomelanin, occlusion: WebGPU has 8 vertex buffers
	for (let r = 0; r < o.length; r++) packed.set([m[2 * r], m[2 * r + 1], o[r]], 3 * r);
	return { baker_fibre: { data: packed, size: 3 }, baker_fibresPos: double(positive, 3, 0), baker_fibresNeg: double(negative, 3, 0) };
}
import { bakerMesh } from './geometry.js';

/**
 * Ribbon arrays of a BAKER_hair primitive: ribbon vertex r is line vertex r / 2 on side r % 2 (the extension's
 * ribbonIndices index them), with the strand's widthScale per vertex. Attributes keep their accessor's size.
 */
export function ribbonArrays(line, widthScale, verticesPerStrand) {
	const count = line.position.count;
	const double = ({ data, size }) => {
		const out = new Float32Array(count * 2 * size);
		for (let v = 0; v < count; v++) {
			out.set(data.subarray(v * size, v * size + size), 2 * v * size);
			out.set(data.subarray(v * size, v * size + size), (2 * v + 1) * size);
		}
		return { data: out, size };
	};
	const side = new Float32Array(count * 2);
	const scale = new Float32Array(count * 2);
	for (let r = 0; r < count * 2; r++) {
		side[r] = r % 2;
		scale[r] = widthScale ? widthScale[Math.floor(Math.floor(r / 2) / verticesPerStrand)] : 1;
	}
	return {
		positions: double(line.position).data,
		attributes: { bakerTangent: double(line.tangent), bakerParam: double(line.param),
			bakerSide: { data: side, size: 1 }, bakerWidthScale: { data: scale, size: 1 } },
	};
}

/** Loader extension for BAKER_hair. options.hair: { specular: [r, g, b], exponent } of Kajiya-Kay. */
export class BakerHairExtension {
	constructor(loader, options = {}) {
		this.name = BAKER_HAIR;
		this.enabled = true;
		this.order = 230;
		this.loader = loader;
		this.shaders = options.shaders || {};
		this.options = options;
		this.style = { ...runtime('hair').options, ...(options.hair || {}) };
		this.shading = hairShadingChoice(options);
	}
	dispose() { this.loader = null; }

	async onReady() {
		const loader = this.loader;
		const scene = loader.babylonScene;
		const c = controls(loader);
		const glsl = engineModule(this, 'hair', scene); // WGSL on WebGPUEngine
		for (const { primitive, mesh } of loadedPrimitives(loader)) {
			const ext = primitive.extensions?.[BAKER_HAIR];
			if (!ext || ext.ribbonIndices === undefined || !mesh) continue;
			const read = (name) => readAccessor(loader, primitive.attributes[name]);
			const [position, tangent, param, indices, widths] = await Promise.all([
				read('POSITION'), read(ext.tangentAttribute ?? '_STRAND_TANGENT'), read(ext.paramAttribute ?? '_STRAND_PARAM'),
				readAccessor(loader, ext.ribbonIndices, { integer: true }),
				ext.widthScale !== undefined ? readAccessor(loader, ext.widthScale) : null,
			]);
			const ribbon = ribbonArrays({ position, tangent, param }, widths && widths.data, ext.verticesPerStrand);
			// under the shared stage's attribute names
			const { bakerTangent, bakerParam, bakerSide, bakerWidthScale } = ribbon.attributes;
			const webgpu = scene.getEngine().isWebGPU;
			const fibre = this.shading === 'fibre' ? hairShadingOf(loader.gltf, primitive.material) : null;
			const attributes = { baker_tangent: bakerTangent, baker_param: bakerParam, baker_side: bakerSide, baker_widthScale: bakerWidthScale,
				...(fibre ? await fibreAttributes(loader, primitive, fibre, position.count) : {}) };
			const ribbons = bakerMesh('baker hair ribbons', scene, mesh.parent, ribbon.positions, indices.data, attributes);
			ribbons.position.copyFrom(mesh.position);
			if (mesh.rotationQuaternion) ribbons.rotationQuaternion = mesh.rotationQuaternion.clone();
			ribbons.scaling.copyFrom(mesh.scaling);
			const json = primitive.material !== undefined ? loader.gltf.materials?.[primitive.material] : null;
			const base = json?.pbrMetallicRoughness?.baseColorFactor ?? [0.18, 0.11, 0.06, 1];
			const material = stageMaterial('baker hair ribbons', scene, {
				glsl: !fibre ? glsl : webgpu ? glsl + requireWgsl(this.options.wgsl, 'hairShading')
					: `#define BAKER_HAIR_SHADING\n${glsl}${hairShadingGlsl(requireShader(this.shaders, 'hairShading'))}`,
				// WebGPU: the WGSL twins of the stages (stages_wgsl.js), the ribbon's fibre part as a stage of its own
				vertex: fibre && webgpu ? 'hair_fibre.vert' : 'hair_ribbon.vert', fragment: fibre ? 'hair_fibre.frag' : 'hair_ribbon.frag', lit: true,
				attributes: ['position', ...Object.keys(attributes)],
				uniforms: ['u_rootWidth', 'u_tipWidth', 'u_lodWidthScale', 'u_color', 'u_specular', 'u_exponent', ...(fibre ? FIBRE_UNIFORMS : [])],
				samplers: fibre ? FIBRE_SAMPLERS : [], alpha: true,
			});
			if (fibre) {
				const textures = await hairShadingTextures(loader, fibre);
				material.setTexture('u_hairLongitudinal', textures.longitudinal);
				material.setTexture('u_hairAzimuthal', textures.azimuthal);
				material.setTexture('u_hairDual', textures.dual);
				material.setVector4('u_hairVariances', { x: fibre.variances[0], y: fibre.variances[1], z: fibre.variances[2], w: fibre.variances[3] });
				material.setVector4('u_hairParams', { x: fibre.params[0], y: fibre.params[1], z: fibre.params[2], w: fibre.params[3] });
				material.setVector3('u_hairSigmaA', { x: fibre.sigmaA[0], y: fibre.sigmaA[1], z: fibre.sigmaA[2] });
				material.setFloat('u_hairMelaninPerVertex', fibre.melaninAttribute ? 1 : 0);
			}
			material.setFloat('u_rootWidth', ext.rootWidth);
			material.setFloat('u_lodWidthScale', 1); // every strand (the lods are @baker/three's setHairLod)
			material.setFloat('u_tipWidth', ext.tipWidth);
			material.setVector3('u_color', { x: base[0], y: base[1], z: base[2] });
			const s = this.style.specular;
			material.setVector3('u_specular', { x: s[0], y: s[1], z: s[2] });
			material.setFloat('u_exponent', this.style.exponent);
			material.backFaceCulling = false;
			ribbons.material = material;
			c.add('hair', (on) => { ribbons.setEnabled(on); mesh.setEnabled(!on); }); // off: the plain lines glTF defines
		}
	}
}

/** What index.js registers with Babylon's glTF loader for this technique (found through the descriptor's name). */
export const LOADER_EXTENSIONS = { [BAKER_HAIR]: BakerHairExtension };
