// Shared by the plugins of @baker/three: the extension names, the techniques (switches) and the per-asset registry
// of their on/off handlers, and the helpers several plugins use (scene lookups, textures, lit ShaderMaterials, the
// viewport uniform). Not an entry point: import from index.js.
import * as THREE from 'three';

import { STAGES, coverageMipLevels, runtime, shaderText, structExpression, uniformValue } from '@baker/shared';

// the extension names, TECHNIQUES and the switch registry are engine-neutral: everything @baker/shared exports
// is re-exported here (index.js names what the package makes public)
export * from '@baker/shared';

export function requireShader(shaders, key) {
	return shaderText(shaders, key, '@baker/three');
}

export function materialsOf(object) {
	return Array.isArray(object.material) ? object.material : [object.material];
}

/** [object, material, materialIndex] for every mesh material of the scene that GLTFLoader built from json.materials. */
export function sceneMaterials(parser, scene) {
	const out = [];
	scene.traverse((object) => {
		if (!object.isMesh) return;
		for (const material of materialsOf(object)) {
			const index = parser.associations.get(material)?.materials;
			if (index !== undefined) out.push([object, material, index]);
		}
	});
	return out;
}

/** The primitive (json) a mesh object was built from, or null. */
export function primitiveOf(parser, object) {
	const a = parser.associations.get(object);
	if (!a || a.meshes === undefined || a.primitives === undefined) return null;
	return parser.json.meshes[a.meshes].primitives[a.primitives];
}

export function textureOf(parser, info) {
	const index = typeof info === 'number' ? info : info?.index;
	return index === undefined ? Promise.resolve(null) : parser.getDependency('texture', index);
}

export function dataTexture(texture, { repeat = false, linear = true } = {}) {
	texture.colorSpace = THREE.NoColorSpace; // LUTs, ramps, TAM and distance fields are data, not sRGB colour
	texture.wrapS = texture.wrapT = repeat ? THREE.RepeatWrapping : THREE.ClampToEdgeWrapping;
	texture.magFilter = linear ? THREE.LinearFilter : THREE.NearestFilter;
	texture.minFilter = THREE.LinearFilter;
	texture.generateMipmaps = false;
	texture.needsUpdate = true;
	return texture;
}

const WRAPS = { 10497: THREE.RepeatWrapping, 33071: THREE.ClampToEdgeWrapping, 33648: THREE.MirroredRepeatWrapping };

/** The stored bytes of texture `texture`'s image (a buffer view, a data URI or a file beside the glTF). */
async function imageBytes(parser, texture) {
	const image = parser.json.images?.[parser.json.textures?.[texture]?.source];
	if (!image) throw new Error(`texture ${texture} has no image`);
	if (image.bufferView !== undefined) return new Uint8Array(await parser.getDependency('bufferView', image.bufferView));
	const url = THREE.LoaderUtils.resolveURL(image.uri, parser.options.path);
	return new Uint8Array(await (await fetch(url)).arrayBuffer());
}

/**
 * The coverage-preserving mip chain of a `coverageMips` entry (Castaño 2010; @baker/shared coverage_mips.js) as a
 * DataTexture whose mipmaps are the chain's levels, uploaded as given (generateMipmaps off), sampled trilinear with
 * the glTF texture's wrap modes; raw data like the PNG path (no sRGB decode). Null when the chain cannot be read:
 * the caller keeps the PNG.
 */
export async function coverageMipsTexture(parser, entry) {
	try {
		const accessor = await parser.getDependency('accessor', entry.accessor);
		const array = accessor.array;
		const bytes = new Uint8Array(array.buffer, array.byteOffset, array.byteLength);
		const { width, height, levels } = await coverageMipLevels(entry, bytes, () => imageBytes(parser, entry.texture));
		const texture = new THREE.DataTexture(levels[0].data, width, height, THREE.RGBAFormat, THREE.UnsignedByteType);
		texture.mipmaps = levels.map(({ data, width: w, height: h }) => ({ data, width: w, height: h }));
		texture.generateMipmaps = false;
		texture.flipY = false; // KTXorientation rd: row 0 is the top, at v = 0 as in glTF
		texture.colorSpace = THREE.NoColorSpace;
		texture.magFilter = THREE.LinearFilter;
		texture.minFilter = THREE.LinearMipmapLinearFilter;
		const sampler = parser.json.samplers?.[parser.json.textures?.[entry.texture]?.sampler] || {};
		texture.wrapS = WRAPS[sampler.wrapS ?? 10497] ?? THREE.RepeatWrapping;
		texture.wrapT = WRAPS[sampler.wrapT ?? 10497] ?? THREE.RepeatWrapping;
		texture.name = `coverage mips of texture ${entry.texture}`;
		texture.needsUpdate = true;
		return texture;
	} catch (e) {
		console.warn(`@baker/three: coverage mips of texture ${entry.texture} unreadable, using its PNG: ${e.message || e}`);
		return null;
	}
}

const VALUES = { vec2: (v) => new THREE.Vector2(...v), vec3: (v) => new THREE.Vector3(...v), vec4: (v) => new THREE.Vector4(...v) };

