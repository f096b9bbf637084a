// The surface techniques (BAKER_thickness, BAKER_skin_lut, BAKER_toon_ramp, BAKER_tonal_art_map, BAKER_curvature,
// BAKER_caustics, BAKER_hair_cards, BAKER_normal_blur):
// each extension builds one part (GLSL module, uniforms, samplers, attributes); one MaterialPluginBase per PBR
// material composes the parts of that material. Per punctual light, after Babylon's own diffuse
// (computeDiffuseLighting), the clamped N.L of Lambert's term becomes f (vec3): per-channel N.L of the blurred
// diffuse normals, the skin LUT (Penner) and/or the
// toon ramp of it, and the translucency is added, both on the base colour as @baker/three does; caustics
// redistribute the directional lights' Lambert light (on the base colour too); hatching multiplies the lit colour (linear, before image processing) by the TAM brightness; the
// curvature view replaces it. Each part is gated by a uniform, so a switch costs no recompile.
// The material's shader language picks the code: GLSL on the WebGL2 Engine (partCode), WGSL on WebGPUEngine
// (partCodeWgsl: the same points and formulas with the parts' baker_*.wgsl modules).
import { MaterialPluginBase } from '@babylonjs/core/Materials/materialPluginBase.js';
import { surfaceStages } from '@baker/shared';
import { GLSL, WGSL, controls, glslType, loadedPrimitives, wgslType } from './common.js';

const PLUGIN_NAME = 'BakerSurface';
const PART_DEFINES = ['translucency', 'skin', 'toon', 'tam', 'curvature', 'caustics', 'cards', 'normalBlur'];
const define = (name) => `BAKER_${name.toUpperCase()}`;
// regular expressions (Babylon's "!" points) matched in the PBR fragment shader after its includes are expanded
const LIGHT_POINT = '!info\\.diffuse=computeDiffuseLighting\\(preInfo,diffuse(\\d+)\\.rgb\\);';
const OUTGOING_POINT = '!finalColor=applyImageProcessing\\(finalColor\\);';
const POINTS = {
	vertex: ['CUSTOM_VERTEX_DEFINITIONS', 'CUSTOM_VERTEX_MAIN_END'],
	fragment: ['CUSTOM_FRAGMENT_DEFINITIONS', 'CUSTOM_FRAGMENT_BEFORE_LIGHTS', LIGHT_POINT,
		'CUSTOM_FRAGMENT_BEFORE_FINALCOLORCOMPOSITION', OUTGOING_POINT],
};

// the first directional light of the scene, towards the light (world space): the key light of hatching
const KEY_LIGHT = `
vec3 baker_key_light(vec3 fallback) {
#if defined(DIRLIGHT0)
	return normalize(-light0.vLightData.xyz);
#elif defined(DIRLIGHT1)
	return normalize(-light1.vLightData.xyz);
#elif defined(DIRLIGHT2)
	return normalize(-light2.vLightData.xyz);
#elif defined(DIRLIGHT3)
	return normalize(-light3.vLightData.xyz);
#else
	return fallback;
#endif
}`;

// hair cards: the strand direction from the flow texture in the card's frame (from screen-space derivatives, as
// @baker/three), then per light Kajiya-Kay along it instead of Lambert's term (baker_hair_cards.glsl); the alpha test
// is the loader's own (alphaCutOff)
const CARDS_FRAME = `
vec3 bakerCardsData = texture(u_bakerCardsData, v_bakerUv).rgb;
vec3 bakerCardsT = baker_hair_cards_flow(texture(u_bakerCardsFlow, v_bakerUv).rgb, normalW,
	baker_hair_cards_frame(normalW, dFdx(vPositionW), dFdy(vPositionW), dFdx(v_bakerUv), dFdy(v_bakerUv)));`;
