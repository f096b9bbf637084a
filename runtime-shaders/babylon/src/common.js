// Shared by the loader extensions of @baker/babylon: the extension names, the techniques (switches) and the
// per-load registry of their on/off handlers, and what several extensions use (primitive -> mesh lookup, a generic
// accessor reader for custom attributes, data textures, scene lights for ShaderMaterials). Import from index.js.
import { Buffer } from '@babylonjs/core/Buffers/buffer.js';
import { Constants } from '@babylonjs/core/Engines/constants.js';
import { ShaderMaterial } from '@babylonjs/core/Materials/shaderMaterial.js';
import { RawTexture } from '@babylonjs/core/Materials/Textures/rawTexture.js';
import { Matrix, Vector2, Vector3 } from '@babylonjs/core/Maths/math.vector.js';
import { DracoDecoder } from '@babylonjs/core/Meshes/Compression/dracoDecoder.js';

import { STAGES_WGSL_BABYLON } from './stages_wgsl.js';
import { RUNTIMES, STAGES, coverageMipLevels, runtime, shaderText, structExpression, uniformValue } from '@baker/shared';

// the extension names, TECHNIQUES and the switch registry are engine-neutral: everything @baker/shared exports
// is re-exported here (index.js names what the package makes public)
export * from '@baker/shared';
export const EXT_EDGE_VISIBILITY = 'EXT_mesh_primitive_edge_visibility';

/**
 * A runtime-shaders module as given, less its // comments: Babylon's shader preprocessor does not read a directive
 * followed by a comment (`#endif // GUARD`) as that directive, which unbalances every #if after it.
 */
export function requireShader(shaders, key) {
	return shaderText(shaders, key, '@baker/babylon').replace(/\/\/[^\n]*/g, '');
}

/** Babylon's ShaderLanguage values (a material's shaderLanguage: WGSL on WebGPUEngine, GLSL on WebGL). */
export const GLSL = 0;
export const WGSL = 1;

/**
 * The WGSL twin of runtime-shaders module `key` (options.wgsl, the baker_<name>.wgsl files as text), less its //
 * comments (Babylon's preprocessor reads the WGSL too); throws a message naming the file when it is missing.
 */
export function requireWgsl(wgsl, key) {
	const text = (wgsl || {})[key];
	if (!text) {
		const file = RUNTIMES.find((r) => r.modules.key === key)?.modules.wgsl ?? `the WGSL twin of ${key}`;
		throw new Error(`@baker/babylon: options.wgsl.${key} (runtime-shaders/${file} as text) is missing: the engine draws WGSL (WebGPU)`);
	}
	return text.replace(/\/\/[^\n]*/g, '');
}

/**
 * The module of a surface part in the shading language of `material` (Babylon's PBRMaterial: WGSL on
 * WebGPUEngine): { glsl } from extension.shaders, or { wgsl } from extension.options.wgsl.
 */
export function partModule(extension, key, material) {
	return material?.shaderLanguage === WGSL ? { wgsl: requireWgsl(extension.options.wgsl, key) }
		: { glsl: requireShader(extension.shaders, key) };
}

/**
 * The runtime-shaders module `key` in the language `scene`'s engine draws: the GLSL of extension.shaders, or on
 * WebGPUEngine the WGSL twin of extension.options.wgsl.
 */
export function engineModule(extension, key, scene) {
	return scene.getEngine().isWebGPU ? requireWgsl(extension.options?.wgsl, key) : requireShader(extension.shaders, key);
}

// The header of every ShaderMaterial stage: Babylon writes the #version line (WebGL2: GLSL ES 3.00) and converts
// attribute/varying/gl_FragColor; the modules need highp samplers for 16-bit data.
export const HEADER = 'precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n';

/**
 * The uniforms of technique `name`'s descriptor for the extension object `ext` as BakerSurfacePlugin part uniforms
 * ({ name: { type, value } }), and the expression of the module's parameter struct.
 */
export function descriptorUniforms(name, ext) {
	const descriptor = runtime(name);
	const uniforms = Object.fromEntries(descriptor.uniforms.map((spec) => [spec.name, { type: spec.type, value: uniformValue(spec, ext) }]));
	return { uniforms, struct: structExpression(descriptor) };
}

