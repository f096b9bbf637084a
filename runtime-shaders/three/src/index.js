// three.js GLTFLoader plugins for baker's BAKER_* extensions.
//
//   import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
//   import { registerBakerPlugins } from '@baker/three';
//   import translucency from '@baker/runtime-shaders/baker_translucency.glsl';  // text (e.g. Vite '?raw')
//   const loader = registerBakerPlugins(new GLTFLoader(), { shaders: { translucency, skin, edges, ... } });
//   const gltf = await loader.loadAsync('asset.glb');
//   gltf.userData.baker.setEnabled('toon', false);   // one switch per technique found (gltf.userData.baker.techniques)
//
// The GLSL comes from runtime-shaders/ as text: the plugins inject the very modules the reference renders use, they
// do not carry a copy. One plugin per extension. Surface techniques (translucency, pre-integrated skin, toon ramp,
// hatching, curvature view) augment the material GLTFLoader made (MeshStandardMaterial / MeshPhysicalMaterial)
// through onBeforeCompile, so PBR, lights and tone mapping stay; each is gated by a uniform, so a switch costs no
// recompile. Geometry techniques (fins, shell outline, wireframe, fur shells and fins, hair ribbons, MSDF text) add
// or replace meshes with ShaderMaterials that include the matching module, lit by the scene's lights (lights: true).
import * as THREE from 'three';

export const BAKER_THICKNESS = 'BAKER_thickness';
export const BAKER_CURVATURE = 'BAKER_curvature';
export const BAKER_SKIN_LUT = 'BAKER_skin_lut';
export const BAKER_EDGES = 'BAKER_edges';
export const BAKER_TONAL_ART_MAP = 'BAKER_tonal_art_map';
export const BAKER_TOON_RAMP = 'BAKER_toon_ramp';
export const BAKER_GLYPH_ATLAS = 'BAKER_glyph_atlas';
export const BAKER_TEXT = 'BAKER_text';
export const BAKER_HAIR = 'BAKER_hair';
export const BAKER_FUR = 'BAKER_fur';

/** Techniques (switch names) and the extension each comes from. Techniques off by default are debug views. */
export const TECHNIQUES = {
	translucency: { extension: BAKER_THICKNESS, label: 'translucency' },
	skin: { extension: BAKER_SKIN_LUT, label: 'pre-integrated skin' },
	toon: { extension: BAKER_TOON_RAMP, label: 'toon ramp' },
	tam: { extension: BAKER_TONAL_ART_MAP, label: 'hatching (TAM)' },
	fins: { extension: BAKER_EDGES, label: 'edge fins' },
	outline: { extension: BAKER_EDGES, label: 'shell outline' },
	wireframe: { extension: BAKER_EDGES, label: 'wireframe', defaultOff: true },
	fur: { extension: BAKER_FUR, label: 'fur shells + fins' },
	hair: { extension: BAKER_HAIR, label: 'hair ribbons' },
	text: { extension: BAKER_TEXT, label: 'MSDF text' },
	curvature: { extension: BAKER_CURVATURE, label: 'curvature view', defaultOff: true },
};

const GLSL_NAMES = {
	translucency: 'baker_translucency.glsl', skin: 'baker_skin.glsl', toon: 'baker_toon.glsl',
	hatching: 'baker_hatching.glsl', edges: 'baker_edges.glsl', fur: 'baker_fur.glsl', hair: 'baker_hair.glsl',
	text: 'baker_text.glsl',
};

// ------------------------------------------------------------------------------------------------ shared state
// One registry per loaded asset (parser): every plugin adds its technique's on/off handler to it; afterRoot of the
// last plugin publishes it as gltf.userData.baker.
class BakerControls {
	constructor() {
		this.found = [];           // names, in discovery order
		this.handlers = new Map(); // name -> [fn(on)]
		this.enabled = new Map();
	}
	add(name, handler) {
		if (!this.handlers.has(name)) {
			this.handlers.set(name, []);
			this.found.push(name);
			this.enabled.set(name, !TECHNIQUES[name]?.defaultOff);
		}
		this.handlers.get(name).push(handler);
		handler(this.enabled.get(name));
	}
	/** The techniques found, in the order of TECHNIQUES (plugins finish in any order). */
	get techniques() {
		const order = Object.keys(TECHNIQUES);
		return [...this.found].sort((a, b) => order.indexOf(a) - order.indexOf(b));
	}
	has(name) { return this.handlers.has(name); }
	isEnabled(name) { return Boolean(this.enabled.get(name)); }
	setEnabled(name, on) {
		if (!this.handlers.has(name)) return;
		this.enabled.set(name, Boolean(on));
		for (const fn of this.handlers.get(name)) fn(Boolean(on));
	}
}

const controlsOf = new WeakMap();
function controls(parser) {
	if (!controlsOf.has(parser)) controlsOf.set(parser, new BakerControls());
	return controlsOf.get(parser);
}

function requireShader(shaders, key) {
	const glsl = shaders[key];
	if (!glsl) throw new Error(`@baker/three: options.shaders.${key} (runtime-shaders/${GLSL_NAMES[key]} as text) is missing`);
	return glsl;
}

function materialsOf(object) {
	return Array.isArray(object.material) ? object.material : [object.material];
}