// normal blur: the three diffuse normals in world space, through the bump texture's frame at its UV (the frame's
// normal column normalized: Babylon scales it by the bump level, the maps have the glTF scale applied already)
const NORMAL_BLUR = `
mat3 bakerTBN = mat3(TBN[0], TBN[1], normalize(TBN[2]));
vec3 bakerNormalRed = normalize(bakerTBN * baker_normal_blur_decode(texture(u_bakerNormalBlurRed, vBumpUV).rgb, 1.0));
vec3 bakerNormalGreen = normalize(bakerTBN * baker_normal_blur_decode(texture(u_bakerNormalBlurGreen, vBumpUV).rgb, 1.0));
vec3 bakerNormalBlue = normalize(bakerTBN * baker_normal_blur_decode(texture(u_bakerNormalBlurBlue, vBumpUV).rgb, 1.0));`;

// the WGSL twins of KEY_LIGHT, CARDS_FRAME and NORMAL_BLUR (Babylon's WGSL PBR: the same names, its inputs under
// fragmentInputs; TBN's normal column normalized likewise)
const KEY_LIGHT_WGSL = `
fn baker_key_light(fallback: vec3f) -> vec3f {
#if defined(DIRLIGHT0)
	return normalize(-light0.vLightData.xyz);
#elif defined(DIRLIGHT1)
	return normalize(-light1.vLightData.xyz);
#elif defined(DIRLIGHT2)
	return normalize(-light2.vLightData.xyz);
#elif defined(DIRLIGHT3)
	return normalize(-light3.vLightData.xyz);
#else
	return fallback;
#endif
}`;
const CARDS_FRAME_WGSL = `
let bakerCardsData = textureSample(u_bakerCardsData, u_bakerCardsDataSampler, v_bakerUv).rgb;
let bakerCardsT = baker_hair_cards_flow(textureSample(u_bakerCardsFlow, u_bakerCardsFlowSampler, v_bakerUv).rgb, normalW,
	baker_hair_cards_frame(normalW, dpdx(vPositionW), dpdy(vPositionW), dpdx(v_bakerUv), dpdy(v_bakerUv)));`;
const NORMAL_BLUR_WGSL = `
let bakerTBN = mat3x3f(TBN[0], TBN[1], normalize(TBN[2]));
let bakerNormalRed = normalize(bakerTBN * baker_normal_blur_decode(textureSample(u_bakerNormalBlurRed, u_bakerNormalBlurRedSampler, fragmentInputs.vBumpUV).rgb, 1.0));
let bakerNormalGreen = normalize(bakerTBN * baker_normal_blur_decode(textureSample(u_bakerNormalBlurGreen, u_bakerNormalBlurGreenSampler, fragmentInputs.vBumpUV).rgb, 1.0));
let bakerNormalBlue = normalize(bakerTBN * baker_normal_blur_decode(textureSample(u_bakerNormalBlurBlue, u_bakerNormalBlurBlueSampler, fragmentInputs.vBumpUV).rgb, 1.0));`;

// every texture a part holds (all its frames when it swaps them), not only those bound now
const partTextures = (p) => p.textures || Object.values(p.samplers || {});

export class BakerSurfacePlugin extends MaterialPluginBase {
	constructor(material) {
		const defines = Object.fromEntries(PART_DEFINES.map((n) => [define(n), false]));
		super(material, PLUGIN_NAME, 300, defines, true, false);
		this.parts = {};
		this._enable(true);
	}

	/** The plugin of a PBR material, created on first use. */
	static of(material) {
		return material.pluginManager?.getPlugin(PLUGIN_NAME) ?? new BakerSurfacePlugin(material);
	}

	getClassName() { return 'BakerSurfacePlugin'; }
	// GLSL (WebGL2) and WGSL (WebGPUEngine): each part carries its module in the material's language
	isCompatible(shaderLanguage) { return shaderLanguage === GLSL || shaderLanguage === WGSL; }

	add(name, part) {
		this.parts[name] = { ...part, on: 1 };
		// the uniform block is laid out at the first draw: a part added after it needs a new one
		if (this._material._uniformBufferLayoutBuilt) {
			this._material.resetDrawCache();
			this._material._createUniformBuffer();
		}
		this.markAllDefinesAsDirty();
	}