// ------------------------------------------------------------------------------------------------ glTF lookups
/**
 * Every mesh primitive the loader turned into a Babylon mesh: { node, meshIndex, primitiveIndex, primitive, mesh }.
 * Uses the loader's node -> primitive mesh association (INode._primitiveBabylonMeshes, in primitive order).
 */
export function loadedPrimitives(loader) {
	const out = [];
	const json = loader.gltf;
	for (const node of json.nodes || []) {
		if (node.mesh === undefined || !node._primitiveBabylonMeshes) continue;
		const primitives = json.meshes[node.mesh].primitives;
		node._primitiveBabylonMeshes.forEach((mesh, primitiveIndex) => {
			out.push({ node, meshIndex: node.mesh, primitiveIndex, primitive: primitives[primitiveIndex], mesh });
		});
	}
	return out;
}

const COMPONENTS = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4, MAT2: 4, MAT3: 9, MAT4: 16 };
const COMPONENT_TYPES = {
	5120: [1, 'getInt8', 127], 5121: [1, 'getUint8', 255], 5122: [2, 'getInt16', 32767],
	5123: [2, 'getUint16', 65535], 5125: [4, 'getUint32', 0], 5126: [4, 'getFloat32', 0],
};

/**
 * An accessor as floats, read from its declared type and component type (not from what a technique expects, so a
 * custom attribute may change its component count). Returns { data: Float32Array, size, count } (with `integer`:
 * a Uint32Array of the raw values, for indices past float precision). Checks that the accessor fits its buffer view
 * before reading.
 */
export async function readAccessor(loader, index, { integer = false } = {}) {
	const context = `/accessors/${index}`;
	const accessor = loader.gltf.accessors?.[index];
	if (!accessor) throw new Error(`${context}: no such accessor`);
	const size = COMPONENTS[accessor.type];
	const type = COMPONENT_TYPES[accessor.componentType];
	if (!size || !type) throw new Error(`${context}: unsupported type ${accessor.type} / ${accessor.componentType}`);
	const [bytes, getter, max] = type;
	const count = accessor.count;
	const data = integer ? new Uint32Array(count * size) : new Float32Array(count * size);
	if (accessor.bufferView === undefined) {
		// an attribute or the indices of a KHR_draco_mesh_compression primitive (gltf-transform draco): Babylon's
		// loader decodes only the standard attributes, so the custom ones are decoded here from the same stream
		const decoded = await dracoAccessor(loader, index);
		if (decoded) {
			if (decoded.length !== count * size) throw new Error(`${context}: Draco decoded ${decoded.length} values, not ${count * size}`);
			data.set(decoded);
		}
		return { data, size, count };
	}
	if (accessor.sparse) throw new Error(`${context}: sparse accessors are not read by @baker/babylon`);
	const view = loader.gltf.bufferViews[accessor.bufferView];
	const buffer = await loader.loadBufferViewAsync(`/bufferViews/${accessor.bufferView}`, view);
	const stride = view.byteStride || size * bytes;
	const offset = accessor.byteOffset || 0;
	if (count > 0 && offset + (count - 1) * stride + size * bytes > buffer.byteLength) {
		throw new Error(`${context}: ${count} elements do not fit buffer view ${accessor.bufferView}`);
	}
	const dv = new DataView(buffer.buffer, buffer.byteOffset + offset, buffer.byteLength - offset);
	const scale = accessor.normalized && max && !integer ? 1 / max : 1;
	for (let i = 0; i < count; i++) {
		for (let k = 0; k < size; k++) {
			const v = dv[getter](i * stride + k * bytes, true) * scale;
			data[i * size + k] = accessor.normalized && !integer ? Math.max(v, -1) : v; // signed normalized: -128 -> -1
		}
	}
	return { data, size, count };
}

// bufferView index -> Promise of the decoded stream ({ indices, attributes: { uniqueId: values } })
const DRACO_STREAMS = new WeakMap();

