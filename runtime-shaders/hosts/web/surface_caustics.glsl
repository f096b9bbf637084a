// BAKER_caustics' part of a web host's surface (@baker/three, @baker/babylon), after the lights: the directional
// lights' Lambert light on the base colour scaled by the irradiance of the two current frames (baker_caustics.glsl);
// browsers decode a gray PNG to equal RGB channels, so the frames are read as RGB whatever their colour type.
// The host defines, around it: bakerWorldPosition (vec3, world space), bakerSunLight (vec3: the directional lights'
// Lambert light on the base colour), bakerDiffuse (vec3, read and written: the direct diffuse light) and
// bakerOtherLight (vec3: the rest of the pixel's light, indirect and specular, as far as the host knows it). The light
// the caustic adds is compressed into the headroom above the pixel (baker_caustics_headroom), so it does not clip.
if (u_baker_caustics_on > 0.5) {
	vec2 bakerCausticsUv = baker_caustics_uv(bakerWorldPosition, u_bakerCausticsProjection, u_bakerCausticsWaterLevel,
		u_bakerCausticsDepth, u_bakerCausticsTileSize);
	float bakerCausticsFade = baker_caustics_fade(baker_caustics_depth(bakerWorldPosition, u_bakerCausticsWaterLevel),
		u_bakerCausticsDepth, u_bakerCausticsFadeDistance);
	vec3 bakerCausticsE = baker_caustics_irradiance(u_bakerCausticsFirst, u_bakerCausticsNext, bakerCausticsUv,
		u_bakerCausticsBlend, u_bakerCausticsScale, 1.0);
	vec3 bakerCausticsLit = baker_caustics_apply(bakerDiffuse, bakerSunLight, bakerCausticsE, u_bakerCausticsStrength,
		bakerCausticsFade);
	bakerDiffuse = baker_caustics_headroom(bakerDiffuse, bakerCausticsLit, bakerOtherLight);
}
