// BAKER_hair: view-facing ribbons extruded in the vertex shader, Kajiya-Kay shading (RTR4 14.7); the stages are
// runtime-shaders/hosts/web/hair_ribbon.*.glsl.
import { runtime } from '@baker/shared';
import { BAKER_HAIR, controls, loadedPrimitives, readAccessor, engineModule, stageMaterial } from './common.js';
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
			const attributes = { baker_tangent: bakerTangent, baker_param: bakerParam, baker_side: bakerSide, baker_widthScale: bakerWidthScale };
			const ribbons = bakerMesh('baker hair ribbons', scene, mesh.parent, ribbon.positions, indices.data, attributes);
			ribbons.position.copyFrom(mesh.position);
			if (mesh.rotationQuaternion) ribbons.rotationQuaternion = mesh.rotationQuaternion.clone();
			ribbons.scaling.copyFrom(mesh.scaling);
			const json = primitive.material !== undefined ? loader.gltf.materials?.[primitive.material] : null;
			const base = json?.pbrMetallicRoughness?.baseColorFactor ?? [0.18, 0.11, 0.06, 1];
			const material = stageMaterial('baker hair ribbons', scene, {
				glsl, vertex: 'hair_ribbon.vert', fragment: 'hair_ribbon.frag', lit: true,
				attributes: ['position', ...Object.keys(attributes)],
				uniforms: ['u_rootWidth', 'u_tipWidth', 'u_lodWidthScale', 'u_color', 'u_specular', 'u_exponent'], alpha: true,
			});
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