/** The values (numbers, dequantized) of accessor `index` when a Draco-compressed primitive holds it, else null. */
async function dracoAccessor(loader, index) {
	for (const mesh of loader.gltf.meshes || []) {
		for (const primitive of mesh.primitives || []) {
			const ext = primitive.extensions?.KHR_draco_mesh_compression;
			if (!ext) continue;
			const name = Object.keys(primitive.attributes || {}).find((n) => primitive.attributes[n] === index);
			if (name === undefined && primitive.indices !== index) continue;
			if (name !== undefined && ext.attributes?.[name] === undefined) continue;
			let streams = DRACO_STREAMS.get(loader.gltf);
			if (!streams) DRACO_STREAMS.set(loader.gltf, (streams = new Map()));
			if (!streams.has(ext.bufferView)) {
				const view = loader.gltf.bufferViews[ext.bufferView];
				streams.set(ext.bufferView, loader.loadBufferViewAsync(`/bufferViews/${ext.bufferView}`, view)
					.then((bytes) => DracoDecoder.Default.decodeMeshToMeshDataAsync(bytes,
						Object.fromEntries(Object.entries(ext.attributes).map(([n, id]) => [n, id]))))
					.then((result) => ({ indices: result.indices,
						attributes: Object.fromEntries(result.attributes.map((a) => [a.kind, dequantized(a)])) })));
			}
			const stream = await streams.get(ext.bufferView);
			return name === undefined ? stream.indices : stream.attributes[name];
		}
	}
	return null;
}

/** A decoded Draco attribute as numbers: normalized integers as glTF reads them (c / max, at least -1). */
function dequantized({ data, normalized }) {
	if (!normalized || data instanceof Float32Array) return data;
	const max = { Int8Array: 127, Uint8Array: 255, Int16Array: 32767, Uint16Array: 65535 }[data.constructor.name];
	return max ? Float32Array.from(data, (c) => Math.max(c / max, -1)) : data;
}

/** GLSL type of an attribute of `size` components. */
export function glslType(size) {
	return size === 1 ? 'float' : `vec${size}`;
}

/** WGSL type of an attribute of `size` components. */
export function wgslType(size) {
	return size === 1 ? 'f32' : `vec${size}f`;
}

/** The first component of a value of `size` components (the scalar a technique reads). */
export function firstComponent(expression, size) {
	return size === 1 ? expression : `${expression}.x`;
}

/**
 * Put the primitive attribute `name` (glTF semantic, e.g. _THICKNESS) on `mesh` as vertex data `kind`. Returns its
 * component count, or 0 when the primitive has no such attribute.
 */
export async function setAttribute(loader, mesh, primitive, name, kind) {
	const index = primitive.attributes?.[name];
	if (index === undefined) return 0;
	const { data, size, count } = await readAccessor(loader, index);
	if (count !== mesh.getTotalVertices()) throw new Error(`${name}: ${count} values for ${mesh.getTotalVertices()} vertices`);
	setPackedVerticesData(mesh, kind, data, size);
	return size;
}

// baker's vertex data of each mesh, interleaved in one Buffer: WebGPU guarantees only 8 vertex buffers per pipeline
// (maxVertexBuffers), and Babylon's WebGPUEngine binds one per Buffer, merging the attributes that follow each other
// in one; the spot with every surface bake has 6 baker attributes beside position, normal and uv
const PACKED = new WeakMap(); // mesh -> { parts: Map(kind -> { data, size }), buffer }

function setPackedVerticesData(mesh, kind, data, size) {
	let packed = PACKED.get(mesh);
	if (!packed) PACKED.set(mesh, packed = { parts: new Map(), buffer: null });
	packed.parts.set(kind, { data, size });
	const count = mesh.getTotalVertices();
	let stride = 0;
	for (const part of packed.parts.values()) stride += part.size;
	const interleaved = new Float32Array(count * stride);
	let offset = 0;
	for (const part of packed.parts.values()) {
		for (let i = 0; i < count; i++) {
			for (let k = 0; k < part.size; k++) interleaved[i * stride + offset + k] = part.data[i * part.size + k];
		}
		offset += part.size;
	}
	const buffer = new Buffer(mesh.getEngine(), interleaved, false, stride);
	offset = 0;
	for (const [name, part] of packed.parts) {
		mesh.setVerticesBuffer(buffer.createVertexBuffer(name, offset, part.size));
		offset += part.size;
	}
	packed.buffer?.dispose();
	packed.buffer = buffer;
}