/** [object, material, materialIndex] for every mesh material of the scene that GLTFLoader built from json.materials. */
function sceneMaterials(parser, scene) {
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
function primitiveOf(parser, object) {
	const a = parser.associations.get(object);
	if (!a || a.meshes === undefined || a.primitives === undefined) return null;
	return parser.json.meshes[a.meshes].primitives[a.primitives];
}

function textureOf(parser, info) {
	const index = typeof info === 'number' ? info : info?.index;
	return index === undefined ? Promise.resolve(null) : parser.getDependency('texture', index);
}

function dataTexture(texture, { repeat = false, linear = true } = {}) {
	texture.colorSpace = THREE.NoColorSpace; // LUTs, ramps, TAM and distance fields are data, not sRGB colour
	texture.wrapS = texture.wrapT = repeat ? THREE.RepeatWrapping : THREE.ClampToEdgeWrapping;
	texture.magFilter = linear ? THREE.LinearFilter : THREE.NearestFilter;
	texture.minFilter = THREE.LinearFilter;
	texture.generateMipmaps = false;
	texture.needsUpdate = true;
	return texture;
}

/** A ShaderMaterial lit by the scene's lights (view-space directionalLights[] etc. through lights_pars_begin). */
function litShaderMaterial(parameters) {
	const uniforms = THREE.UniformsUtils.merge([THREE.UniformsLib.lights]);
	Object.assign(uniforms, parameters.uniforms); // not cloned: textures stay shared
	return new THREE.ShaderMaterial({ ...parameters, uniforms, lights: true });
}

// Diffuse light from the directional lights of the scene, view space: sum of color * max(N.L, 0).
const DIRECTIONAL_DIFFUSE = `
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
function trackViewport(object, uniforms) {
	const previous = object.onBeforeRender;
	object.onBeforeRender = function (renderer, ...rest) {
		renderer.getDrawingBufferSize(viewportSize);
		uniforms.u_viewport.value.copy(viewportSize);
		previous.call(this, renderer, ...rest);
	};
}

// ------------------------------------------------------------------------------------------------ surface
// The surface techniques of one material, composed in one onBeforeCompile: per directional light the Lambert term
// max(N.L, 0) is replaced by f (vec3): skin LUT (Penner) and/or toon ramp of it; translucency is added; hatching
// multiplies the outgoing light by the TAM brightness; the curvature view replaces it.
class BakerSurface {
	constructor(material, shaders) {
		this.material = material;
		this.shaders = shaders;
		this.parts = {};       // technique -> { glsl, uniforms, vertex, fragment }
		this.uniforms = {};
		const previous = material.onBeforeCompile;
		material.onBeforeCompile = (shader, renderer) => {
			if (previous) previous(shader, renderer);
			this.inject(shader);
		};
		material.customProgramCacheKey = () => `baker-surface-${Object.keys(this.parts).sort().join('-')}-${this.attributes().join('-')}`;
	}

	static of(material, shaders) {
		material.userData.bakerSurface ??= new BakerSurface(material, shaders);
		return material.userData.bakerSurface;
	}

	add(name, part) {
		this.parts[name] = part;
		Object.assign(this.uniforms, part.uniforms);
		this.uniforms[`u_baker_${name}_on`] = { value: 1 };
		this.material.needsUpdate = true;
	}

	setEnabled(name, on) {
		const u = this.uniforms[`u_baker_${name}_on`];
		if (u) u.value = on ? 1 : 0;
	}

	attributes() {
		const names = new Map();
		for (const p of Object.values(this.parts)) for (const [name, type] of p.attributes || []) names.set(name, type);
		return [...names.entries()].sort((a, b) => (a[0] < b[0] ? -1 : 1));
	}

	inject(shader) {
		const p = this.parts;
		Object.assign(shader.uniforms, this.uniforms);
		const attributes = this.attributes();
		const modules = [...new Set(Object.values(p).map((x) => x.glsl).filter(Boolean))].join('\n');
		const declarations = Object.keys(this.uniforms).map((name) => {
			const part = Object.values(p).find((x) => x.types && x.types[name]);
			return `uniform ${part ? part.types[name] : 'float'} ${name};`;
		}).join('\n');
		const varyings = attributes.map(([name, type]) => `varying ${type} vBaker${name};`).join('\n');
		shader.vertexShader = shader.vertexShader
			.replace('#include <common>', `#include <common>\n${attributes.map(([n, t]) => `attribute ${t} ${n};`).join('\n')}
${varyings}\nvarying vec2 vBakerUv;`)
			.replace('#include <begin_vertex>', `#include <begin_vertex>\n${attributes.map(([n]) => `vBaker${n} = ${n};`).join('\n')}
vBakerUv = uv;`);

		const diffuse = [];
		if (p.skin) diffuse.push(`if (u_baker_skin_on > 0.5) {
			f = baker_skin_diffuse(u_bakerSkin, u_bakerSkinLut, normal, normal, L, ${p.skin.curvature});
		}`);
		if (p.toon) diffuse.push(`if (u_baker_toon_on > 0.5) {
			// the ramp indexed by the lit shade so far (N.L, or the skin LUT's luminance mapped back to -1..1)
			float nl = ${p.skin ? 'u_baker_skin_on > 0.5 ? 2.0 * dot(f, vec3(0.2126, 0.7152, 0.0722)) - 1.0 : dotNL' : 'dotNL'};
			f = vec3(u_bakerToonXtoon == 0 ? baker_toon_ramp(u_bakerToonRamp, nl)
				: baker_xtoon(u_bakerToonRamp, nl, u_bakerToonXtoon == 1
					? baker_xtoon_detail_depth(-vViewPosition.z, u_bakerToonDepthRange.x, u_bakerToonDepthRange.y)
					: baker_xtoon_detail_orientation(normal, normalize(vViewPosition) * -1.0, u_bakerToonOrientationPower)));
		}`);
		let lights = '';
		if (diffuse.length || p.translucency) {
			lights = `
#if NUM_DIR_LIGHTS > 0
	for (int i = 0; i < NUM_DIR_LIGHTS; i++) {
		vec3 L = directionalLights[i].direction;  // view space, towards the light
		float dotNL = dot(normal, L);
		vec3 f = vec3(saturate(dotNL));
		${diffuse.join('\n\t\t')}
		reflectedLight.directDiffuse += directionalLights[i].color * BRDF_Lambert(diffuseColor.rgb) * (f - vec3(saturate(dotNL)));
		${p.translucency ? `reflectedLight.directDiffuse += u_baker_translucency_on * diffuseColor.rgb * directionalLights[i].color *
			baker_translucency(u_bakerThickness, normal, normalize(vViewPosition), L, vBaker${p.translucency.attribute});` : ''}
	}
#endif`;
		}
		let outgoing = '';
		if (p.tam) outgoing += `
	if (u_baker_tam_on > 0.5) {
		vec2 tile = baker_tam_coord(vBakerUv, u_bakerTamScale, u_bakerTamFinestSize);
		float lod = baker_tam_lod(dFdx(tile), dFdy(tile), u_bakerTamFinestSize, u_bakerTamLevels);
		float darkness = baker_hatching_darkness(normal, baker_key_light(vec3(0.0, 0.0, 1.0)), 1.0);
		outgoingLight *= baker_hatching(u_bakerTam012, u_bakerTam345, tile, lod, darkness, u_bakerTamTonesA, u_bakerTamTonesB);
	}`;
		if (p.curvature) outgoing += `
	if (u_baker_curvature_on > 0.5) {
		// diverging map: blue concave, white flat, red convex; curvature * meanLength, saturating at +-1
		float k = clamp(vBaker${p.curvature.attribute} / u_bakerCurvatureScale, -1.0, 1.0);
		outgoingLight = k > 0.0 ? mix(vec3(1.0), vec3(0.85, 0.1, 0.05), k) : mix(vec3(1.0), vec3(0.05, 0.2, 0.85), -k);
		outgoingLight *= 0.35 + 0.65 * saturate(dot(normal, baker_key_light(vec3(0.0, 0.0, 1.0))));
	}`;
		shader.fragmentShader = shader.fragmentShader
			.replace('#include <common>', `#include <common>\n${modules}\n${declarations}\n${varyings}\nvarying vec2 vBakerUv;`)
			.replace('#include <lights_pars_begin>', `#include <lights_pars_begin>\n${DIRECTIONAL_DIFFUSE}`)
			.replace('#include <lights_fragment_end>', `#include <lights_fragment_end>\n${lights}`)
			.replace('#include <opaque_fragment>', `${outgoing}\n#include <opaque_fragment>`);
	}
}

