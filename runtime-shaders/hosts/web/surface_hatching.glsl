// BAKER_tonal_art_map's part of a web host's surface (@baker/three, @baker/babylon), on the outgoing colour: Praun
// et al. hatching (baker_hatching.glsl), the tone from the key light, multiplying the lit colour.
// The host defines, around it: bakerUv (vec2, TEXCOORD_0), bakerNormal (vec3), bakerKeyLight (vec3: towards the key
// light, in bakerNormal's space) and bakerColor (vec3, read and written: the lit colour, linear). When the TAM reads
// another set (texCoord > 0: baker's stroke parameterization, issue 38), the host's tam part defines BAKER_TAM_UV as
// the varying that carries it.
if (u_baker_tam_on > 0.5) {
#ifdef BAKER_TAM_UV
	vec2 tile = baker_tam_coord(BAKER_TAM_UV, u_bakerTamScale, u_bakerTamFinestSize);
#else
	vec2 tile = baker_tam_coord(bakerUv, u_bakerTamScale, u_bakerTamFinestSize);
#endif
	float lod = baker_tam_lod(dFdx(tile), dFdy(tile), u_bakerTamFinestSize, u_bakerTamLevels);
	float darkness = baker_hatching_darkness(bakerNormal, bakerKeyLight, 1.0);
	bakerColor *= baker_hatching(u_bakerTam012, u_bakerTam345, tile, lod, darkness, u_bakerTamTonesA, u_bakerTamTonesB);
}