	setEnabled(name, on) {
		if (this.parts[name]) this.parts[name].on = on ? 1 : 0;
	}

	attributes() {
		const out = new Map();
		// [kind, component count, optional vertex-stage expression of the varying (default: the attribute itself)]
		for (const p of Object.values(this.parts || {})) for (const entry of p.attributes || []) out.set(entry[0], entry);
		return [...out.values()].sort((a, b) => (a[0] < b[0] ? -1 : 1));
	}

	prepareDefinesBeforeAttributes(defines) {
		if (!this.parts) return;
		for (const n of PART_DEFINES) defines[define(n)] = Boolean(this.parts[n]);
		if (this.parts.tam) defines._needUVs = true; // the TAM tiles over TEXCOORD_0 even on an untextured material
	}

	getAttributes(attributes) {
		for (const [kind] of this.attributes()) attributes.push(kind);
	}

	getSamplers(samplers) {
		for (const p of Object.values(this.parts || {})) samplers.push(...Object.keys(p.samplers || {}));
	}

	getUniforms(shaderLanguage = GLSL) {
		const ubo = [];
		for (const [name, p] of Object.entries(this.parts || {})) {
			ubo.push({ name: `u_baker_${name}_on`, size: 1, type: 'float' });
			for (const [u, { type }] of Object.entries(p.uniforms || {})) ubo.push({ name: u, size: { float: 1, int: 1, vec2: 2, vec3: 3, vec4: 4 }[type], type });
		}
		// WGSL: Babylon declares the block's members itself (`uniform name: type;`, read as uniforms.name)
		if (shaderLanguage === WGSL) return { ubo };
		const declarations = ubo.map((u) => `uniform ${u.type} ${u.name};`).join('\n');
		return { ubo, vertex: declarations, fragment: declarations };
	}

	bindForSubMesh(uniformBuffer) {
		for (const [name, p] of Object.entries(this.parts || {})) {
			if (p.update) p.update(); // e.g. the caustic frames of the current time
			uniformBuffer.updateFloat(`u_baker_${name}_on`, p.on);
			for (const [u, { type, value }] of Object.entries(p.uniforms || {})) {
				if (type === 'float') uniformBuffer.updateFloat(u, value);
				else if (type === 'int') uniformBuffer.updateInt(u, value);
				else if (type === 'vec2') uniformBuffer.updateFloat2(u, value[0], value[1]);
				else if (type === 'vec3') uniformBuffer.updateFloat3(u, value[0], value[1], value[2]);
				else uniformBuffer.updateFloat4(u, value[0], value[1], value[2], value[3]);
			}
			for (const [s, texture] of Object.entries(p.samplers || {})) uniformBuffer.setTexture(s, texture);
		}
	}

	getActiveTextures(activeTextures) {
		for (const p of Object.values(this.parts || {})) activeTextures.push(...partTextures(p));
	}

	hasTexture(texture) {
		return Object.values(this.parts || {}).some((p) => partTextures(p).includes(texture));
	}

	// Babylon collects the injection points once, when the plugin is added (before any part): every point is
	// always listed, with empty code where this material's parts need none.
	getCustomCode(shaderType, shaderLanguage = GLSL) {
		const code = Object.fromEntries(POINTS[shaderType].map((point) => [point, '']));
		if (!this.parts || !Object.keys(this.parts).length) return code;
		return Object.assign(code, shaderLanguage === WGSL ? this.partCodeWgsl(shaderType) : this.partCode(shaderType));
	}

	// The uniforms of the parts (the on switches included), in uniform-block order
	uniformNames() {
		return Object.entries(this.parts).flatMap(([name, p]) => [`u_baker_${name}_on`, ...Object.keys(p.uniforms || {})]);
	}

