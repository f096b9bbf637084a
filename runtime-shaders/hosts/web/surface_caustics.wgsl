// BAKER_caustics' part of a web host's surface on WebGPU (@baker/babylon's WGSL material plugin), after the lights:
// the WGSL twin of surface_caustics.glsl (baker_caustics.wgsl; each sampler2D argument a texture and its sampler).
// The host defines, around it: bakerWorldPosition (vec3f, world space), bakerSunLight (vec3f: the directional
// lights' Lambert light on the base colour), bakerDiffuse (var vec3f, read and written: the direct diffuse light),
// bakerOtherLight (vec3f: the rest of the pixel's light, indirect and specular, as far as the host knows it), and the
// part's uniforms under their own names.
if (u_baker_caustics_on > 0.5) {
	let bakerCausticsUv = baker_caustics_uv(bakerWorldPosition, u_bakerCausticsProjection, u_bakerCausticsWaterLevel,
		u_bakerCausticsDepth, u_bakerCausticsTileSize);
	let bakerCausticsFade = baker_caustics_fade(baker_caustics_depth(bakerWorldPosition, u_bakerCausticsWaterLevel),
		u_bakerCausticsDepth, u_bakerCausticsFadeDistance);
	let bakerCausticsE = baker_caustics_irradiance(u_bakerCausticsFirst, u_bakerCausticsFirstSampler,
		u_bakerCausticsNext, u_bakerCausticsNextSampler, bakerCausticsUv, u_bakerCausticsBlend, u_bakerCausticsScale, 1.0);
	let bakerCausticsLit = baker_caustics_apply(bakerDiffuse, bakerSunLight, bakerCausticsE, u_bakerCausticsStrength,
		bakerCausticsFade);
	bakerDiffuse = baker_caustics_headroom(bakerDiffuse, bakerCausticsLit, bakerOtherLight);
}
