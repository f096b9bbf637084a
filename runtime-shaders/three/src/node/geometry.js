// The geometry techniques on WebGPURenderer: the WebGL plugins draw fins, the shell outline, the wireframe, fur
// shells and fins, hair ribbons and MSDF text with ShaderMaterials of the shared stages (runtime-shaders/hosts/web);
// each becomes here a MeshBasicNodeMaterial doing what its stages do, in the same order, with the runtime-shaders/
// modules (./modules.js): the vertex stage as positionNode (object space) or vertexNode (clip space, the fins),
// the fragment stage as fragmentNode. The uniforms are the ShaderMaterial's own holders (read through reference
// nodes), so the plugins' switches, trackViewport and setHairLod keep driving them.
//
// The stages write gl_FragColor as it is (no colour-space conversion: a ShaderMaterial's output is not encoded);
// WebGPURenderer encodes every material's output to the canvas' sRGB, so the fragment here is decoded first
// (sRGBTransferEOTF) and the canvas receives the same values.
import { Color, FunctionCallNode, FunctionNode, MeshBasicNodeMaterial, Vector2, Vector3, Vector4 } from 'three/webgpu';
import {
	Discard, Fn, If, attribute, cameraPosition, cameraProjectionMatrix, distance, float, fwidth, max, mix, modelNormalMatrix,
	modelViewMatrix, modelWorldMatrixInverse, normalGeometry, normalize, positionGeometry, positionView, reference,
	nodeObject, sRGBTransferEOTF, step, texture, uniform, uv, varying, vec2, vec3, vec4,
} from 'three/tsl';
import { STAGES } from '@baker/shared';
import { isWgslBuilder } from './modules.js';

const MAX_LIGHTS = 4;

/** The node type of a ShaderMaterial uniform's value. */
function typeOf(value) {
	if (value?.isTexture) return 'texture';
	if (value instanceof Color) return 'color';
	if (value instanceof Vector4) return 'vec4';
	if (value instanceof Vector3) return 'vec3';
	if (value instanceof Vector2) return 'vec2';
	return 'float';
}

/**
 * The scene's directional lights (up to MAX_LIGHTS, the rest zero) in view space and its ambient light, as WebGL's
 * directionalLights[] and ambientLightColor give them (colour x intensity; the HemisphereLight is not ambient there).
 */
function sceneLights() {
	const state = { renderId: -1, directions: [], colors: [], ambient: new Color() };
	for (let i = 0; i < MAX_LIGHTS; i++) {
		state.directions.push(new Vector3(0, 0, 1));
		state.colors.push(new Color(0, 0, 0));
	}
	const a = new Vector3();
	const b = new Vector3();
	const refresh = ({ scene, camera, renderId }) => {
		if (state.renderId === renderId || !scene || !camera) return;
		state.renderId = renderId;
		let n = 0;
		state.ambient.setRGB(0, 0, 0);
		scene.traverseVisible((o) => {
			if (o.isAmbientLight) state.ambient.add(o.color.clone().multiplyScalar(o.intensity));
			if (!o.isDirectionalLight || n >= MAX_LIGHTS) return;
			a.setFromMatrixPosition(o.matrixWorld);
			b.setFromMatrixPosition(o.target.matrixWorld);
			state.directions[n].subVectors(a, b).transformDirection(camera.matrixWorldInverse);
			state.colors[n].copy(o.color).multiplyScalar(o.intensity);
			n++;
		});
		for (let i = n; i < MAX_LIGHTS; i++) state.colors[i].setRGB(0, 0, 0);
	};
	const node = (get) => uniform(get()).onRenderUpdate((frame) => { refresh(frame); return get(); });
	return {
		directions: state.directions.map((_, i) => node(() => state.directions[i])),
		colors: state.colors.map((_, i) => node(() => state.colors[i])),
		ambient: node(() => state.ambient),
	};
}

/** sum of color * max(N.L, 0) over the directional lights (hosts/web/lights.glsl). */
function directionalDiffuse(lights, N) {
	return lights.directions.reduce((sum, L, i) => sum.add(lights.colors[i].mul(max(N.dot(L), 0))), vec3(0));
}