function surfacePlugin(name, build) {
	return class {
		constructor(parser, options = {}) {
			this.parser = parser;
			this.name = TECHNIQUES[name]?.extension ?? name;
			this.shaders = options.shaders || {};
			this.options = options;
		}
		async afterRoot(result) {
			const json = this.parser.json.materials || [];
			const done = new Set();
			for (const [object, material, index] of sceneMaterials(this.parser, result.scene)) {
				const ext = json[index]?.extensions?.[this.name];
				if (!ext || done.has(material) || ext.finsOf !== undefined) continue;
				const part = await build.call(this, ext, object, material);
				if (!part) continue;
				done.add(material);
				const surface = BakerSurface.of(material, this.shaders);
				surface.add(name, part);
				controls(this.parser).add(name, (on) => surface.setEnabled(name, on));
			}
			return null;
		}
	};
}

function geometryHas(object, attribute) {
	return Boolean(attribute && object.geometry.getAttribute(attribute.toLowerCase()));
}

/** Translucency parameters of a material's BAKER_thickness, with the extension's defaults filled in. */
export function thicknessParameters(ext) {
	const color = ext.subsurfaceColor ?? [1, 1, 1];
	return {
		attenuationDistance: ext.attenuationDistance ?? ext.meanThickness ?? 1,
		distortion: ext.distortion ?? 0.2,
		power: ext.power ?? 4,
		scale: ext.scale ?? 1,
		ambient: ext.ambient ?? 0,
		subsurfaceColor: color.slice(0, 3),
		attribute: ext.attribute ?? null,
	};
}

/** GLTFLoader plugin for BAKER_thickness: back-lit translucency (GDC 2011 form of RTR4 eq. 14.30) per directional light. */
export const BakerThicknessPlugin = surfacePlugin('translucency', function (ext, object, material) {
	const params = thicknessParameters(ext);
	if (!geometryHas(object, params.attribute)) return null; // texture-only thickness: not drawn by this plugin
	material.userData.bakerThickness = params;
	const c = params.subsurfaceColor;
	return {
		glsl: requireShader(this.shaders, 'translucency'),
		attributes: [[params.attribute.toLowerCase(), 'float']],
		attribute: params.attribute.toLowerCase(),
		uniforms: {
			u_bakerThickness: {
				value: {
					attenuationDistance: params.attenuationDistance, distortion: params.distortion, power: params.power,
					scale: params.scale, ambient: params.ambient, subsurfaceColor: new THREE.Vector3(c[0], c[1], c[2]),
				},
			},
		},
		types: { u_bakerThickness: 'BakerThickness' },
	};
});