	/**
	 * partCode's WGSL twin, for Babylon's WGSL PBR shaders (WebGPUEngine): the same points, names and formulas, with
	 * the parts' WGSL modules (runtime-shaders/baker_*.wgsl: a sampler2D argument is a texture and its sampler).
	 * The parts' uniforms, varyings and vPositionW are aliased by their own names at the start of the lighting, so
	 * the parts' expressions (the thickness, the curvature, the parameter structs) read the same in both languages.
	 */
	partCodeWgsl(shaderType) {
		const p = this.parts;
		const attributes = this.attributes();
		const varyings = attributes.map(([kind, size]) => `varying v_${kind}: ${wgslType(size)};`).join('\n') + '\nvarying v_bakerUv: vec2f;';
		if (shaderType === 'vertex') {
			return {
				CUSTOM_VERTEX_DEFINITIONS: `${attributes.map(([kind, size]) => `attribute ${kind}: ${wgslType(size)};`).join('\n')}
${varyings}`,
				CUSTOM_VERTEX_MAIN_END: `${attributes.map(([kind, , , v]) => `vertexOutputs.v_${kind} = ${v ?? `vertexInputs.${kind}`};`).join('\n')}
#ifdef UV1
vertexOutputs.v_bakerUv = vertexInputs.uv;
#else
vertexOutputs.v_bakerUv = vec2f(0.0);
#endif`,
			};
		}
		const samplers = Object.values(p).flatMap((x) => Object.keys(x.samplers || {}))
			.map((s) => `var ${s}Sampler: sampler;\nvar ${s}: texture_2d<f32>;`).join('\n');
		const modules = [...new Set(Object.values(p).map((x) => x.wgsl).filter(Boolean))].join('\n');
		const aliases = [
			...this.uniformNames().map((u) => `let ${u} = uniforms.${u};`),
			...attributes.map(([kind]) => `let v_${kind} = fragmentInputs.v_${kind};`),
			'let v_bakerUv = fragmentInputs.v_bakerUv;',
			'let vPositionW = fragmentInputs.vPositionW;',
		].join('\n');
		const diffuse = [];
		if (p.normalBlur) diffuse.push(`var bakerNdotL = vec3f(dotNL);
if (u_baker_normalBlur_on > 0.5) {
	bakerNdotL = baker_normal_blur_ndotl(bakerNormalRed, bakerNormalGreen, bakerNormalBlue, bakerL);
	f = clamp(bakerNdotL, vec3f(0.0), vec3f(1.0));
	bakerReplaced = true;
}`);
		const skin = (normals) => `baker_skin_diffuse(${p.skin.struct}, u_bakerSkinLut, u_bakerSkinLutSampler, ${normals}, bakerL, bakerSkinK)`;
		if (p.skin) diffuse.push(`if (u_baker_skin_on > 0.5) {
	let bakerSkinK = ${p.skin.curvature('geometricNormalW', 'bakerL')};
	${p.normalBlur ? `if (u_baker_normalBlur_on > 0.5) {
		f = baker_skin_diffuse_normals(${p.skin.struct}, u_bakerSkinLut, u_bakerSkinLutSampler, bakerNdotL, bakerSkinK);
	} else {
		f = ${skin('normalW, normalW')};
	}` : `f = ${skin('normalW, normalW')};`}
	bakerReplaced = true;
}`);
		if (p.toon) diffuse.push(`if (u_baker_toon_on > 0.5) {
	// the ramp indexed by the lit shade so far (N.L, or the skin LUT's luminance mapped back to -1..1)
	var nl = dotNL;
	${p.skin ? 'if (u_baker_skin_on > 0.5) { nl = 2.0 * dot(f, vec3f(0.2126, 0.7152, 0.0722)) - 1.0; }' : ''}
	if (u_bakerToonXtoon < 0.5) {
		f = vec3f(baker_toon_ramp(u_bakerToonRamp, u_bakerToonRampSampler, nl));
	} else if (u_bakerToonXtoon < 1.5) {
		f = vec3f(baker_xtoon(u_bakerToonRamp, u_bakerToonRampSampler, nl, baker_xtoon_detail_depth(
			abs((scene.view * vec4f(vPositionW, 1.0)).z), u_bakerToonDepthRange.x, u_bakerToonDepthRange.y)));
	} else {
		f = vec3f(baker_xtoon(u_bakerToonRamp, u_bakerToonRampSampler, nl,
			baker_xtoon_detail_orientation(normalW, viewDirectionW, u_bakerToonOrientationPower)));
	}
	bakerReplaced = true;
}`);
		const code = {
			CUSTOM_FRAGMENT_DEFINITIONS: `${modules}\n${samplers}\n${varyings}\n${KEY_LIGHT_WGSL}`,
		};
		const afterLights = surfaceStages(p, 'afterLights', 'wgsl');
		if (diffuse.length || p.translucency || afterLights || p.cards) {
			code[LIGHT_POINT] = `info.diffuse=computeDiffuseLighting(preInfo,diffuse$1.rgb);
{
	let bakerL = preInfo.L;
	let dotNL = preInfo.NdotLUnclamped;
	var f = vec3f(clamp(dotNL, 0.0, 1.0));
	var bakerReplaced = false;
	${diffuse.join('\n\t')}
	if (bakerReplaced) { bakerLambert += (f - vec3f(clamp(dotNL, 0.0, 1.0))) * (preInfo.attenuation / PI) * diffuse$1.rgb; }
	${p.translucency ? `bakerDirect += u_baker_translucency_on * preInfo.attenuation * diffuse$1.rgb *
		baker_translucency(${p.translucency.struct}, normalW, viewDirectionW, bakerL, ${p.translucency.thickness});` : ''}
	${p.cards ? `if (u_baker_cards_on > 0.5) { bakerCards += (preInfo.attenuation / PI) * (baker_hair_cards_shade(
		albedoOpacityOut.surfaceAlbedo, bakerCardsT, normalW, bakerL, viewDirectionW, diffuse$1.rgb, bakerCardsData.g,
		bakerCardsData.b, 40.0, 0.1, 0.4) - clamp(dotNL, 0.0, 1.0) * diffuse$1.rgb * albedoOpacityOut.surfaceAlbedo); }` : ''}
#ifdef DIRLIGHT$1
	bakerSun += clamp(dotNL, 0.0, 1.0) * (preInfo.attenuation / PI) * diffuse$1.rgb;
#endif
}`;
		}
		code.CUSTOM_FRAGMENT_BEFORE_LIGHTS = `${aliases}
var bakerDirect = vec3f(0.0);
var bakerLambert = vec3f(0.0);
var bakerSun = vec3f(0.0);
var bakerCards = vec3f(0.0);` + (p.cards ? CARDS_FRAME_WGSL : '') + (p.normalBlur ? NORMAL_BLUR_WGSL : '');
		const albedo = p.normalBlur ? 'surfaceAlbedo.rgb' : 'albedoOpacityOut.surfaceAlbedo';
		code.CUSTOM_FRAGMENT_BEFORE_FINALCOLORCOMPOSITION = 'finalDiffuse += bakerDirect * albedoOpacityOut.surfaceAlbedo * uniforms.vLightingIntensity.x;' +
			`\nfinalDiffuse += bakerLambert * ${albedo} * uniforms.vLightingIntensity.x;` +
			'\nfinalDiffuse += bakerCards * uniforms.vLightingIntensity.x;' +
			(afterLights && `
{
let bakerWorldPosition = vPositionW;
let bakerSunLight = bakerSun * albedoOpacityOut.surfaceAlbedo * uniforms.vLightingIntensity.x;
var bakerDiffuse = finalDiffuse;
var bakerOtherLight = vec3f(0.0);  // the specular light (the hemispheric light is in finalDiffuse)
#ifdef SPECULARTERM
bakerOtherLight += finalSpecularScaled;
#endif
#ifdef REFLECTION
bakerOtherLight += finalIrradiance;
#endif
${afterLights}
finalDiffuse = bakerDiffuse;
}`);
		let outgoing = '';
		const onOutgoing = surfaceStages(p, 'outgoing', 'wgsl');
		if (onOutgoing) outgoing += `
{
let bakerUv = v_bakerUv;
let bakerTamUv = ${p.tam?.tamUv ?? 'v_bakerUv'};
let bakerNormal = normalW;
let bakerKeyLight = baker_key_light(viewDirectionW);
var bakerColor = finalColor.rgb;
${onOutgoing}
finalColor = vec4f(bakerColor, finalColor.a);
}`;
		if (p.curvature) outgoing += `
if (u_baker_curvature_on > 0.5) {
	// diverging map: blue concave, white flat, red convex; curvature * meanLength, saturating at +-1
	let k = clamp(${p.curvature.value} / u_bakerCurvatureScale, -1.0, 1.0);
	var bakerView = select(mix(vec3f(1.0), vec3f(0.05, 0.2, 0.85), -k), mix(vec3f(1.0), vec3f(0.85, 0.1, 0.05), k), k > 0.0);
	bakerView *= 0.35 + 0.65 * clamp(dot(normalW, baker_key_light(viewDirectionW)), 0.0, 1.0);
	finalColor = vec4f(bakerView, finalColor.a);
}`;
		if (outgoing) code[OUTGOING_POINT] = `${outgoing}\nfinalColor=applyImageProcessing(finalColor);`;
		return code;
	}