const objectEye = () => modelWorldMatrixInverse.mul(vec4(cameraPosition, 1)).xyz;
const clip = (p) => cameraProjectionMatrix.mul(modelViewMatrix).mul(vec4(p, 1));
const projectionY = () => cameraProjectionMatrix.element(1).y;
const raw = (rgb, a) => vec4(sRGBTransferEOTF(rgb), a);

// baker_hair_shading with its three tables, in WGSL or GLSL. A TSL wrapper passes a texture node as a WGSL
// texture_2d<f32> (and its sampler), but three.js builds a GLSL sampler2D argument as '<name>_sampler', which WebGL2
// lacks: the GLSL wrapper's sampler2D inputs are read as 'texture', which builds to the sampler2D uniform itself.
const FIBRE_WGSL = `fn baker_hair_fibre_node(mTable: texture_2d<f32>, mTableSampler: sampler, nTable: texture_2d<f32>,
	nTableSampler: sampler, dualTable: texture_2d<f32>, dualTableSampler: sampler, variances: vec4f, params: vec4f,
	T: vec3f, L: vec3f, V: vec3f, fibres: f32, sigmaA: vec3f) -> vec3f {
	let h = BakerHairShading(variances, params.x, params.y, params.z, params.w, 1.0, 1.0);
	return baker_hair_shading(mTable, mTableSampler, nTable, nTableSampler, dualTable, dualTableSampler, h, T, L, V,
		fibres, sigmaA);
}`;
const FIBRE_GLSL = `vec3 baker_hair_fibre_node(sampler2D mTable, sampler2D nTable, sampler2D dualTable, vec4 variances,
	vec4 params, vec3 T, vec3 L, vec3 V, float fibres, vec3 sigmaA) {
	BakerHairShading h = BakerHairShading(variances, params.x, params.y, params.z, params.w, 1.0, 1.0);
	return baker_hair_shading(mTable, nTable, dualTable, h, T, L, V, fibres, sigmaA);
}`;
function fibreFunction(m) {
	const module = m.module('hairShading');
	const wgsl = new FunctionNode(FIBRE_WGSL, [module.wgsl], 'wgsl');
	const glsl = new FunctionNode(FIBRE_GLSL, [module.glsl], 'glsl');
	const parse = glsl.getNodeFunction.bind(glsl);
	glsl.getNodeFunction = (builder) => {
		const fn = parse(builder);
		for (const input of fn.inputs) if (input.type === 'sampler2D') input.type = 'texture';
		return fn;
	};
	return (tables, rest) => Fn((builder) => (isWgslBuilder(builder)
		? nodeObject(new FunctionCallNode(wgsl, [tables[0], tables[0], tables[1], tables[1], tables[2], tables[2], ...rest]))
		: nodeObject(new FunctionCallNode(glsl, [...tables, ...rest]))))();
}

/** hair_ribbon.vert (BAKER_HAIR_SHADING) + hair_fibre.frag: the ribbon of the Kajiya-Kay stage, shaded as fibres. */
function fibreRibbon(u, m, lights, { tangent, eye, cov, opacity, T }) {
	const fibre = attribute('baker_fibre', 'vec3');
	const melanin = m.fn('hairShading', 'baker_hair_shading_melanin')(fibre.x, fibre.y);
	const sigmaA = varying(mix(u('u_hairSigmaA'), melanin, u('u_hairMelaninPerVertex')));
	const occlusion = varying(fibre.z);
	const positive = varying(attribute('baker_fibresPos', 'vec3'));
	const negative = varying(attribute('baker_fibresNeg', 'vec3'));
	const axis = (x, y, z) => varying(normalize(modelViewMatrix.mul(vec4(x, y, z, 0)).xyz));
	const axes = [axis(1, 0, 0), axis(0, 1, 0), axis(0, 0, 1)];
	const shade = fibreFunction(m);
	const tables = ['u_hairLongitudinal', 'u_hairAzimuthal', 'u_hairDual'].map((name) => texture(u(name).value));
	return {
		positionNode: m.fn('hair', 'baker_hair_ribbon_position')(positionGeometry, tangent, eye, cov.x, attribute('baker_side', 'float')),
		fragmentNode: Fn(() => {
			const Tn = normalize(T);
			const V = normalize(positionView.negate());
			const color = lights.directions.reduce((sum, L, i) => {
				const l = normalize(vec3(L.dot(axes[0]), L.dot(axes[1]), L.dot(axes[2])));
				const fibres = l.mul(l).dot(mix(negative, positive, step(vec3(0), l)));
				return sum.add(lights.colors[i].mul(shade(tables, [u('u_hairVariances'), u('u_hairParams'), Tn, L, V, fibres, sigmaA])));
			}, lights.ambient.mul(u('u_color')).mul(occlusion));
			return raw(color, opacity);
		})(),
	};
}