/** A glTF texture (textureInfo or index) as a Babylon texture holding data: linear, clamped unless `repeat`. */
export async function dataTexture(loader, info, { repeat = false, mipmaps = false } = {}) {
	const index = typeof info === 'number' ? info : info?.index;
	if (index === undefined) return null;
	// nonColorData: no sRGB texture format (it would decode the values); LUTs, ramps, distance fields are data, and
	// @baker/three samples the fur textures raw too
	const texture = await loader.loadTextureInfoAsync(`/textures/${index}`, { index, nonColorData: true }, () => {});
	texture.gammaSpace = false;
	texture.wrapU = texture.wrapV = repeat ? Constants.TEXTURE_WRAP_ADDRESSMODE : Constants.TEXTURE_CLAMP_ADDRESSMODE;
	texture.updateSamplingMode(mipmaps ? Constants.TEXTURE_TRILINEAR_SAMPLINGMODE : Constants.TEXTURE_LINEAR_LINEAR);
	return texture;
}

/**
 * Levels 1.. of `levels` ([{ data, width, height }], finest first) uploaded over the mip levels of `texture`, a
 * RawTexture created with generated mips (its mip storage). On WebGPUEngine the generated mips are commands of the
 * engine's upload encoder, submitted at the end of the frame, after the queue's writes of these levels: they are
 * submitted first (flushFramebuffer), so the levels kept are the given ones, as on WebGL.
 */
export function uploadMipLevels(texture, levels) {
	const engine = texture.getScene().getEngine();
	if (engine.isWebGPU) engine.flushFramebuffer();
	const internal = texture.getInternalTexture();
	levels.forEach(({ data, width, height }, lod) => {
		if (lod > 0) engine.updateTextureData(internal, data, 0, 0, width, height, 0, lod, false);
	});
}

const WRAPS = { 10497: Constants.TEXTURE_WRAP_ADDRESSMODE, 33071: Constants.TEXTURE_CLAMP_ADDRESSMODE,
	33648: Constants.TEXTURE_MIRROR_ADDRESSMODE };

/** The stored bytes of texture `texture`'s image (a buffer view, a data URI or a file beside the glTF). */
async function imageBytes(loader, texture) {
	const index = loader.gltf.textures?.[texture]?.source;
	const image = loader.gltf.images?.[index];
	if (!image) throw new Error(`texture ${texture} has no image`);
	if (image.bufferView !== undefined) {
		const view = loader.gltf.bufferViews[image.bufferView];
		return loader.loadBufferViewAsync(`/bufferViews/${image.bufferView}`, view);
	}
	return loader.loadUriAsync(`/images/${index}`, image, image.uri);
}

/**
 * The coverage-preserving mip chain of a `coverageMips` entry (Castaño 2010; @baker/shared coverage_mips.js) as a
 * RawTexture holding the chain's levels, sampled trilinear with the glTF texture's wrap modes; raw data like
 * dataTexture (no sRGB decode). WebGL's raw textures take one level: the texture is created with its full mip storage
 * (Babylon allocates it by generating mips from level 0) and every further level is then uploaded over it from the
 * chain (engine.updateTextureData at that lod), so what is sampled is the chain, not generated mips. Null when the
 * chain cannot be read: the caller keeps the PNG.
 */
