// BAKER_tonal_art_map's part of a web host's surface on WebGPU (@baker/babylon's WGSL material plugin), on the
// outgoing colour: the WGSL twin of surface_hatching.glsl (baker_hatching.wgsl).
// The host defines, around it: bakerUv (vec2f, TEXCOORD_0), bakerNormal (vec3f), bakerKeyLight (vec3f: towards the
// key light, in bakerNormal's space), bakerColor (var vec3f, read and written: the lit colour, linear), bakerTamUv
// (vec2f: the set the TAM tiles over, bakerUv unless texCoord names baker's stroke parameterization; the GLSL stage's
// BAKER_TAM_UV define) and the part's uniforms under their own names.
if (u_baker_tam_on > 0.5) {
	let tile = baker_tam_coord(bakerTamUv, u_bakerTamScale, u_bakerTamFinestSize);
	let lod = baker_tam_lod(dpdx(tile), dpdy(tile), u_bakerTamFinestSize, u_bakerTamLevels);
	let darkness = baker_hatching_darkness(bakerNormal, bakerKeyLight, 1.0);
	bakerColor *= baker_hatching(u_bakerTam012, u_bakerTam012Sampler, u_bakerTam345, u_bakerTam345Sampler, tile, lod,
		darkness, u_bakerTamTonesA, u_bakerTamTonesB);
}