// the shared stages, by the name of their vertex stage: (u: uniform reader, m: BakerModules) -> node properties
const STAGE_NODES = {
	'edges_fin.vert': (u, m) => {
		const fin = m.custom('edges', `fn baker_fin_vertex_node(v0: vec3f, v1: vec3f, v2: vec3f, v3: vec3f, flags: f32, corner: f32,
	eye: vec3f, creaseCos: f32, classes: f32, clip0: vec4f, clip1: vec4f, widthPx: f32, viewport: vec2f) -> vec4f {
	let c = baker_fin_classify(v0, v1, v2, v3, flags, eye, creaseCos);
	if ((c & i32(classes + 0.5)) == 0 || clip0.w <= 0.0 || clip1.w <= 0.0) {
		return baker_fin_culled();
	}
	var p = baker_fin_position(clip0, clip1, corner, widthPx, viewport);
	p.z -= 0.5e-4 * p.w;  // the stage's 1e-4 of GL's z range [-1, 1]: the same depth offset in WebGPU's [0, 1]
	return p;
}`, `vec4 baker_fin_vertex_node(vec3 v0, vec3 v1, vec3 v2, vec3 v3, float flags, float corner, vec3 eye, float creaseCos,
	float classes, vec4 clip0, vec4 clip1, float widthPx, vec2 viewport) {
	int c = baker_fin_classify(v0, v1, v2, v3, flags, eye, creaseCos);
	if ((c & int(classes + 0.5)) == 0 || clip0.w <= 0.0 || clip1.w <= 0.0) {
		return baker_fin_culled();
	}
	vec4 p = baker_fin_position(clip0, clip1, corner, widthPx, viewport);
	p.z -= 1e-4 * p.w;
	return p;
}`);
		const v = [0, 1, 2, 3].map((i) => attribute(`_fin_v${i}`, 'vec3'));
		return {
			vertexNode: fin(v[0], v[1], v[2], v[3], attribute('_fin_flags', 'float'), attribute('_fin_corner', 'float'),
				objectEye(), u('u_creaseCos'), u('u_classes'), clip(v[0]), clip(v[1]), u('u_width'), u('u_viewport')),
		};
	},
	'edges_outline.vert': (u, m) => {
		const w = clip(positionGeometry).w;
		return {
			positionNode: m.fn('edges', 'baker_shell_position')(positionGeometry, attribute('_outline_normal', 'vec3'), w,
				u('u_width'), u('u_viewport').y, projectionY()),
		};
	},
	'edges_wireframe.vert': (u, m) => {
		const wire = m.custom('edges', `fn baker_wireframe_node(bary: vec3f, barySlope: vec3f, mask: f32, widthPx: f32) -> vec2f {
	return baker_wireframe(bary, barySlope, i32(mask + 0.5), widthPx, 0.0);
}`, `vec2 baker_wireframe_node(vec3 bary, vec3 barySlope, float mask, float widthPx) {
	return baker_wireframe(bary, barySlope, int(mask + 0.5), widthPx, 0.0);
}`);
		const bary = varying(attribute('baker_bary', 'vec3'));
		const mask = varying(attribute('baker_mask', 'float'));  // the same on a triangle's three corners (flat in GLSL)
		return {
			fragmentNode: Fn(() => {
				const cov = wire(bary, fwidth(bary), mask, u('u_width'));
				If(cov.x.lessThanEqual(0), () => Discard());
				return raw(u('u_color').mul(cov.x), cov.x);
			})(),
		};
	},
	'fur_shell.vert': (u, m, lights) => {
		const shell = u('u_shell');
		const count = u('u_shellCount');
		const furUv = varying(m.fn('fur', 'baker_fur_shell_uv')(uv(), u('u_tiling')));
		const normalLight = varying(modelNormalMatrix.mul(normalGeometry));
		return {
			positionNode: m.fn('fur', 'baker_fur_shell_position')(positionGeometry, normalGeometry, shell, u('u_shellSpacing'),
				count, vec3(0)),
			fragmentNode: Fn(() => {
				const texel = texture(u('u_texture').value, furUv);
				If(texel.a.lessThan(u('u_alphaCutoff')), () => Discard());
				const shaded = m.fn('fur', 'baker_fur_shell_shade')(texel, m.fn('fur', 'baker_fur_shell_height')(shell, count), 0.35);
				const light = lights.ambient.add(directionalDiffuse(lights, normalize(normalLight)).mul(0.5));
				return raw(shaded.rgb.mul(light), mix(shaded.a, 1, u('u_alphaTest')));
			})(),
		};
	},
	'fur_fin.vert': (u, m, lights) => {
		const v = [0, 1, 2, 3].map((i) => attribute(`_fin_v${i}`, 'vec3'));
		const finNormal = attribute('_fur_fin_normal', 'vec3');
		const p = m.fn('fur', 'baker_fur_fin_position')(v[0], v[1], finNormal, attribute('_fin_corner', 'float'), u('u_length'));
		const weightOf = m.custom('fur', `fn baker_fur_fin_weight_node(v0: vec3f, v1: vec3f, v2: vec3f, v3: vec3f, p: vec3f, eye: vec3f,
	threshold: f32) -> f32 {
	var n0: vec3f;
	var n1: vec3f;
	baker_fur_fin_face_normals(v0, v1, v2, v3, &n0, &n1);
	return baker_fur_fin_weight(n0, n1, normalize(eye - p), threshold);
}`, `float baker_fur_fin_weight_node(vec3 v0, vec3 v1, vec3 v2, vec3 v3, vec3 p, vec3 eye, float threshold) {
	vec3 n0;
	vec3 n1;
	baker_fur_fin_face_normals(v0, v1, v2, v3, n0, n1);
	return baker_fur_fin_weight(n0, n1, normalize(eye - p), threshold);
}`);
		const weight = varying(weightOf(v[0], v[1], v[2], v[3], p, objectEye(), u('u_threshold')));
		const finUv = varying(attribute('_fur_fin_uv', 'vec2'));
		const normalLight = varying(modelNormalMatrix.mul(finNormal));
		return {
			positionNode: p,
			fragmentNode: Fn(() => {
				const texel = texture(u('u_texture').value, finUv);
				If(texel.a.lessThan(u('u_alphaCutoff')), () => Discard());
				const a = mix(texel.a, 1, u('u_alphaTest')).mul(weight);
				If(a.lessThan(0.01), () => Discard());
				const light = lights.ambient.add(directionalDiffuse(lights, normalize(normalLight)).mul(0.5));
				return raw(texel.rgb.mul(light), a);
			})(),
		};
	},
	'hair_ribbon.vert': (u, m, lights, holders) => {
		const eye = objectEye();
		const param = attribute('baker_param', 'float');
		const tangent = attribute('baker_tangent', 'vec3');
		const w = m.fn('hair', 'baker_hair_lod_width')(m.fn('hair', 'baker_hair_width')(u('u_rootWidth'), u('u_tipWidth'), param,
			attribute('baker_widthScale', 'float')), u('u_lodWidthScale'));
		const tanHalfFovY = float(1).div(projectionY());
		const cov = m.fn('hair', 'baker_hair_coverage')(w, m.fn('hair', 'baker_hair_pixel_size')(distance(eye, positionGeometry),
			tanHalfFovY, u('u_viewport').y));
		const opacity = varying(cov.y);
		const T = varying(normalize(modelViewMatrix.mul(vec4(tangent, 0)).xyz));
		const kajiyaKay = m.fn('hair', 'baker_hair_kajiya_kay');
		if (holders.u_hairLongitudinal) return fibreRibbon(u, m, lights, { tangent, eye, cov, opacity, T });
		return {
			positionNode: m.fn('hair', 'baker_hair_ribbon_position')(positionGeometry, tangent, eye, cov.x, attribute('baker_side', 'float')),
			fragmentNode: Fn(() => {
				const Tn = normalize(T);
				const V = normalize(positionView.negate());
				const color = lights.directions.reduce((sum, L, i) => sum.add(lights.colors[i].mul(
					kajiyaKay(Tn, L, V, u('u_color'), u('u_specular'), u('u_exponent')))), lights.ambient.mul(u('u_color')));
				return raw(color, opacity);
			})(),
		};
	},
	'text.vert': (u, m) => {
		const shade = m.custom('text', `fn baker_text_shade_node(color: vec4f, softness: f32, outlineColor: vec4f, outlineWidth: f32,
	glowColor: vec4f, glowWidth: f32, shadowColor: vec4f, shadowSoftness: f32, texel: vec4f, shadowTexel: vec4f, fieldType: f32,
	distanceRange: f32, screenPxRange: f32) -> vec4f {
	let style = BakerTextStyle(color, softness, outlineColor, outlineWidth, glowColor, glowWidth, shadowColor, shadowSoftness);
	return baker_text_shade(style, texel, shadowTexel, i32(fieldType + 0.5), distanceRange, screenPxRange);
}`, `vec4 baker_text_shade_node(vec4 color, float softness, vec4 outlineColor, float outlineWidth, vec4 glowColor,
	float glowWidth, vec4 shadowColor, float shadowSoftness, vec4 texel, vec4 shadowTexel, float fieldType, float distanceRange,
	float screenPxRange) {
	BakerTextStyle style = BakerTextStyle(color, softness, outlineColor, outlineWidth, glowColor, glowWidth, shadowColor,
		shadowSoftness);
	return baker_text_shade(style, texel, shadowTexel, int(fieldType + 0.5), distanceRange, screenPxRange);
}`);
		const atlas = u('u_atlas').value;
		const textUv = uv();
		return {
			fragmentNode: Fn(() => {
				const size = vec2(atlas.image?.width ?? 1, atlas.image?.height ?? 1);
				const range = m.fn('text', 'baker_text_screen_px_range')(u('u_distanceRange'), size, fwidth(textUv));
				const texel = texture(atlas, textUv);
				const shadowTexel = texture(atlas, textUv.sub(u('u_shadowOffset')));
				const color = shade(u('u_color'), u('u_softness'), u('u_outlineColor'), u('u_outlineWidth'), u('u_glowColor'),
					u('u_glowWidth'), u('u_shadowColor'), u('u_shadowSoftness'), texel, shadowTexel, u('u_fieldType'),
					u('u_distanceRange'), range);
				If(color.a.lessThanEqual(0), () => Discard());
				return raw(color.rgb, color.a);
			})(),
		};
	},
};