export async function coverageMipsTexture(loader, entry) {
	try {
		const accessor = loader.gltf.accessors?.[entry.accessor];
		if (!accessor || accessor.componentType !== 5121 || accessor.type !== 'SCALAR' || accessor.sparse || accessor.bufferView === undefined) {
			throw new Error(`accessor ${entry.accessor} is not a plain UNSIGNED_BYTE SCALAR accessor`);
		}
		const view = loader.gltf.bufferViews[accessor.bufferView];
		const buffer = await loader.loadBufferViewAsync(`/bufferViews/${accessor.bufferView}`, view);
		const offset = accessor.byteOffset || 0;
		if (offset + accessor.count > buffer.byteLength) throw new Error(`accessor ${entry.accessor} overruns its buffer view`);
		const { width, height, levels } = await coverageMipLevels(entry, buffer.subarray(offset, offset + accessor.count),
			() => imageBytes(loader, entry.texture));
		const scene = loader.babylonScene;
		const texture = new RawTexture(levels[0].data, width, height, Constants.TEXTUREFORMAT_RGBA, scene, true, false,
			Constants.TEXTURE_TRILINEAR_SAMPLINGMODE, Constants.TEXTURETYPE_UNSIGNED_BYTE);
		uploadMipLevels(texture, levels);
		texture.name = `coverage mips of texture ${entry.texture}`;
		texture.gammaSpace = false;
		const sampler = loader.gltf.samplers?.[loader.gltf.textures?.[entry.texture]?.sampler] || {};
		texture.wrapU = WRAPS[sampler.wrapS ?? 10497] ?? Constants.TEXTURE_WRAP_ADDRESSMODE;
		texture.wrapV = WRAPS[sampler.wrapT ?? 10497] ?? Constants.TEXTURE_WRAP_ADDRESSMODE;
		return texture;
	} catch (e) {
		console.warn(`@baker/babylon: coverage mips of texture ${entry.texture} unreadable, using its PNG: ${e.message || e}`);
		return null;
	}
}

// ------------------------------------------------------------------------------------------------ ShaderMaterials
export const MAX_LIGHTS = 4;
// glTF's front faces wind counter-clockwise; the meshes built here keep the file's indices
export const GLTF_FRONT = Constants.MATERIAL_CounterClockWiseSideOrientation;
const LIGHT_UNIFORMS = ['u_lightCount', 'u_lightDirection', 'u_lightColor', 'u_ambientLight'];

/**
 * A ShaderMaterial with the baker module prepended to the stages that use it, the matrices, the eye, the viewport
 * and the scene's directional lights (u_lightDirection[i] towards the light, world space; u_lightColor[i] = colour x
 * intensity; u_ambientLight = scene.ambientColor) bound at every draw.
 */
export function bakerShaderMaterial(name, scene, { vertex, fragment, attributes, uniforms = [], samplers = [], alpha = false }) {
	const material = new ShaderMaterial(name, scene, { vertexSource: HEADER + vertex, fragmentSource: HEADER + fragment }, {
		attributes, samplers, needAlphaBlending: alpha,
		uniforms: ['world', 'worldView', 'worldViewProjection', 'view', 'projection', 'viewProjection', 'u_eye', 'u_viewport',
			...LIGHT_UNIFORMS, ...uniforms],
	});
	material.onBindObservable.add(() => {
		const engine = scene.getEngine();
		const effect = material.getEffect();
		if (!effect) return;
		const camera = scene.activeCamera;
		if (camera) effect.setVector3('u_eye', camera.globalPosition);
		effect.setFloat2('u_viewport', engine.getRenderWidth(), engine.getRenderHeight());
		const lights = sceneLights(scene);
		effect.setInt('u_lightCount', lights.count);
		effect.setArray3('u_lightDirection', lights.directions);
		effect.setArray3('u_lightColor', lights.colors);
		effect.setColor3('u_ambientLight', scene.ambientColor);
	});
	return material;
}