/** GLTFLoader plugin for BAKER_skin_lut (+ the BAKER_curvature attribute): Penner's pre-integrated skin diffuse. */
export const BakerSkinLutPlugin = surfacePlugin('skin', async function (ext, object, material) {
	const lut = await textureOf(this.parser, ext.lutTexture);
	if (!lut) return null;
	const lutTexture = dataTexture(lut.clone());
	if (ext.encoding === 'srgb') lutTexture.colorSpace = THREE.SRGBColorSpace;
	const attribute = ext.curvatureAttribute && geometryHas(object, ext.curvatureAttribute) ? ext.curvatureAttribute.toLowerCase() : null;
	const v2 = (a, d) => new THREE.Vector2(...(a ?? d));
	const v3 = (a, d) => new THREE.Vector3(...(a ?? d));
	return {
		glsl: requireShader(this.shaders, 'skin'),
		attributes: attribute ? [[attribute, 'float']] : [],
		// without the baked attribute: the per-pixel estimate of RTR4 14.6.3 (screen-space derivatives)
		curvature: attribute ? `vBaker${attribute}` : 'baker_skin_curvature_from_derivatives(fwidth(normal), fwidth(vViewPosition))',
		uniforms: {
			u_bakerSkinLut: { value: lutTexture },
			u_bakerSkin: {
				value: {
					curvatureRange: v2(ext.curvatureRange, [0.01, 1]), curvatureScale: ext.curvatureScale ?? 1,
					penumbraWidthRange: v2(ext.penumbraWidthRange, [0.01, 1]), normalBlend: v3(ext.normalBlend, [1, 0.5, 0.25]),
					wrap: ext.wrap ?? 0.5, scatterWidth: ext.scatterWidth ?? 0.3, scatterColor: v3(ext.scatterColor, [0.8, 0.25, 0.1]),
				},
			},
		},
		types: { u_bakerSkinLut: 'sampler2D', u_bakerSkin: 'BakerSkin' },
	};
});

/** GLTFLoader plugin for BAKER_toon_ramp: the Lambert term through the baked ramp (or X-Toon map). */
export const BakerToonRampPlugin = surfacePlugin('toon', async function (ext) {
	const ramp = await textureOf(this.parser, ext.rampTexture);
	if (!ramp) return null;
	const xtoon = { none: 0, depth: 1, orientation: 2 }[ext.xtoon ?? 'none'] ?? 0;
	return {
		glsl: requireShader(this.shaders, 'toon'),
		uniforms: {
			u_bakerToonRamp: { value: dataTexture(ramp.clone()) },
			u_bakerToonXtoon: { value: xtoon },
			u_bakerToonDepthRange: { value: new THREE.Vector2(...(ext.depthRange ?? [1, 100])) },
			u_bakerToonOrientationPower: { value: ext.orientationPower ?? 1 },
		},
		types: { u_bakerToonRamp: 'sampler2D', u_bakerToonXtoon: 'int', u_bakerToonDepthRange: 'vec2' },
	};
});

/**
 * The TAM's packed textures as two textures whose mip chains are the TAM's own levels (Praun et al. 2001): level i
 * of the extension is uploaded as mip level i, as baker_hatching.glsl expects.
 */
export async function tamTextures(parser, ext) {
	const levels = ext.levels || [];
	const loaded = await Promise.all(levels.map((l) => Promise.all((l.textures || []).map((t) => textureOf(parser, t)))));
	return [0, 1].map((k) => {
		const images = loaded.map((pair) => pair[k].image);
		const texture = new THREE.Texture(images[0]);
		texture.mipmaps = images;
		texture.colorSpace = THREE.NoColorSpace;
		texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
		texture.magFilter = THREE.LinearFilter;
		texture.minFilter = THREE.LinearMipmapLinearFilter;
		texture.generateMipmaps = false;
		texture.flipY = false;
		texture.needsUpdate = true;
		return texture;
	});
}

/** GLTFLoader plugin for BAKER_tonal_art_map (packed layout): hatching strokes, tone from the key light. */
export const BakerTonalArtMapPlugin = surfacePlugin('tam', async function (ext) {
	if ((ext.layout ?? 'packed') !== 'packed' || !ext.levels?.length) {
		console.warn('@baker/three: BAKER_tonal_art_map: only the packed layout is drawn by this plugin');
		return null;
	}
	const [t012, t345] = await tamTextures(this.parser, ext);
	const tones = ext.tones;
	return {
		glsl: requireShader(this.shaders, 'hatching'),
		uniforms: {
			u_bakerTam012: { value: t012 }, u_bakerTam345: { value: t345 },
			u_bakerTamScale: { value: ext.scale ?? ext.levels[0].size },
			u_bakerTamFinestSize: { value: ext.levels[0].size },
			u_bakerTamLevels: { value: ext.levels.length },
			u_bakerTamTonesA: { value: new THREE.Vector3(tones[0], tones[1], tones[2]) },
			u_bakerTamTonesB: { value: new THREE.Vector3(tones[3], tones[4], tones[5]) },
		},
		types: { u_bakerTam012: 'sampler2D', u_bakerTam345: 'sampler2D', u_bakerTamTonesA: 'vec3', u_bakerTamTonesB: 'vec3' },
	};
});

/** GLTFLoader plugin for BAKER_curvature: a diverging false-colour view of the baked mean curvature (off by default). */
export const BakerCurvaturePlugin = surfacePlugin('curvature', function (ext, object) {
	if (!geometryHas(object, ext.attribute)) return null;
	const range = ext.range ?? [-1, 1];
	return {
		attributes: [[ext.attribute.toLowerCase(), 'float']],
		attribute: ext.attribute.toLowerCase(),
		uniforms: { u_bakerCurvatureScale: { value: Math.max(Math.abs(ext.meanCurvature ?? 0) * 4, Math.abs(range[1]) * 0.5, 1e-6) } },
	};
});

