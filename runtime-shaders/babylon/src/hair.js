// BAKER_hair: view-facing ribbons extruded in the vertex shader, Kajiya-Kay shading (RTR4 14.7).
import { BAKER_HAIR, LIGHTS_GLSL, bakerShaderMaterial, controls, loadedPrimitives, readAccessor, requireShader } from './common.js';
import { asComponents, bakerMesh } from './geometry.js';

const HAIR_VERTEX = (a) => `
attribute vec3 position;
attribute ${a.tangentType} bakerTangent;
attribute ${a.paramType} bakerParam;
attribute float bakerSide;
attribute float bakerWidthScale;
uniform mat4 world;
uniform mat4 view;
uniform mat4 projection;
uniform vec3 u_eye;
uniform vec2 u_viewport;
uniform float u_rootWidth;
uniform float u_tipWidth;
varying float vOpacity;
varying vec3 vTangentW;
varying vec3 vViewW;
void main() {
	vec3 tangent = ${a.tangent};
	vec3 eye = (inverse(world) * vec4(u_eye, 1.0)).xyz;  // object space
	float w = baker_hair_width(u_rootWidth, u_tipWidth, ${a.param}, bakerWidthScale);
	float tanHalfFovY = 1.0 / projection[1][1];
	vec2 cov = baker_hair_coverage(w, baker_hair_pixel_size(distance(eye, position), tanHalfFovY, u_viewport.y));
	vec3 p = baker_hair_ribbon_position(position, tangent, eye, cov.x, bakerSide);
	vOpacity = cov.y;
	vec4 worldPosition = world * vec4(p, 1.0);
	vTangentW = normalize(mat3(world) * tangent);
	vViewW = u_eye - worldPosition.xyz;
	gl_Position = projection * view * worldPosition;
}`;

const HAIR_FRAGMENT = `
uniform vec3 u_color;
uniform vec3 u_specular;
uniform float u_exponent;
varying float vOpacity;
varying vec3 vTangentW;
varying vec3 vViewW;
void main() {
	vec3 T = normalize(vTangentW);
	vec3 V = normalize(vViewW);
	vec3 color = u_ambientLight * u_color;
	for (int i = 0; i < 4; i++) {
		if (i >= u_lightCount) break;
		color += u_lightColor[i] * baker_hair_kajiya_kay(T, u_lightDirection[i], V, u_color, u_specular, u_exponent);
	}
	gl_FragColor = vec4(color, vOpacity);
}`;

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
		this.style = { specular: [0.3, 0.28, 0.25], exponent: 60, ...(options.hair || {}) };
	}
	dispose() { this.loader = null; }

	async onReady() {
		const loader = this.loader;
		const scene = loader.babylonScene;
		const c = controls(loader);
		const glsl = requireShader(this.shaders, 'hair');
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
			const ribbons = bakerMesh('baker hair ribbons', scene, mesh.parent, ribbon.positions, indices.data, ribbon.attributes);
			ribbons.position.copyFrom(mesh.position);
			if (mesh.rotationQuaternion) ribbons.rotationQuaternion = mesh.rotationQuaternion.clone();
			ribbons.scaling.copyFrom(mesh.scaling);
			const json = primitive.material !== undefined ? loader.gltf.materials?.[primitive.material] : null;
			const base = json?.pbrMetallicRoughness?.baseColorFactor ?? [0.18, 0.11, 0.06, 1];
			const material = bakerShaderMaterial('baker hair ribbons', scene, {
				vertex: glsl + HAIR_VERTEX({
					tangentType: tangent.size === 1 ? 'float' : `vec${tangent.size}`, paramType: param.size === 1 ? 'float' : `vec${param.size}`,
					tangent: asComponents('bakerTangent', tangent.size, 3), param: asComponents('bakerParam', param.size, 1),
				}),
				fragment: `${glsl}${LIGHTS_GLSL}${HAIR_FRAGMENT}`,
				attributes: ['position', ...Object.keys(ribbon.attributes)],
				uniforms: ['u_rootWidth', 'u_tipWidth', 'u_color', 'u_specular', 'u_exponent'], alpha: true,
			});
			material.setFloat('u_rootWidth', ext.rootWidth);
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