/**
 * The uniforms of technique `name`'s descriptor for the extension object `ext` as three.js uniforms, their GLSL types
 * (for the declarations BakerSurface writes) and the expression of the module's parameter struct.
 */
export function descriptorUniforms(name, ext) {
	const descriptor = runtime(name);
	const uniforms = {};
	const types = {};
	for (const spec of descriptor.uniforms) {
		const value = uniformValue(spec, ext);
		uniforms[spec.name] = { value: VALUES[spec.type]?.(value) ?? value };
		types[spec.name] = spec.type;
	}
	return { uniforms, types, struct: structExpression(descriptor) };
}

/** A ShaderMaterial lit by the scene's lights (view-space directionalLights[] etc. through lights_pars_begin). */
export function litShaderMaterial(parameters) {
	const uniforms = THREE.UniformsUtils.merge([THREE.UniformsLib.lights]);
	Object.assign(uniforms, parameters.uniforms); // not cloned: textures stay shared
	return new THREE.ShaderMaterial({ ...parameters, uniforms, lights: true });
}

// What the shared stages (runtime-shaders/hosts/web) ask of a host, in three.js's terms: object space in, the lights'
// space is view space (directionalLights[] of lights_pars_begin).
const VERTEX_PRELUDE = `
vec4 baker_clip(vec3 p) { return projectionMatrix * modelViewMatrix * vec4(p, 1.0); }
vec3 baker_object_eye() { return (inverse(modelMatrix) * vec4(cameraPosition, 1.0)).xyz; }
vec3 baker_light_normal(vec3 n) { return normalize(normalMatrix * n); }
vec3 baker_light_vector(vec3 d) { return (modelViewMatrix * vec4(d, 0.0)).xyz; }
vec3 baker_to_eye(vec3 p) { return -(modelViewMatrix * vec4(p, 1.0)).xyz; }
float baker_projection_y() { return projectionMatrix[1][1]; }
`;
const LIGHTS_PRELUDE = `#include <common>
#include <lights_pars_begin>
#if NUM_DIR_LIGHTS > 0
const int BAKER_MAX_LIGHTS = NUM_DIR_LIGHTS;
vec3 baker_light_direction(int i) { return directionalLights[i].direction; }
vec3 baker_light_color(int i) { return directionalLights[i].color; }
#else
const int BAKER_MAX_LIGHTS = 0;
vec3 baker_light_direction(int i) { return vec3(0.0); }
vec3 baker_light_color(int i) { return vec3(0.0); }
#endif
int baker_light_count() { return BAKER_MAX_LIGHTS; }
vec3 baker_ambient_light() { return ambientLightColor; }
`;

/**
 * A ShaderMaterial drawing the shared stages `vertex` and `fragment` (names of runtime-shaders/hosts/web files) with
 * the runtime module `glsl`; `lit`: the fragment reads the scene's lights (a litShaderMaterial).
 */
export function stageMaterial({ glsl, vertex, fragment, lit = false, ...parameters }) {
	const vertexShader = VERTEX_PRELUDE + glsl + STAGES[vertex];
	const fragmentShader = lit ? LIGHTS_PRELUDE + glsl + STAGES.lights + STAGES[fragment] : glsl + STAGES[fragment];
	return (lit ? litShaderMaterial : (p) => new THREE.ShaderMaterial(p))({ ...parameters, vertexShader, fragmentShader });
}

// Diffuse light from the directional lights of the scene, view space: sum of color * max(N.L, 0).
export const DIRECTIONAL_DIFFUSE = `
vec3 baker_directional_diffuse(vec3 N) {
	vec3 sum = vec3(0.0);
#if NUM_DIR_LIGHTS > 0
	for (int i = 0; i < NUM_DIR_LIGHTS; i++) sum += directionalLights[i].color * max(dot(N, directionalLights[i].direction), 0.0);
#endif
	return sum;
}
vec3 baker_key_light(vec3 fallback) {
#if NUM_DIR_LIGHTS > 0
	return directionalLights[0].direction;
#else
	return fallback;
#endif
}`;

const viewportSize = new THREE.Vector2();
/** Keep `u_viewport` of a material in drawing-buffer pixels (fins, outlines, hair need pixel widths). */
export function trackViewport(object, uniforms) {
	const previous = object.onBeforeRender;
	object.onBeforeRender = function (renderer, ...rest) {
		renderer.getDrawingBufferSize(viewportSize);
		uniforms.u_viewport.value.copy(viewportSize);
		previous.call(this, renderer, ...rest);
	};
}

/** Keep `uniform` at `value` / the length scale of the object's world matrix (cube root of |det|): a length the
 * stage adds in the object's space while it means world units (the outline's width, in pixels at the object's
 * depth), under a node that scales (KHR_mesh_quantization's dequantization, after gltf-transform quantize). */
export function trackWorldScale(object, uniform, value) {
	const previous = object.onBeforeRender;
	object.onBeforeRender = function (...args) {
		const scale = Math.cbrt(Math.abs(this.matrixWorld.determinant())) || 1;
		uniform.value = value / scale;
		previous.call(this, ...args);
	};
}

export function geometryHas(object, attribute) {
	return Boolean(attribute && object.geometry.getAttribute(attribute.toLowerCase()));
}