// ------------------------------------------------------------------------------------------------ edges
const FIN_VERTEX = `
attribute vec3 _fin_v0;
attribute vec3 _fin_v1;
attribute vec3 _fin_v2;
attribute vec3 _fin_v3;
attribute float _fin_corner;
attribute float _fin_flags;
uniform vec2 u_viewport;
uniform float u_width;
uniform float u_creaseCos;
uniform int u_classes;
void main() {
	vec3 eye = (inverse(modelMatrix) * vec4(cameraPosition, 1.0)).xyz;  // object space
	int c = baker_fin_classify(_fin_v0, _fin_v1, _fin_v2, _fin_v3, _fin_flags, eye, u_creaseCos);
	vec4 clip0 = projectionMatrix * modelViewMatrix * vec4(_fin_v0, 1.0);
	vec4 clip1 = projectionMatrix * modelViewMatrix * vec4(_fin_v1, 1.0);
	if ((c & u_classes) == 0 || clip0.w <= 0.0 || clip1.w <= 0.0) {
		gl_Position = baker_fin_culled();
		return;
	}
	gl_Position = baker_fin_position(clip0, clip1, _fin_corner, u_width, u_viewport);
	gl_Position.z -= 1e-4 * gl_Position.w;  // over the surface it outlines
}`;

const SOLID_FRAGMENT = `
uniform vec3 u_color;
void main() { gl_FragColor = vec4(u_color, 1.0); }`;

const OUTLINE_VERTEX = `
attribute vec3 _outline_normal;
uniform vec2 u_viewport;
uniform float u_width;
void main() {
	vec4 clip = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
	vec3 p = baker_shell_position(position, _outline_normal, clip.w, u_width, u_viewport.y, projectionMatrix[1][1]);
	gl_Position = projectionMatrix * modelViewMatrix * vec4(p, 1.0);
}`;