	partCode(shaderType) {
		const p = this.parts;
		const attributes = this.attributes();
		// injected after Babylon turned attribute/varying into GLSL ES 3.00's in/out: written as in/out here
		const io = shaderType === 'vertex' ? 'out' : 'in';
		const varyings = attributes.map(([kind, size]) => `${io} ${glslType(size)} v_${kind};`).join('\n') + `\n${io} vec2 v_bakerUv;`;
		if (shaderType === 'vertex') {
			return {
				CUSTOM_VERTEX_DEFINITIONS: `${attributes.map(([kind, size]) => `in ${glslType(size)} ${kind};`).join('\n')}
${varyings}`,
				CUSTOM_VERTEX_MAIN_END: `${attributes.map(([kind, , v]) => `v_${kind} = ${v ?? kind};`).join('\n')}
#ifdef UV1
v_bakerUv = uv;
#else
v_bakerUv = vec2(0.0);
#endif`,
			};
		}
		const samplers = Object.values(p).flatMap((x) => Object.keys(x.samplers || {})).map((s) => `uniform sampler2D ${s};`).join('\n');
		const modules = [...new Set(Object.values(p).map((x) => x.glsl).filter(Boolean))].join('\n');
		const structs = Object.values(p).map((x) => x.structs || '').join('\n');
		const diffuse = [];
		// BAKER_normal_blur: one N.L per channel from the blurred maps (the specular term keeps the bump's normal)
		if (p.normalBlur) diffuse.push(`vec3 bakerNdotL = vec3(dotNL);
if (u_baker_normalBlur_on > 0.5) {
	bakerNdotL = baker_normal_blur_ndotl(bakerNormalRed, bakerNormalGreen, bakerNormalBlue, bakerL);
	f = clamp(bakerNdotL, 0.0, 1.0);
	bakerReplaced = true;
}`);
		const skin = (normals) => `baker_skin_diffuse(${p.skin.struct}, u_bakerSkinLut, ${normals}, bakerL, bakerSkinK)`;
		// the curvature of the surface (geometricNormalW: before the bump) along L
		if (p.skin) diffuse.push(`if (u_baker_skin_on > 0.5) {
	float bakerSkinK = ${p.skin.curvature('geometricNormalW', 'bakerL')};
	f = ${p.normalBlur ? `u_baker_normalBlur_on > 0.5
		? baker_skin_diffuse_normals(${p.skin.struct}, u_bakerSkinLut, bakerNdotL, bakerSkinK)
		: ${skin('normalW, normalW')}` : skin('normalW, normalW')};
	bakerReplaced = true;
}`);
		if (p.toon) diffuse.push(`if (u_baker_toon_on > 0.5) {
	// the ramp indexed by the lit shade so far (N.L, or the skin LUT's luminance mapped back to -1..1)
	float nl = ${p.skin ? 'u_baker_skin_on > 0.5 ? 2.0 * dot(f, vec3(0.2126, 0.7152, 0.0722)) - 1.0 : dotNL' : 'dotNL'};
	f = vec3(u_bakerToonXtoon < 0.5 ? baker_toon_ramp(u_bakerToonRamp, nl)
			: baker_xtoon(u_bakerToonRamp, nl, u_bakerToonXtoon < 1.5
			? baker_xtoon_detail_depth(abs((view * vec4(vPositionW, 1.0)).z), u_bakerToonDepthRange.x, u_bakerToonDepthRange.y)
			: baker_xtoon_detail_orientation(normalW, viewDirectionW, u_bakerToonOrientationPower)));
	bakerReplaced = true;
}`);
		const code = {
			CUSTOM_FRAGMENT_DEFINITIONS: `${modules}\n${structs}\n${samplers}\n${varyings}\n${KEY_LIGHT}`,
		};
		const afterLights = surfaceStages(p, 'afterLights');
		if (diffuse.length || p.translucency || afterLights || p.cards) {
			// after Babylon's own diffuse of light $1 (directional, point or spot): f replaces the clamped N.L
			code[LIGHT_POINT] = `info.diffuse=computeDiffuseLighting(preInfo,diffuse$1.rgb);
{
	vec3 bakerL = preInfo.L;
	float dotNL = preInfo.NdotLUnclamped;
	vec3 f = vec3(clamp(dotNL, 0.0, 1.0));
	bool bakerReplaced = false;
	${diffuse.join('\n\t')}
	// like @baker/three: the change to Lambert's term, and the translucency, on the base colour (not metal-weighted)
	if (bakerReplaced) bakerLambert += (f - vec3(clamp(dotNL, 0.0, 1.0))) * (preInfo.attenuation / PI) * diffuse$1.rgb;
	${p.translucency ? `bakerDirect += u_baker_translucency_on * preInfo.attenuation * diffuse$1.rgb *
		baker_translucency(${p.translucency.struct}, normalW, viewDirectionW, bakerL, ${p.translucency.thickness});` : ''}
	${p.cards ? `if (u_baker_cards_on > 0.5) bakerCards += (preInfo.attenuation / PI) * (baker_hair_cards_shade(
		albedoOpacityOut.surfaceAlbedo, bakerCardsT, normalW, bakerL, viewDirectionW, diffuse$1.rgb, bakerCardsData.g,
		bakerCardsData.b, 40.0, 0.1, 0.4) - clamp(dotNL, 0.0, 1.0) * diffuse$1.rgb * albedoOpacityOut.surfaceAlbedo);` : ''}
#ifdef DIRLIGHT$1
	bakerSun += clamp(dotNL, 0.0, 1.0) * (preInfo.attenuation / PI) * diffuse$1.rgb;
#endif
}`;
		}
		code.CUSTOM_FRAGMENT_BEFORE_LIGHTS = 'vec3 bakerDirect = vec3(0.0);\nvec3 bakerLambert = vec3(0.0);\nvec3 bakerSun = vec3(0.0);' +
			'\nvec3 bakerCards = vec3(0.0);' + (p.cards ? CARDS_FRAME : '') + (p.normalBlur ? NORMAL_BLUR : '');
		// the change to Lambert's term on the base colour (skin, toon: as @baker/three does); with blurred diffuse
		// normals on Babylon's diffuse albedo (surfaceAlbedo: metal-weighted), so a metal shows no change
		const albedo = p.normalBlur ? 'surfaceAlbedo.rgb' : 'albedoOpacityOut.surfaceAlbedo';
		code.CUSTOM_FRAGMENT_BEFORE_FINALCOLORCOMPOSITION = 'finalDiffuse += bakerDirect * albedoOpacityOut.surfaceAlbedo * vLightingIntensity.x;' +
			`\nfinalDiffuse += bakerLambert * ${albedo} * vLightingIntensity.x;` +
			'\nfinalDiffuse += bakerCards * vLightingIntensity.x;' +
			// the parts both hosts share (runtime-shaders/hosts/web/surface_*.glsl) in a block defining their names
			(afterLights && `
{
vec3 bakerWorldPosition = vPositionW;
vec3 bakerSunLight = bakerSun * albedoOpacityOut.surfaceAlbedo * vLightingIntensity.x;
vec3 bakerDiffuse = finalDiffuse;
vec3 bakerOtherLight = vec3(0.0);  // the specular light (the hemispheric light is in finalDiffuse)
#ifdef SPECULARTERM
bakerOtherLight += finalSpecularScaled;
#endif
#ifdef REFLECTION
bakerOtherLight += finalIrradiance;
#endif
${afterLights}
finalDiffuse = bakerDiffuse;
}`);
		let outgoing = '';
		const onOutgoing = surfaceStages(p, 'outgoing');
		if (onOutgoing) outgoing += `
{
vec2 bakerUv = v_bakerUv;
vec3 bakerNormal = normalW;
vec3 bakerKeyLight = baker_key_light(viewDirectionW);
vec3 bakerColor = finalColor.rgb;
${onOutgoing}
finalColor.rgb = bakerColor;
}`;
		if (p.curvature) outgoing += `
if (u_baker_curvature_on > 0.5) {
	// diverging map: blue concave, white flat, red convex; curvature * meanLength, saturating at +-1
	float k = clamp(${p.curvature.value} / u_bakerCurvatureScale, -1.0, 1.0);
	finalColor.rgb = k > 0.0 ? mix(vec3(1.0), vec3(0.85, 0.1, 0.05), k) : mix(vec3(1.0), vec3(0.05, 0.2, 0.85), -k);
	finalColor.rgb *= 0.35 + 0.65 * clamp(dot(normalW, baker_key_light(viewDirectionW)), 0.0, 1.0);
}`;
		// linear colour, before Babylon's image processing (tone mapping, exposure, gamma)
		if (outgoing) code[OUTGOING_POINT] = `${outgoing}\nfinalColor=applyImageProcessing(finalColor);`;
		return code;
	}
}

