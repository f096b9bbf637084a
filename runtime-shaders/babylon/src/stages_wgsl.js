// The geometry techniques' ShaderMaterial stages in WGSL, for Babylon's WebGPUEngine: the twins of the shared GLSL
// stages (runtime-shaders/hosts/web/*.glsl, @baker/shared STAGES) under the same names, with the same inputs,
// uniforms and formulas (the runtime modules baker_*.wgsl do the work). They are written in Babylon's WGSL dialect
// (`attribute` / `varying` / `uniform` declarations, vertexInputs, vertexOutputs, fragmentOutputs, uniforms), which
// Babylon's shader processor turns into WGSL: no other host reads them, so they live here, not in hosts/web.
// The host preludes (common.js) define what the GLSL preludes do: baker_clip, baker_object_eye, baker_light_normal,
// baker_light_vector, baker_to_eye, baker_projection_y, u_viewport; and for lit stages the light accessors.

export const STAGES_WGSL_BABYLON = {
	'edges_fin.vert': `
attribute _fin_v0: vec3f;
attribute _fin_v1: vec3f;
attribute _fin_v2: vec3f;
attribute _fin_v3: vec3f;
attribute _fin_corner: f32;
attribute _fin_flags: f32;
uniform u_width: f32;
uniform u_creaseCos: f32;
uniform u_classes: i32;
@vertex
fn main(input: VertexInputs) -> FragmentInputs {
	let eye = baker_object_eye();
	let c = baker_fin_classify(vertexInputs._fin_v0, vertexInputs._fin_v1, vertexInputs._fin_v2, vertexInputs._fin_v3,
		vertexInputs._fin_flags, eye, uniforms.u_creaseCos);
	let clip0 = baker_clip(vertexInputs._fin_v0);
	let clip1 = baker_clip(vertexInputs._fin_v1);
	if ((c & uniforms.u_classes) == 0 || clip0.w <= 0.0 || clip1.w <= 0.0) {
		vertexOutputs.position = baker_fin_culled();
		return vertexOutputs;
	}
	var p = baker_fin_position(clip0, clip1, vertexInputs._fin_corner, uniforms.u_width, uniforms.u_viewport);
	p.z -= 1e-4 * p.w;
	vertexOutputs.position = p;
}
`,
	'edges_outline.vert': `
attribute _outline_normal: vec3f;
uniform u_width: f32;
@vertex
fn main(input: VertexInputs) -> FragmentInputs {
	let clip = baker_clip(vertexInputs.position);
	let p = baker_shell_position(vertexInputs.position, vertexInputs._outline_normal, clip.w, uniforms.u_width,
		uniforms.u_viewport.y, baker_projection_y());
	vertexOutputs.position = baker_clip(p);
}
`,
	'edges_wireframe.vert': `
attribute baker_bary: vec3f;
attribute baker_mask: f32;
varying vBary: vec3f;
flat varying vMask: i32;
@vertex
fn main(input: VertexInputs) -> FragmentInputs {
	vertexOutputs.vBary = vertexInputs.baker_bary;
	vertexOutputs.vMask = i32(vertexInputs.baker_mask + 0.5);
	vertexOutputs.position = baker_clip(vertexInputs.position);
}
`,
	'edges_wireframe.frag': `
uniform u_color: vec3f;
uniform u_width: f32;
varying vBary: vec3f;
flat varying vMask: i32;
@fragment
fn main(input: FragmentInputs) -> FragmentOutputs {
	let cov = baker_wireframe(fragmentInputs.vBary, fwidth(fragmentInputs.vBary), fragmentInputs.vMask, uniforms.u_width, 0.0);
	if (cov.x <= 0.0) {
		discard;
	}
	fragmentOutputs.color = vec4f(uniforms.u_color * cov.x, cov.x);
}
`,
	'solid.frag': `
uniform u_color: vec3f;
@fragment
fn main(input: FragmentInputs) -> FragmentOutputs {
	fragmentOutputs.color = vec4f(uniforms.u_color, 1.0);
}
`,
	'fur_fin.vert': `
attribute _fin_v0: vec3f;
attribute _fin_v1: vec3f;
attribute _fin_v2: vec3f;
attribute _fin_v3: vec3f;
attribute _fin_corner: f32;
attribute _fur_fin_normal: vec3f;
attribute _fur_fin_uv: vec2f;
uniform u_length: f32;
uniform u_threshold: f32;
varying vUvFin: vec2f;
varying vWeight: f32;
varying vNormalLight: vec3f;
@vertex
fn main(input: VertexInputs) -> FragmentInputs {
	let p = baker_fur_fin_position(vertexInputs._fin_v0, vertexInputs._fin_v1, vertexInputs._fur_fin_normal,
		vertexInputs._fin_corner, uniforms.u_length);
	var n0: vec3f;
	var n1: vec3f;
	baker_fur_fin_face_normals(vertexInputs._fin_v0, vertexInputs._fin_v1, vertexInputs._fin_v2, vertexInputs._fin_v3, &n0, &n1);
	vertexOutputs.vWeight = baker_fur_fin_weight(n0, n1, normalize(baker_object_eye() - p), uniforms.u_threshold);
	vertexOutputs.vUvFin = vertexInputs._fur_fin_uv;
	vertexOutputs.vNormalLight = baker_light_normal(vertexInputs._fur_fin_normal);
	vertexOutputs.position = baker_clip(p);
}
`,
	'fur_fin.frag': `
var u_textureSampler: sampler;
var u_texture: texture_2d<f32>;
uniform u_alphaCutoff: f32;
uniform u_alphaTest: f32;
varying vUvFin: vec2f;
varying vWeight: f32;
varying vNormalLight: vec3f;
@fragment
fn main(input: FragmentInputs) -> FragmentOutputs {
	let texel = textureSample(u_texture, u_textureSampler, fragmentInputs.vUvFin);
	if (texel.a < uniforms.u_alphaCutoff) {
		discard;
	}
	let a = mix(texel.a, 1.0, uniforms.u_alphaTest) * fragmentInputs.vWeight;
	if (a < 0.01) {
		discard;
	}
	let light = baker_ambient_light() + baker_directional_diffuse(normalize(fragmentInputs.vNormalLight)) * 0.5;
	fragmentOutputs.color = vec4f(texel.rgb * light, a);
}
`,
	'fur_shell.vert': `
uniform u_shell: f32;
uniform u_shellCount: f32;
uniform u_shellSpacing: f32;
uniform u_tiling: f32;
varying vUvFur: vec2f;
varying vNormalLight: vec3f;
@vertex
fn main(input: VertexInputs) -> FragmentInputs {
	let p = baker_fur_shell_position(vertexInputs.position, vertexInputs.normal, uniforms.u_shell, uniforms.u_shellSpacing,
		uniforms.u_shellCount, vec3f(0.0));
	vertexOutputs.vUvFur = baker_fur_shell_uv(vertexInputs.uv, uniforms.u_tiling);
	vertexOutputs.vNormalLight = baker_light_normal(vertexInputs.normal);
	vertexOutputs.position = baker_clip(p);
}
`,
	'fur_shell.frag': `
var u_textureSampler: sampler;
var u_texture: texture_2d<f32>;
uniform u_shell: f32;
uniform u_shellCount: f32;
uniform u_alphaCutoff: f32;
uniform u_alphaTest: f32;
varying vUvFur: vec2f;
varying vNormalLight: vec3f;
@fragment
fn main(input: FragmentInputs) -> FragmentOutputs {
	let texel = textureSample(u_texture, u_textureSampler, fragmentInputs.vUvFur);
	if (texel.a < uniforms.u_alphaCutoff) {
		discard;
	}
	let shaded = baker_fur_shell_shade(texel, baker_fur_shell_height(uniforms.u_shell, uniforms.u_shellCount), 0.35);
	let light = baker_ambient_light() + baker_directional_diffuse(normalize(fragmentInputs.vNormalLight)) * 0.5;
	fragmentOutputs.color = vec4f(shaded.rgb * light, mix(shaded.a, 1.0, uniforms.u_alphaTest));
}
`,
	'hair_ribbon.vert': `
attribute baker_tangent: vec3f;
attribute baker_param: f32;
attribute baker_side: f32;
attribute baker_widthScale: f32;
uniform u_rootWidth: f32;
uniform u_tipWidth: f32;
uniform u_lodWidthScale: f32;
varying vOpacity: f32;
varying vTangent: vec3f;
varying vView: vec3f;
@vertex
fn main(input: VertexInputs) -> FragmentInputs {
	let eye = baker_object_eye();
	let w = baker_hair_lod_width(baker_hair_width(uniforms.u_rootWidth, uniforms.u_tipWidth, vertexInputs.baker_param,
		vertexInputs.baker_widthScale), uniforms.u_lodWidthScale);
	let tanHalfFovY = 1.0 / baker_projection_y();
	let cov = baker_hair_coverage(w, baker_hair_pixel_size(distance(eye, vertexInputs.position), tanHalfFovY, uniforms.u_viewport.y));
	let p = baker_hair_ribbon_position(vertexInputs.position, vertexInputs.baker_tangent, eye, cov.x, vertexInputs.baker_side);
	vertexOutputs.vOpacity = cov.y;
	vertexOutputs.vTangent = normalize(baker_light_vector(vertexInputs.baker_tangent));
	vertexOutputs.vView = baker_to_eye(p);
	vertexOutputs.position = baker_clip(p);
}
`,
	'hair_ribbon.frag': `
uniform u_color: vec3f;
uniform u_specular: vec3f;
uniform u_exponent: f32;
varying vOpacity: f32;
varying vTangent: vec3f;
varying vView: vec3f;
@fragment
fn main(input: FragmentInputs) -> FragmentOutputs {
	let T = normalize(fragmentInputs.vTangent);
	let V = normalize(fragmentInputs.vView);
	var color = baker_ambient_light() * uniforms.u_color;
	for (var i = 0; i < BAKER_MAX_LIGHTS; i++) {
		if (i >= baker_light_count()) {
			break;
		}
		color += baker_light_color(i) * baker_hair_kajiya_kay(T, baker_light_direction(i), V, uniforms.u_color,
			uniforms.u_specular, uniforms.u_exponent);
	}
	fragmentOutputs.color = vec4f(color, fragmentInputs.vOpacity);
}
`,
	// hair_ribbon.vert with BAKER_HAIR_SHADING defined (the GLSL stage's #ifdef part), and hair_fibre.frag
	'hair_fibre.vert': `
attribute baker_tangent: vec3f;
attribute baker_param: f32;
attribute baker_side: f32;
attribute baker_widthScale: f32;
attribute baker_fibre: vec3f;
attribute baker_fibresPos: vec3f;
attribute baker_fibresNeg: vec3f;
uniform u_rootWidth: f32;
uniform u_tipWidth: f32;
uniform u_lodWidthScale: f32;
uniform u_hairSigmaA: vec3f;
uniform u_hairMelaninPerVertex: f32;
varying vOpacity: f32;
varying vTangent: vec3f;
varying vView: vec3f;
varying vSigmaA: vec3f;
varying vOcclusion: f32;
varying vFibresPos: vec3f;
varying vFibresNeg: vec3f;
varying vAxisX: vec3f;
varying vAxisY: vec3f;
varying vAxisZ: vec3f;
@vertex
fn main(input: VertexInputs) -> FragmentInputs {
	let eye = baker_object_eye();
	let w = baker_hair_lod_width(baker_hair_width(uniforms.u_rootWidth, uniforms.u_tipWidth, vertexInputs.baker_param,
		vertexInputs.baker_widthScale), uniforms.u_lodWidthScale);
	let tanHalfFovY = 1.0 / baker_projection_y();
	let cov = baker_hair_coverage(w, baker_hair_pixel_size(distance(eye, vertexInputs.position), tanHalfFovY, uniforms.u_viewport.y));
	let p = baker_hair_ribbon_position(vertexInputs.position, vertexInputs.baker_tangent, eye, cov.x, vertexInputs.baker_side);
	vertexOutputs.vOpacity = cov.y;
	vertexOutputs.vTangent = normalize(baker_light_vector(vertexInputs.baker_tangent));
	vertexOutputs.vView = baker_to_eye(p);
	vertexOutputs.position = baker_clip(p);
	vertexOutputs.vSigmaA = select(uniforms.u_hairSigmaA, baker_hair_shading_melanin(vertexInputs.baker_fibre.x,
		vertexInputs.baker_fibre.y), uniforms.u_hairMelaninPerVertex > 0.5);
	vertexOutputs.vOcclusion = vertexInputs.baker_fibre.z;
	vertexOutputs.vFibresPos = vertexInputs.baker_fibresPos;
	vertexOutputs.vFibresNeg = vertexInputs.baker_fibresNeg;
	vertexOutputs.vAxisX = normalize(baker_light_vector(vec3f(1.0, 0.0, 0.0)));
	vertexOutputs.vAxisY = normalize(baker_light_vector(vec3f(0.0, 1.0, 0.0)));
	vertexOutputs.vAxisZ = normalize(baker_light_vector(vec3f(0.0, 0.0, 1.0)));
}
`,
	'hair_fibre.frag': `
uniform u_color: vec3f;
uniform u_hairVariances: vec4f;
uniform u_hairParams: vec4f;
var u_hairLongitudinalSampler: sampler;
var u_hairLongitudinal: texture_2d<f32>;
var u_hairAzimuthalSampler: sampler;
var u_hairAzimuthal: texture_2d<f32>;
var u_hairDualSampler: sampler;
var u_hairDual: texture_2d<f32>;
varying vOpacity: f32;
varying vTangent: vec3f;
varying vView: vec3f;
varying vSigmaA: vec3f;
varying vOcclusion: f32;
varying vFibresPos: vec3f;
varying vFibresNeg: vec3f;
varying vAxisX: vec3f;
varying vAxisY: vec3f;
varying vAxisZ: vec3f;
@fragment
fn main(input: FragmentInputs) -> FragmentOutputs {
	let T = normalize(fragmentInputs.vTangent);
	let V = normalize(fragmentInputs.vView);
	let h = BakerHairShading(uniforms.u_hairVariances, uniforms.u_hairParams.x, uniforms.u_hairParams.y,
		uniforms.u_hairParams.z, uniforms.u_hairParams.w, 1.0, 1.0);
	var color = baker_ambient_light() * uniforms.u_color * fragmentInputs.vOcclusion;
	for (var i = 0; i < BAKER_MAX_LIGHTS; i++) {
		if (i >= baker_light_count()) {
			break;
		}
		let L = baker_light_direction(i);
		let l = normalize(vec3f(dot(L, fragmentInputs.vAxisX), dot(L, fragmentInputs.vAxisY), dot(L, fragmentInputs.vAxisZ)));
		let fibres = dot(l * l, mix(fragmentInputs.vFibresNeg, fragmentInputs.vFibresPos, step(vec3f(0.0), l)));
		color += baker_light_color(i) * baker_hair_shading(u_hairLongitudinal, u_hairLongitudinalSampler, u_hairAzimuthal,
			u_hairAzimuthalSampler, u_hairDual, u_hairDualSampler, h, T, L, V, fibres, fragmentInputs.vSigmaA);
	}
	fragmentOutputs.color = vec4f(color, fragmentInputs.vOpacity);
}
`,
	'text.vert': `
varying vUvText: vec2f;
@vertex
fn main(input: VertexInputs) -> FragmentInputs {
	vertexOutputs.vUvText = vertexInputs.uv;
	vertexOutputs.position = baker_clip(vertexInputs.position);
}
`,
	'text.frag': `
var u_atlasSampler: sampler;
var u_atlas: texture_2d<f32>;
uniform u_color: vec4f;
uniform u_softness: f32;
uniform u_outlineColor: vec4f;
uniform u_outlineWidth: f32;
uniform u_glowColor: vec4f;
uniform u_glowWidth: f32;
uniform u_shadowColor: vec4f;
uniform u_shadowSoftness: f32;
uniform u_fieldType: i32;
uniform u_distanceRange: f32;
uniform u_shadowOffset: vec2f;
varying vUvText: vec2f;
@fragment
fn main(input: FragmentInputs) -> FragmentOutputs {
	let style = BakerTextStyle(uniforms.u_color, uniforms.u_softness, uniforms.u_outlineColor, uniforms.u_outlineWidth,
		uniforms.u_glowColor, uniforms.u_glowWidth, uniforms.u_shadowColor, uniforms.u_shadowSoftness);
	let atlasSize = vec2f(textureDimensions(u_atlas, 0));
	let range = baker_text_screen_px_range(uniforms.u_distanceRange, atlasSize, fwidth(fragmentInputs.vUvText));
	let texel = textureSample(u_atlas, u_atlasSampler, fragmentInputs.vUvText);
	let shadowTexel = textureSample(u_atlas, u_atlasSampler, fragmentInputs.vUvText - uniforms.u_shadowOffset);
	let color = baker_text_shade(style, texel, shadowTexel, uniforms.u_fieldType, uniforms.u_distanceRange, range);
	if (color.a <= 0.0) {
		discard;
	}
	fragmentOutputs.color = color;
}
`,
	lights: `
fn baker_directional_diffuse(N: vec3f) -> vec3f {
	var sum = vec3f(0.0);
	for (var i = 0; i < BAKER_MAX_LIGHTS; i++) {
		if (i >= baker_light_count()) {
			break;
		}
		sum += baker_light_color(i) * max(dot(N, baker_light_direction(i)), 0.0);
	}
	return sum;
}
`,
};