// The WGSL preludes (Babylon's WGSL dialect): WGSL has no inverse(), so the eye in object space is a uniform set per
// mesh at bind; the lights are one uniform per light (no uniform arrays of vec3 in Babylon's leftover block).
const VERTEX_PRELUDE_WGSL = `
uniform world: mat4x4f;
uniform viewProjection: mat4x4f;
uniform projection: mat4x4f;
uniform u_eye: vec3f;
uniform u_objectEye: vec3f;
uniform u_viewport: vec2f;
fn baker_clip(p: vec3f) -> vec4f { return uniforms.viewProjection * uniforms.world * vec4f(p, 1.0); }
fn baker_object_eye() -> vec3f { return uniforms.u_objectEye; }
fn baker_world3() -> mat3x3f { return mat3x3f(uniforms.world[0].xyz, uniforms.world[1].xyz, uniforms.world[2].xyz); }
fn baker_light_normal(n: vec3f) -> vec3f { return normalize(baker_world3() * n); }
fn baker_light_vector(d: vec3f) -> vec3f { return baker_world3() * d; }
fn baker_to_eye(p: vec3f) -> vec3f { return uniforms.u_eye - (uniforms.world * vec4f(p, 1.0)).xyz; }
fn baker_projection_y() -> f32 { return uniforms.projection[1][1]; }
`;
const LIGHTS_PRELUDE_WGSL = `
uniform u_lightCount: i32;
${Array.from({ length: MAX_LIGHTS }, (_, i) => `uniform u_lightDirection${i}: vec3f;\nuniform u_lightColor${i}: vec3f;`).join('\n')}
uniform u_ambientLight: vec3f;
const BAKER_MAX_LIGHTS: i32 = ${MAX_LIGHTS};
fn baker_light_count() -> i32 { return uniforms.u_lightCount; }
fn baker_light_direction(i: i32) -> vec3f {
	let all = array<vec3f, ${MAX_LIGHTS}>(${Array.from({ length: MAX_LIGHTS }, (_, i) => `uniforms.u_lightDirection${i}`).join(', ')});
	return all[i];
}
fn baker_light_color(i: i32) -> vec3f {
	let all = array<vec3f, ${MAX_LIGHTS}>(${Array.from({ length: MAX_LIGHTS }, (_, i) => `uniforms.u_lightColor${i}`).join(', ')});
	return all[i];
}
fn baker_ambient_light() -> vec3f { return uniforms.u_ambientLight; }
`;
// vertex data the WGSL preludes declare when a material lists them (the stages declare their own custom ones)
const PRELUDE_ATTRIBUTES_WGSL = { position: 'vec3f', normal: 'vec3f', uv: 'vec2f' };

/**
 * bakerShaderMaterial's WGSL twin (ShaderLanguage.WGSL, for WebGPUEngine): the same bindings, the eye also in the
 * mesh's object space (u_objectEye), the lights one uniform each, only for `lit` stages.
 */
function bakerShaderMaterialWgsl(name, scene, { vertex, fragment, attributes, uniforms = [], samplers = [], alpha = false, lit = false }) {
	const lightUniforms = lit ? ['u_lightCount', 'u_ambientLight', ...Array.from({ length: MAX_LIGHTS }, (_, i) => [`u_lightDirection${i}`, `u_lightColor${i}`]).flat()] : [];
	const material = new ShaderMaterial(name, scene, { vertexSource: vertex, fragmentSource: fragment }, {
		attributes, samplers, needAlphaBlending: alpha, shaderLanguage: WGSL,
		uniforms: ['world', 'projection', 'viewProjection', 'u_eye', 'u_objectEye', 'u_viewport', ...lightUniforms, ...uniforms],
	});
	const inverse = new Matrix();
	material.onBindObservable.add((mesh) => {
		const engine = scene.getEngine();
		const effect = material.getEffect();
		if (!effect) return;
		const camera = scene.activeCamera;
		if (camera) {
			effect.setVector3('u_eye', camera.globalPosition);
			mesh.getWorldMatrix().invertToRef(inverse);
			effect.setVector3('u_objectEye', Vector3.TransformCoordinates(camera.globalPosition, inverse));
		}
		effect.setFloat2('u_viewport', engine.getRenderWidth(), engine.getRenderHeight());
		if (!lit) return;
		const lights = sceneLights(scene);
		effect.setInt('u_lightCount', lights.count);
		for (let i = 0; i < MAX_LIGHTS; i++) {
			effect.setFloat3(`u_lightDirection${i}`, ...lights.directions.slice(3 * i, 3 * i + 3));
			effect.setFloat3(`u_lightColor${i}`, ...lights.colors.slice(3 * i, 3 * i + 3));
		}
		effect.setColor3('u_ambientLight', scene.ambientColor);
	});
	return material;
}

