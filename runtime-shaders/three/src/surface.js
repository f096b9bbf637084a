// The surface techniques (BAKER_thickness, BAKER_skin_lut, BAKER_toon_ramp, BAKER_tonal_art_map, BAKER_curvature,
// BAKER_caustics, BAKER_hair_cards, BAKER_normal_blur):
// the plugins of those extensions each build one part (GLSL module, uniforms, attributes); BakerSurface composes
// the parts of one material in a single onBeforeCompile.
import { surfaceStages } from '@baker/shared';
import { DIRECTIONAL_DIFFUSE, TECHNIQUES, controls, sceneMaterials } from './common.js';

// ------------------------------------------------------------------------------------------------ surface
// The surface techniques of one material, composed in one onBeforeCompile: per directional light the Lambert term
// max(N.L, 0) is replaced by f (vec3): per-channel N.L of the blurred diffuse normals, skin LUT (Penner) and/or toon
// ramp of it; translucency is added; caustics
// redistribute the directional lights' Lambert light; hatching multiplies the outgoing light by the TAM brightness;
// the curvature view replaces it.
export class BakerSurface {
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
		// [name, GLSL type, optional vertex-stage expression of the varying (default: the attribute itself)]
		for (const p of Object.values(this.parts)) for (const entry of p.attributes || []) names.set(entry[0], entry);
		return [...names.values()].sort((a, b) => (a[0] < b[0] ? -1 : 1));
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
		const world = Object.values(p).some((x) => x.worldPosition);
		const varyings = attributes.map(([name, type]) => `varying ${type} vBaker${name};`).join('\n') +
			(world ? '\nvarying vec3 vBakerWorldPosition;' : '');
		shader.vertexShader = shader.vertexShader
			.replace('#include <common>', `#include <common>\n${attributes.map(declareAttribute).join('\n')}
${varyings}\nvarying vec2 vBakerUv;`)
			.replace('#include <begin_vertex>', `#include <begin_vertex>\n${attributes.map(([n, , v]) => `vBaker${n} = ${v ?? n};`).join('\n')}
vBakerUv = uv;`)
			.replace('#include <worldpos_vertex>', `#include <worldpos_vertex>\n${world ? WORLD_POSITION : ''}`);

		const diffuse = [];
		// BAKER_normal_blur: one N.L per channel from the blurred maps (the specular term keeps normalMap's normal)
		if (p.normalBlur) diffuse.push(`vec3 bakerNdotL = vec3(dotNL);
		if (u_baker_normalBlur_on > 0.5) {
			bakerNdotL = baker_normal_blur_ndotl(bakerNormalRed, bakerNormalGreen, bakerNormalBlue, L);
			f = clamp(bakerNdotL, 0.0, 1.0);
		}`);
		// the curvature of the surface (nonPerturbedNormal: before the normal map) along L
		if (p.skin) diffuse.push(`if (u_baker_skin_on > 0.5) {
			float bakerSkinK = ${p.skin.curvature('nonPerturbedNormal', 'L')};
			${p.normalBlur ? `f = u_baker_normalBlur_on > 0.5
				? baker_skin_diffuse_normals(${p.skin.struct}, u_bakerSkinLut, bakerNdotL, bakerSkinK)
				: baker_skin_diffuse(${p.skin.struct}, u_bakerSkinLut, normal, normal, L, bakerSkinK);`
		: `f = baker_skin_diffuse(${p.skin.struct}, u_bakerSkinLut, normal, normal, L, bakerSkinK);`}
		}`);
		if (p.toon) diffuse.push(`if (u_baker_toon_on > 0.5) {
			// the ramp indexed by the lit shade so far (N.L, or the skin LUT's luminance mapped back to -1..1)
			float nl = ${p.skin ? 'u_baker_skin_on > 0.5 ? 2.0 * dot(f, vec3(0.2126, 0.7152, 0.0722)) - 1.0 : dotNL' : 'dotNL'};
			f = vec3(u_bakerToonXtoon < 0.5 ? baker_toon_ramp(u_bakerToonRamp, nl)
				: baker_xtoon(u_bakerToonRamp, nl, u_bakerToonXtoon < 1.5
					? baker_xtoon_detail_depth(-vViewPosition.z, u_bakerToonDepthRange.x, u_bakerToonDepthRange.y)
					: baker_xtoon_detail_orientation(normal, normalize(vViewPosition) * -1.0, u_bakerToonOrientationPower)));
		}`);
		// the change to Lambert's term goes on the base colour (skin, toon: as Babylon's plugin does); with blurred
		// diffuse normals on the material's diffuse albedo (metal-weighted), so a metal, which has no diffuse term,
		// shows no change
		const albedo = p.normalBlur ? 'material.diffuseContribution' : 'diffuseColor.rgb';
		// the parts both hosts share (runtime-shaders/hosts/web/surface_*.glsl) in a block defining their names
		const afterLights = surfaceStages(p, 'afterLights');
		const shared = afterLights && `{
vec3 bakerWorldPosition = vBakerWorldPosition;
vec3 bakerSunLight = bakerSun;
vec3 bakerDiffuse = reflectedLight.directDiffuse;
vec3 bakerOtherLight = reflectedLight.indirectDiffuse + reflectedLight.directSpecular + reflectedLight.indirectSpecular;
${afterLights}
reflectedLight.directDiffuse = bakerDiffuse;
}`;
		let lights = '';
		if (diffuse.length || p.translucency || afterLights || p.cards) {  // normal blur: one of `diffuse`
			lights = `${p.normalBlur ? NORMAL_BLUR : ''}
vec3 bakerSun = vec3(0.0);  // Lambert light of the directional lights (the sun) on the base colour
${p.cards ? CARDS_FRAME : ''}
#if NUM_DIR_LIGHTS > 0
	for (int i = 0; i < NUM_DIR_LIGHTS; i++) {
		vec3 L = directionalLights[i].direction;  // view space, towards the light
		float dotNL = dot(normal, L);
		vec3 f = vec3(saturate(dotNL));
		${diffuse.join('\n\t\t')}
		reflectedLight.directDiffuse += directionalLights[i].color * BRDF_Lambert(${albedo}) * (f - vec3(saturate(dotNL)));
		${p.translucency ? `reflectedLight.directDiffuse += u_baker_translucency_on * diffuseColor.rgb * directionalLights[i].color *
			baker_translucency(${p.translucency.struct}, normal, normalize(vViewPosition), L, vBaker${p.translucency.attribute});` : ''}
		${p.cards ? CARDS_LIGHT : ''}
		bakerSun += directionalLights[i].color * BRDF_Lambert(diffuseColor.rgb) * saturate(dotNL);
	}
#endif
${shared}`;
		}
		let outgoing = '';
		const onOutgoing = surfaceStages(p, 'outgoing');
		if (onOutgoing) outgoing += `
	{
	vec2 bakerUv = vBakerUv;
	vec3 bakerNormal = normal;
	vec3 bakerKeyLight = baker_key_light(vec3(0.0, 0.0, 1.0));
	vec3 bakerColor = outgoingLight;
	${onOutgoing}
	outgoingLight = bakerColor;
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

// a part's vertex attribute; three declares uv1..uv3 itself when a map reads them (USE_UV<n>)
function declareAttribute([name, type]) {
	const declaration = `attribute ${type} ${name};`;
	return /^uv[1-3]$/.test(name) ? `#ifndef USE_${name.toUpperCase()}\n${declaration}\n#endif` : declaration;
}