/**
 * A glTF loader extension for a surface technique: for every material with the extension, build(ext, mesh, json
 * material) returns the part (or null when this primitive cannot draw it) that the material's BakerSurfacePlugin adds.
 */
export function surfaceExtension(technique, extensionName, build) {
	return class {
		constructor(loader, options = {}) {
			this.name = extensionName;
			this.enabled = true;
			this.order = 200;
			this.loader = loader;
			this.options = options;
			this.shaders = options.shaders || {};
		}
		dispose() { this.loader = null; }
		async onReady() {
			const materials = this.loader.gltf.materials || [];
			const done = new Set();
			for (const { primitive, mesh } of loadedPrimitives(this.loader)) {
				const ext = primitive.material !== undefined && materials[primitive.material]?.extensions?.[extensionName];
				const material = mesh.material;
				if (!ext || !material || done.has(material) || material.getClassName() !== 'PBRMaterial') continue;
				if (primitive.extensions?.BAKER_edges?.finsOf !== undefined || primitive.extensions?.BAKER_fur?.finsOf !== undefined) continue;
				const part = await build.call(this, ext, mesh, primitive, material);
				if (!part) continue;
				done.add(material);
				const plugin = BakerSurfacePlugin.of(material);
				plugin.add(technique, part);
				controls(this.loader).add(technique, (on) => plugin.setEnabled(technique, on));
			}
		}
	};
}