/** The enabled directional lights of a scene, at most MAX_LIGHTS, towards the light, world space. */
export function sceneLights(scene) {
	const directions = new Array(MAX_LIGHTS * 3).fill(0);
	const colors = new Array(MAX_LIGHTS * 3).fill(0);
	let count = 0;
	for (const light of scene.lights) {
		if (count >= MAX_LIGHTS || !light.isEnabled() || light.getClassName() !== 'DirectionalLight') continue;
		const d = light.direction.normalizeToNew();
		directions.splice(count * 3, 3, -d.x, -d.y, -d.z);
		colors.splice(count * 3, 3, light.diffuse.r * light.intensity, light.diffuse.g * light.intensity, light.diffuse.b * light.intensity);
		count += 1;
	}
	return { count, directions, colors };
}

// What the shared stages (runtime-shaders/hosts/web) ask of a host, in Babylon's terms: object space in, the lights'
// space is world space (the u_light* uniforms bakerShaderMaterial binds).
const VERTEX_PRELUDE = `
attribute vec3 position;
attribute vec3 normal;
attribute vec2 uv;
uniform mat4 world;
uniform mat4 viewProjection;
uniform mat4 projection;
uniform vec3 u_eye;
vec4 baker_clip(vec3 p) { return viewProjection * world * vec4(p, 1.0); }
vec3 baker_object_eye() { return (inverse(world) * vec4(u_eye, 1.0)).xyz; }
vec3 baker_light_normal(vec3 n) { return normalize(mat3(world) * n); }
vec3 baker_light_vector(vec3 d) { return mat3(world) * d; }
vec3 baker_to_eye(vec3 p) { return u_eye - (world * vec4(p, 1.0)).xyz; }
float baker_projection_y() { return projection[1][1]; }
`;
const LIGHTS_PRELUDE = `
uniform int u_lightCount;
uniform vec3 u_lightDirection[${MAX_LIGHTS}];
uniform vec3 u_lightColor[${MAX_LIGHTS}];
uniform vec3 u_ambientLight;
const int BAKER_MAX_LIGHTS = ${MAX_LIGHTS};
int baker_light_count() { return u_lightCount; }
vec3 baker_light_direction(int i) { return u_lightDirection[i]; }
vec3 baker_light_color(int i) { return u_lightColor[i]; }
vec3 baker_ambient_light() { return u_ambientLight; }
`;

/**
 * A bakerShaderMaterial drawing the shared stages `vertex` and `fragment` (names of runtime-shaders/hosts/web files)
 * with the runtime module `glsl`; `lit`: the fragment reads the scene's directional lights.
 */
export function stageMaterial(name, scene, { glsl, vertex, fragment, lit = false, ...rest }) {
	if (scene.getEngine().isWebGPU) {
		// `glsl` is then the WGSL twin (engineModule); the stages are their WGSL twins (stages_wgsl.js)
		const declared = (stage) => Object.entries(PRELUDE_ATTRIBUTES_WGSL).filter(([kind]) => rest.attributes?.includes(kind)
			&& !new RegExp(`attribute\\s+${kind}\\s*:`).test(stage)).map(([kind, type]) => `attribute ${kind}: ${type};`).join('\n');
		const vertexStage = STAGES_WGSL_BABYLON[vertex];
		return bakerShaderMaterialWgsl(name, scene, {
			...rest, lit,
			vertex: declared(vertexStage) + VERTEX_PRELUDE_WGSL + glsl + vertexStage,
			fragment: (lit ? LIGHTS_PRELUDE_WGSL + glsl + STAGES_WGSL_BABYLON.lights : glsl) + STAGES_WGSL_BABYLON[fragment],
		});
	}
	return bakerShaderMaterial(name, scene, {
		...rest,
		vertex: VERTEX_PRELUDE + glsl + STAGES[vertex],
		fragment: lit ? LIGHTS_PRELUDE + glsl + STAGES.lights + STAGES[fragment] : glsl + STAGES[fragment],
	});
}

export { Vector2, Vector3 };