// the world position of the vertex (after skinning and morphs), for techniques projected in world space
const WORLD_POSITION = `vec4 bakerWorld = vec4(transformed, 1.0);
#ifdef USE_BATCHING
bakerWorld = batchingMatrix * bakerWorld;
#endif
#ifdef USE_INSTANCING
bakerWorld = instanceMatrix * bakerWorld;
#endif
vBakerWorldPosition = (modelMatrix * bakerWorld).xyz;`;

// normal blur: the three diffuse normals in view space, through the normal map's frame (tbn) at its UV
const NORMAL_BLUR = `
vec3 bakerNormalRed = normalize(tbn * baker_normal_blur_decode(texture2D(u_bakerNormalBlurRed, vNormalMapUv).rgb,
	u_bakerNormalBlurFlipY));
vec3 bakerNormalGreen = normalize(tbn * baker_normal_blur_decode(texture2D(u_bakerNormalBlurGreen, vNormalMapUv).rgb,
	u_bakerNormalBlurFlipY));
vec3 bakerNormalBlue = normalize(tbn * baker_normal_blur_decode(texture2D(u_bakerNormalBlurBlue, vNormalMapUv).rgb,
	u_bakerNormalBlurFlipY));`;

// hair cards: the strand direction from the flow texture in the card's frame (from screen-space derivatives: three.js
// passes no TANGENT without a normal map), then per directional light Kajiya-Kay along it instead of Lambert
// (baker_hair_cards.glsl); the alpha test is the material's own (alphaTest = alphaCutoff)
const CARDS_FRAME = `
vec3 bakerCardsData = texture(u_bakerCardsData, vBakerUv).rgb;
vec3 bakerCardsT = baker_hair_cards_flow(texture(u_bakerCardsFlow, vBakerUv).rgb, normal,
	baker_hair_cards_frame(normal, dFdx(-vViewPosition), dFdy(-vViewPosition), dFdx(vBakerUv), dFdy(vBakerUv)));`;
const CARDS_LIGHT = `if (u_baker_cards_on > 0.5) {
			reflectedLight.directDiffuse += RECIPROCAL_PI * baker_hair_cards_shade(diffuseColor.rgb, bakerCardsT, normal, L,
				normalize(vViewPosition), directionalLights[i].color, bakerCardsData.g, bakerCardsData.b, 40.0, 0.1, 0.4)
				- directionalLights[i].color * BRDF_Lambert(diffuseColor.rgb) * saturate(dotNL);
		}`;

export function surfacePlugin(name, build) {
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