const WIREFRAME_VERTEX = `
attribute vec3 baker_bary;
attribute float baker_mask;
varying vec3 vBary;
flat varying int vMask;
void main() {
	vBary = baker_bary;
	vMask = int(baker_mask + 0.5);
	gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

const WIREFRAME_FRAGMENT = `
uniform vec3 u_color;
uniform float u_width;
varying vec3 vBary;
flat varying int vMask;
void main() {
	vec2 cov = baker_wireframe(vBary, fwidth(vBary), vMask, u_width, 0.0);
	if (cov.x <= 0.0) discard;
	gl_FragColor = vec4(u_color * cov.x, cov.x);  // premultiplied
}`;

/**
 * Triangles of an indexed geometry as a non-indexed one with per-corner barycentrics and the triangle's wireframe
 * mask (Baerentzen et al. 2006 need one vertex per corner).
 */
export function wireframeGeometry(geometry, mask) {
	const flat = geometry.index ? geometry.toNonIndexed() : geometry.clone();
	const count = flat.attributes.position.count;
	const bary = new Float32Array(count * 3);
	const masks = new Float32Array(count);
	for (let v = 0; v < count; v++) {
		bary[v * 3 + (v % 3)] = 1;
		masks[v] = mask ? mask[Math.floor(v / 3)] : 7;
	}
	const out = new THREE.BufferGeometry();
	out.setAttribute('position', flat.attributes.position);
	out.setAttribute('baker_bary', new THREE.BufferAttribute(bary, 3));
	out.setAttribute('baker_mask', new THREE.BufferAttribute(masks, 1));
	return out;
}

/** GLTFLoader plugin for BAKER_edges: fins (McGuire & Hughes 2004), shell outline (RTR4 15.2.2), wireframe (Baerentzen 2006). */
export class BakerEdgesPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_EDGES;
		this.shaders = options.shaders || {};
		this.style = { color: [0.02, 0.02, 0.03], finWidth: 2.5, outlineWidth: 3, wireframeWidth: 1.25,
			wireframeColor: [0.95, 0.75, 0.2], classes: 1 | 2 | 4 | 8, ...(options.edges || {}) };
	}

	async afterRoot(result) {
		const glsl = () => requireShader(this.shaders, 'edges');
		const c = controls(this.parser);
		const meshes = [];
		result.scene.traverse((o) => o.isMesh && meshes.push(o));
		for (const object of meshes) {
			const ext = primitiveOf(this.parser, object)?.extensions?.[BAKER_EDGES];
			if (!ext) continue;
			if (ext.finsOf !== undefined) {
				// the fin primitive: degenerate quads the vertex shader opens where the edge is wanted
				const source = this.parser.json.meshes[this.parser.associations.get(object).meshes].primitives[ext.finsOf];
				const crease = source?.extensions?.[BAKER_EDGES]?.creaseAngle ?? Math.PI / 3;
				const uniforms = {
					u_viewport: { value: new THREE.Vector2(1, 1) }, u_width: { value: this.style.finWidth },
					u_creaseCos: { value: Math.cos(crease) }, u_classes: { value: this.style.classes },
					u_color: { value: new THREE.Color(...this.style.color) },
				};
				object.material = new THREE.ShaderMaterial({
					name: 'baker fins', uniforms, vertexShader: glsl() + FIN_VERTEX, fragmentShader: SOLID_FRAGMENT,
					side: THREE.DoubleSide,
				});
				object.frustumCulled = false;
				object.renderOrder = 2;
				trackViewport(object, uniforms);
				c.add('fins', (on) => { object.visible = on; });
				continue;
			}
			const outline = ext.outlineNormal ?? '_OUTLINE_NORMAL';
			if (geometryHas(object, outline)) {
				const uniforms = {
					u_viewport: { value: new THREE.Vector2(1, 1) }, u_width: { value: this.style.outlineWidth },
					u_color: { value: new THREE.Color(...this.style.color) },
				};
				const geometry = new THREE.BufferGeometry();
				geometry.setIndex(object.geometry.index);
				geometry.setAttribute('position', object.geometry.attributes.position);
				geometry.setAttribute('_outline_normal', object.geometry.getAttribute(outline.toLowerCase()));
				const shell = new THREE.Mesh(geometry, new THREE.ShaderMaterial({
					name: 'baker shell outline', uniforms, vertexShader: glsl() + OUTLINE_VERTEX, fragmentShader: SOLID_FRAGMENT,
					side: THREE.BackSide,
				}));
				shell.name = 'baker outline';
				shell.frustumCulled = false;
				trackViewport(shell, uniforms);
				object.add(shell);
				c.add('outline', (on) => { shell.visible = on; });
			}
			if (ext.wireframeMask !== undefined || ext.wireframeHides) {
				const mask = ext.wireframeMask !== undefined ? (await this.parser.getDependency('accessor', ext.wireframeMask)).array : null;
				const uniforms = { u_width: { value: this.style.wireframeWidth }, u_color: { value: new THREE.Color(...this.style.wireframeColor) } };
				const wire = new THREE.Mesh(wireframeGeometry(object.geometry, mask), new THREE.ShaderMaterial({
					name: 'baker wireframe', uniforms, vertexShader: WIREFRAME_VERTEX, fragmentShader: glsl() + WIREFRAME_FRAGMENT,
					transparent: true, depthWrite: false, side: THREE.FrontSide,
					blending: THREE.CustomBlending, blendSrc: THREE.OneFactor, blendDst: THREE.OneMinusSrcAlphaFactor,
					polygonOffset: true, polygonOffsetFactor: -1, polygonOffsetUnits: -4,
				}));
				wire.name = 'baker wireframe';
				wire.renderOrder = 1;
				object.add(wire);
				c.add('wireframe', (on) => { wire.visible = on; });
			}
		}
		return null;
	}
}

// ------------------------------------------------------------------------------------------------ fur
const FUR_SHELL_VERTEX = `
uniform float u_shell;
uniform float u_shellCount;
uniform float u_shellSpacing;
uniform float u_tiling;
varying vec2 vUvFur;
varying vec3 vNormalView;
void main() {
	vec3 p = baker_fur_shell_position(position, normal, u_shell, u_shellSpacing, u_shellCount, vec3(0.0));
	vUvFur = baker_fur_shell_uv(uv, u_tiling);
	vNormalView = normalize(normalMatrix * normal);
	gl_Position = projectionMatrix * modelViewMatrix * vec4(p, 1.0);
}`;

const FUR_SHELL_FRAGMENT = `
uniform sampler2D u_texture;
uniform float u_shell;
uniform float u_shellCount;
varying vec2 vUvFur;
varying vec3 vNormalView;
void main() {
	vec4 texel = texture(u_texture, vUvFur);
	if (texel.a < 0.01) discard;
	vec4 shaded = baker_fur_shell_shade(texel, baker_fur_shell_height(u_shell, u_shellCount), 0.35);
	vec3 light = ambientLightColor + baker_directional_diffuse(normalize(vNormalView)) * 0.5;
	gl_FragColor = vec4(shaded.rgb * light, shaded.a);
}`;

const FUR_FIN_VERTEX = `
attribute vec3 _fin_v0;
attribute vec3 _fin_v1;
attribute vec3 _fin_v2;
attribute vec3 _fin_v3;
attribute float _fin_corner;
attribute vec3 _fur_fin_normal;
attribute vec2 _fur_fin_uv;
uniform float u_length;
uniform float u_threshold;
varying vec2 vUvFin;
varying float vWeight;
varying vec3 vNormalView;
void main() {
	vec3 p = baker_fur_fin_position(_fin_v0, _fin_v1, _fur_fin_normal, _fin_corner, u_length);
	vec3 n0;
	vec3 n1;
	baker_fur_fin_face_normals(_fin_v0, _fin_v1, _fin_v2, _fin_v3, n0, n1);
	vec3 eye = (inverse(modelMatrix) * vec4(cameraPosition, 1.0)).xyz;
	vWeight = baker_fur_fin_weight(n0, n1, normalize(eye - p), u_threshold);
	vUvFin = _fur_fin_uv;
	vNormalView = normalize(normalMatrix * _fur_fin_normal);
	gl_Position = projectionMatrix * modelViewMatrix * vec4(p, 1.0);
}`;

const FUR_FIN_FRAGMENT = `
uniform sampler2D u_texture;
varying vec2 vUvFin;
varying float vWeight;
varying vec3 vNormalView;
void main() {
	vec4 texel = texture(u_texture, vUvFin);
	float a = texel.a * vWeight;
	if (a < 0.01) discard;
	vec3 light = ambientLightColor + baker_directional_diffuse(normalize(vNormalView)) * 0.5;
	gl_FragColor = vec4(texel.rgb * light, a);
}`;

/** GLTFLoader plugin for BAKER_fur: shells (one transparent pass per shell texture) and fins (Lengyel et al. 2001). */
export class BakerFurPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_FUR;
		this.shaders = options.shaders || {};
		this.finThreshold = options.fur?.finThreshold ?? 0.4;
	}

	async afterRoot(result) {
		const c = controls(this.parser);
		const materials = this.parser.json.materials || [];
		const glsl = () => requireShader(this.shaders, 'fur');
		for (const [object, , index] of sceneMaterials(this.parser, result.scene)) {
			const ext = materials[index]?.extensions?.[BAKER_FUR];
			if (!ext) continue;
			const primitive = primitiveOf(this.parser, object);
			const finOf = primitive?.extensions?.[BAKER_FUR]?.finsOf;
			if (finOf !== undefined) {
				const texture = await textureOf(this.parser, ext.finTexture);
				if (!texture) continue;
				const uniforms = { u_texture: { value: texture }, u_length: { value: ext.length }, u_threshold: { value: this.finThreshold } };
				object.material = litShaderMaterial({
					name: 'baker fur fins', uniforms, vertexShader: glsl() + FUR_FIN_VERTEX,
					fragmentShader: `#include <common>\n#include <lights_pars_begin>\n${glsl()}${DIRECTIONAL_DIFFUSE}${FUR_FIN_FRAGMENT}`,
					transparent: true, depthWrite: false, side: THREE.DoubleSide,
				});
				object.frustumCulled = false;
				object.renderOrder = 3;
				c.add('fur', (on) => { object.visible = on; });
				continue;
			}
			if (primitive?.extensions?.[BAKER_EDGES]?.finsOf !== undefined) continue;
			const textures = await Promise.all((ext.shellTextures || []).map((t) => textureOf(this.parser, t)));
			const shells = new THREE.Group();
			shells.name = 'baker fur shells';
			textures.forEach((texture, i) => {
				texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
				texture.needsUpdate = true;
				const uniforms = {
					u_texture: { value: texture }, u_shell: { value: i }, u_shellCount: { value: ext.shellCount ?? textures.length },
					u_shellSpacing: { value: ext.shellSpacing ?? (ext.length / textures.length) }, u_tiling: { value: ext.tiling ?? 1 },
				};
				const shell = new THREE.Mesh(object.geometry, litShaderMaterial({
					name: `baker fur shell ${i}`, uniforms, vertexShader: glsl() + FUR_SHELL_VERTEX,
					fragmentShader: `#include <common>\n#include <lights_pars_begin>\n${glsl()}${DIRECTIONAL_DIFFUSE}${FUR_SHELL_FRAGMENT}`,
					transparent: true, depthWrite: false,
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

// ------------------------------------------------------------------------------------------------ hair
const HAIR_VERTEX = `
attribute vec3 baker_tangent;
attribute float baker_param;
attribute float baker_side;
attribute float baker_widthScale;
uniform float u_rootWidth;
uniform float u_tipWidth;
uniform vec2 u_viewport;
varying float vOpacity;
varying vec3 vTangent;
varying vec3 vView;
void main() {
	vec3 eye = (inverse(modelMatrix) * vec4(cameraPosition, 1.0)).xyz;  // object space
	float w = baker_hair_width(u_rootWidth, u_tipWidth, baker_param, baker_widthScale);
	float tanHalfFovY = 1.0 / projectionMatrix[1][1];
	vec2 cov = baker_hair_coverage(w, baker_hair_pixel_size(distance(eye, position), tanHalfFovY, u_viewport.y));
	vec3 p = baker_hair_ribbon_position(position, baker_tangent, eye, cov.x, baker_side);
	vOpacity = cov.y;
	vec4 view = modelViewMatrix * vec4(p, 1.0);
	vTangent = normalize((modelViewMatrix * vec4(baker_tangent, 0.0)).xyz);
	vView = -view.xyz;
	gl_Position = projectionMatrix * view;
}`;

const HAIR_FRAGMENT = `
uniform vec3 u_color;
uniform vec3 u_specular;
uniform float u_exponent;
varying float vOpacity;
varying vec3 vTangent;
varying vec3 vView;
void main() {
	vec3 T = normalize(vTangent);
	vec3 V = normalize(vView);
	vec3 color = ambientLightColor * u_color;
#if NUM_DIR_LIGHTS > 0
	for (int i = 0; i < NUM_DIR_LIGHTS; i++) {
		color += directionalLights[i].color * baker_hair_kajiya_kay(T, directionalLights[i].direction, V, u_color, u_specular, u_exponent);
	}
#endif
	gl_FragColor = vec4(color, vOpacity);
}`;

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

/** GLTFLoader plugin for BAKER_hair: view-facing ribbons extruded in the vertex shader, Kajiya-Kay shading. */
export class BakerHairPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_HAIR;
		this.shaders = options.shaders || {};
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
				u_rootWidth: { value: ext.rootWidth }, u_tipWidth: { value: ext.tipWidth },
				u_viewport: { value: new THREE.Vector2(1, 1) },
				u_color: { value: new THREE.Vector3(base.r, base.g, base.b) },
				u_specular: { value: new THREE.Vector3(0.3, 0.28, 0.25) }, u_exponent: { value: 60 },
			};
			const glsl = requireShader(this.shaders, 'hair');
			const ribbons = new THREE.Mesh(geometry, litShaderMaterial({
				name: 'baker hair ribbons', uniforms, vertexShader: glsl + HAIR_VERTEX,
				fragmentShader: `#include <common>\n#include <lights_pars_begin>\n${glsl}${HAIR_FRAGMENT}`,
				transparent: true, side: THREE.DoubleSide,
			}));
			ribbons.name = 'baker hair ribbons';
			ribbons.frustumCulled = false;
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

// ------------------------------------------------------------------------------------------------ text
const TEXT_VERTEX = `
varying vec2 vUvText;
void main() {
	vUvText = uv;
	gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

const TEXT_FRAGMENT = `
uniform sampler2D u_atlas;
uniform BakerTextStyle u_style;
uniform int u_fieldType;
uniform float u_distanceRange;
uniform vec2 u_shadowOffset;
varying vec2 vUvText;
void main() {
	vec2 atlasSize = vec2(textureSize(u_atlas, 0));
	float range = baker_text_screen_px_range(u_distanceRange, atlasSize, fwidth(vUvText));
	vec4 texel = texture(u_atlas, vUvText);
	vec4 shadowTexel = texture(u_atlas, vUvText - u_shadowOffset);
	vec4 color = baker_text_shade(u_style, texel, shadowTexel, u_fieldType, u_distanceRange, range);
	if (color.a <= 0.0) discard;
	gl_FragColor = color;  // premultiplied
}`;

const FIELD_TYPES = { sdf: 0, psdf: 1, msdf: 2, mtsdf: 3 };

/** GLTFLoader plugin for BAKER_glyph_atlas: loads the fonts' atlases (used by BAKER_text). */
export class BakerGlyphAtlasPlugin {
	constructor(parser) {
		this.parser = parser;
		this.name = BAKER_GLYPH_ATLAS;
	}
	/** The atlas texture and its font entry for BAKER_glyph_atlas.fonts[index]. */
	async font(index) {
		const font = this.parser.json.extensions?.[BAKER_GLYPH_ATLAS]?.fonts?.[index];
		if (!font) return null;
		const texture = await textureOf(this.parser, font.texture);
		return texture && { font, texture: dataTexture(texture.clone()) };
	}
}

/** GLTFLoader plugin for BAKER_text: the label's glyph quads drawn with the distance-field shader (outline, glow, shadow). */
export class BakerTextPlugin {
	constructor(parser, options = {}) {
		this.parser = parser;
		this.name = BAKER_TEXT;
		this.shaders = options.shaders || {};
		this.atlas = new BakerGlyphAtlasPlugin(parser);
	}

	async afterRoot(result) {
		const c = controls(this.parser);
		const nodes = this.parser.json.nodes || [];
		const labels = [];
		result.scene.traverse((o) => {
			const index = this.parser.associations.get(o)?.nodes;
			const ext = index !== undefined && nodes[index]?.extensions?.[BAKER_TEXT];
			if (ext) labels.push([o, ext]);
		});
		for (const [node, ext] of labels) {
			const atlas = await this.atlas.font(ext.font ?? 0);
			if (!atlas) continue;
			const { font, texture } = atlas;
			const size = font.size ?? 32;
			const rgba = (a, d) => new THREE.Vector4(...(a ?? d).concat([1, 1, 1, 1]).slice(0, 4));
			const style = {
				color: rgba(ext.color, [1, 1, 1, 1]), softness: ext.softness ?? 0,
				outlineColor: rgba(ext.outline?.color, [0, 0, 0, 1]), outlineWidth: (ext.outline?.width ?? 0) * size,
				glowColor: rgba(ext.glow?.color, [1, 1, 1, 0]), glowWidth: (ext.glow?.width ?? 0) * size,
				shadowColor: rgba(ext.shadow?.color, [0, 0, 0, 0]), shadowSoftness: (ext.shadow?.softness ?? 0) * size,
			};
			if (!ext.shadow) style.shadowColor.w = 0;
			// the field saturates half a range outside the glyph: a wider outline would fill the whole quad
			const widest = 0.5 * (font.distanceRange ?? 4) - 0.5;
			if (style.outlineWidth > widest) {
				console.warn(`@baker/three: BAKER_text outline (${style.outlineWidth.toFixed(2)} atlas px) is wider than the ` +
					`atlas distance range allows; drawn ${widest} px wide`);
				style.outlineWidth = widest;
			}
			const offset = ext.shadow?.offset ?? [0, 0];
			const uniforms = {
				u_atlas: { value: texture }, u_style: { value: style }, u_fieldType: { value: FIELD_TYPES[font.type] ?? 2 },
				u_distanceRange: { value: font.distanceRange ?? 4 },
				u_shadowOffset: { value: new THREE.Vector2(offset[0] * size / (font.width ?? 1), offset[1] * size / (font.height ?? 1)) },
			};
			const material = new THREE.ShaderMaterial({
				name: 'baker MSDF text', uniforms, vertexShader: TEXT_VERTEX,
				fragmentShader: requireShader(this.shaders, 'text') + TEXT_FRAGMENT,
				transparent: true, depthWrite: false, side: THREE.DoubleSide,
				blending: THREE.CustomBlending, blendSrc: THREE.OneFactor, blendDst: THREE.OneMinusSrcAlphaFactor,
			});
			node.traverse((o) => {
				if (!o.isMesh) return;
				const fallback = o.material; // glTF's alpha-tested single-channel field
				c.add('text', (on) => { o.material = on ? material : fallback; });
			});
		}
		return null;
	}
}

// ------------------------------------------------------------------------------------------------ registration
/** Publishes the switches of every technique found as gltf.userData.baker (runs after every other plugin). */
class BakerControlsPlugin {
	constructor(parser) {
		this.parser = parser;
		this.name = 'BAKER_controls';
	}
	afterRoot(result) {
		result.userData ??= {};
		const c = controls(this.parser);
		result.userData.baker = c;
		result.scene.userData.baker = c;
		return null;
	}
}

export const PLUGINS = [BakerThicknessPlugin, BakerCurvaturePlugin, BakerSkinLutPlugin, BakerToonRampPlugin,
	BakerTonalArtMapPlugin, BakerEdgesPlugin, BakerFurPlugin, BakerHairPlugin, BakerTextPlugin];

/**
 * Register every baker plugin on a GLTFLoader. `options.shaders` holds the runtime-shaders/ modules as text:
 * { translucency, skin, toon, hatching, edges, fur, hair, text } (baker_<name>.glsl). `options.edges` overrides the
 * line style ({ color, finWidth, outlineWidth, wireframeWidth, wireframeColor } in pixels / linear RGB).
 */
export function registerBakerPlugins(loader, options = {}) {
	for (const Plugin of PLUGINS) loader.register((parser) => new Plugin(parser, options));
	// GLTFLoader runs afterRoot hooks concurrently; this one only publishes the shared object the others fill
	loader.register((parser) => new BakerControlsPlugin(parser));
	return loader;
}