/** The name of the shared vertex stage a stageMaterial (../common.js) was built from, or null. */
export function stageOf(material) {
	return Object.keys(STAGE_NODES).find((name) => material.vertexShader?.endsWith(STAGES[name])) ?? null;
}

const COPIED = ['name', 'side', 'transparent', 'depthWrite', 'depthTest', 'blending', 'blendSrc', 'blendDst',
	'blendEquation', 'polygonOffset', 'polygonOffsetFactor', 'polygonOffsetUnits', 'visible'];

/**
 * The node material drawing the ShaderMaterial `material` of a geometry technique (null for a ShaderMaterial that
 * is not one of the shared stages). `modules`: BakerModules.
 */
export function geometryNodeMaterial(material, modules) {
	const stage = stageOf(material);
	if (!stage) return null;
	const holders = material.uniforms;
	const u = (name) => {
		const holder = holders[name];
		if (!holder) throw new Error(`@baker/three: ${material.name}: uniform ${name} missing`);
		if (typeOf(holder.value) === 'texture') return holder;  // sampled with texture(holder.value, uv)
		return reference('value', typeOf(holder.value), holder);
	};
	const node = new MeshBasicNodeMaterial();
	for (const key of COPIED) node[key] = material[key];
	Object.assign(node, STAGE_NODES[stage](u, modules, sceneLights(), holders));
	// fins and the shell outline: hosts/web/solid.frag.glsl, one flat colour
	if (!node.fragmentNode && material.fragmentShader?.endsWith(STAGES['solid.frag'])) node.fragmentNode = raw(u('u_color'), 1);
	node.uniforms = holders;  // setHairLod and the caustics-like callers write ribbons.material.uniforms.*.value
	node.userData.bakerStage = stage;
	return node;
}
