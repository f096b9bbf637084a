// The runtime descriptor of every technique: what a web host needs to know of it, once. @baker/three,
// @baker/babylon, the viewer and the tests read these entries instead of keeping their own tables; a host file
// holds only what its engine does differently. Plain data (no engine import, no functions), so a test can print it
// as JSON (tests/test_runtime_descriptors.py checks the READMEs' runtime tables against it).
//
// Per entry:
// - name: the technique (the extension without BAKER_, as baker's technique folders name it);
// - extension, on: the glTF extension and the glTF objects it sits on ('material', 'mesh.primitive', 'node', 'glTF');
// - kind: 'surface' (a part of the loader's own PBR material) or 'geometry' (meshes of its own);
// - modules: the runtime-shaders/ files, by shading language (`key`: the name under which a host's options.shaders
//   passes the GLSL as text; `wgsl`: the WGSL twin, under the same key in a WebGPU host's options.wgsl);
// - switches: the on/off names published in gltf.userData.baker / the root's metadata.baker, in display order
//   (defaultOff: a debug view, off until asked for);
// - attributes: custom vertex attributes (`from`: the extension property naming it, else `name` itself);
// - textures: samplers bound from the extension's texture infos (`from`: its property; `sampling`: 'data' is linear,
//   clamped, no mips, no sRGB decode; 'file' keeps the file's sampler, repeating and mipmapped);
// - uniforms: the uniforms a surface part binds from the extension (geometry techniques set theirs in their host
//   file), per uniform its GLSL type and where its value comes from: `from` (an extension property, or a list of
//   them, the first present wins; 'a.0.b' walks into arrays), `default`, `enum` (a string property to a number),
//   `slice` ([begin, end] of an array), `count` (the length of an array property), `compute` (a formula of
//   values.js COMPUTED, by name);
// - struct: the module's parameter struct, built in GLSL from these uniforms in this order;
// - surface: a surface part written once for both hosts, `stage` (runtime-shaders/hosts/web/<stage>.glsl, in
//   stages.js) injected at `point`: 'afterLights' (reads bakerWorldPosition, bakerSunLight; writes bakerDiffuse) or
//   'outgoing' (reads bakerUv, bakerNormal, bakerKeyLight; writes bakerColor), names each host's surface.js defines;
// - options: the defaults of options.<name> (a host's user overrides);
// - readme: the technique's rows in the READMEs' runtime tables, the cells the descriptor cannot give:
//   `shaders` (runtime-shaders/README.md's module table: technique, extension, twin and tests), `three` (one
//   [extension, plugin, what it does] per switch), `babylon` ([extension, technique (switch), Babylon.js object] per
//   switch and per extension it also reads), `gltfTransform` (the whole rows of its extensions);
//   `node runtime-shaders/shared/tools/readme_tables.mjs` writes the tables (module, switch and GLSL-module cells
//   from the descriptor), `--check` (tests/test_runtime_descriptors.py) fails when a README differs.

export const RUNTIMES = [
	{
		name: 'thickness', extension: 'BAKER_thickness', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_translucency.glsl', key: 'translucency', wgsl: 'baker_translucency.wgsl' },
		switches: [{ name: 'translucency', label: 'translucency' }],
		attributes: [{ name: 'thickness', from: 'attribute', type: 'float' }],
		textures: [],
		struct: {
			type: 'BakerThickness',
			fields: ['u_bakerThAttenuation', 'u_bakerThDistortion', 'u_bakerThPower', 'u_bakerThScale', 'u_bakerThAmbient', 'u_bakerThColor'],
		},
		uniforms: [
			{ name: 'u_bakerThAttenuation', type: 'float', from: ['attenuationDistance', 'meanThickness'], default: 1 },
			{ name: 'u_bakerThDistortion', type: 'float', from: 'distortion', default: 0.2 },
			{ name: 'u_bakerThPower', type: 'float', from: 'power', default: 4 },
			{ name: 'u_bakerThScale', type: 'float', from: 'scale', default: 1 },
			{ name: 'u_bakerThAmbient', type: 'float', from: 'ambient', default: 0 },
			{ name: 'u_bakerThColor', type: 'vec3', from: 'subsurfaceColor', default: [1, 1, 1] },
		],
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["local-thickness translucency, Barré-Brisebois & Bouchard GDC 2011, RTR4 eq. 14.30", "[`BAKER_thickness`](../schemas/BAKER_thickness/README.md) + `KHR_materials_volume`", "`tests/gl/twins_translucency.py`, `tests/gl/test_translucency.py`"],
			three: [
				["`BAKER_thickness`", "`BakerThicknessPlugin`", "adds back-lit translucency (`baker_translucency`, GDC 2011 form of RTR4 eq. 14.30) per directional light, from `_THICKNESS`"],
			],
			babylon: [
				["`BAKER_thickness`", "back-lit translucency (`translucency`), GDC 2011 form of RTR4 eq. 14.30 per punctual light", "`BakerSurfacePlugin` (a `MaterialPluginBase`) on the loader's `PBRMaterial`; `_THICKNESS` read from its accessor"],
			],
			gltfTransform: [
				["`BAKER_thickness`", "`BakerThickness`", "`Thickness` (material)", "none (the thickness texture is `KHR_materials_volume`'s, carried by `KHRONOS_EXTENSIONS`)"],
			],
		},
	},
	{
		name: 'skin_lut', extension: 'BAKER_skin_lut', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_skin.glsl', key: 'skin', wgsl: 'baker_skin.wgsl' },
		switches: [{ name: 'skin', label: 'pre-integrated skin' }],
		// the mean curvature, or BAKER_curvature's principal curvatures and direction (baker's names)
		attributes: [
			{ name: 'curvature', from: 'curvatureAttribute', type: 'float' },
			{ name: '_PRINCIPAL_CURVATURES', type: 'vec2' },
			{ name: '_PRINCIPAL_DIRECTION', type: 'vec3' },
		],
		textures: [{ name: 'u_bakerSkinLut', from: 'lutTexture', sampling: 'data' }],
		struct: {
			type: 'BakerSkin',
			fields: ['u_bakerSkinCurvatureRange', 'u_bakerSkinCurvatureScale', 'u_bakerSkinPenumbraRange', 'u_bakerSkinNormalBlend',
				'u_bakerSkinWrap', 'u_bakerSkinScatterWidth', 'u_bakerSkinScatterColor'],
		},
		uniforms: [
			{ name: 'u_bakerSkinCurvatureRange', type: 'vec2', from: 'curvatureRange', default: [0.01, 1] },
			{ name: 'u_bakerSkinCurvatureScale', type: 'float', from: 'curvatureScale', default: 1 },
			{ name: 'u_bakerSkinPenumbraRange', type: 'vec2', from: 'penumbraWidthRange', default: [0.01, 1] },
			{ name: 'u_bakerSkinNormalBlend', type: 'vec3', from: 'normalBlend', default: [1, 0.5, 0.25] },
			{ name: 'u_bakerSkinWrap', type: 'float', from: 'wrap', default: 0.5 },
			{ name: 'u_bakerSkinScatterWidth', type: 'float', from: 'scatterWidth', default: 0.3 },
			{ name: 'u_bakerSkinScatterColor', type: 'vec3', from: 'scatterColor', default: [0.8, 0.25, 0.1] },
		],
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["pre-integrated skin (Penner 2011, RTR4 14.6.3): LUT by N.L and curvature (baked or `fwidth` estimate), penumbra LUT, per-channel normal blending; wrap lighting with a color shift (RTR4 14.6.1)", "[`BAKER_skin_lut`](../schemas/BAKER_skin_lut/README.md) + [`BAKER_curvature`](../schemas/BAKER_curvature/README.md)", "`tests/gl/twins_skin.py`, `tests/gl/test_skin.py` (functions and uniforms: see the BAKER_skin_lut README)"],
			three: [
				["`BAKER_skin_lut` (+ `BAKER_curvature`)", "`BakerSkinLutPlugin`", "replaces each directional light's Lambert term by Penner's pre-integrated LUT (`baker_skin_diffuse`) at the baked `_CURVATURE` (or the per-pixel `fwidth` estimate without it)"],
			],
			babylon: [
				["`BAKER_skin_lut` (+ `BAKER_curvature` attribute)", "pre-integrated skin (`skin`), Penner 2011: Lambert's N.L through the LUT by curvature", "same plugin, per light"],
			],
			gltfTransform: [
				["`BAKER_skin_lut`", "`BakerSkinLut`", "`SkinLut` (material)", "`lutTexture`, `penumbraTexture`, `curvatureTexture`"],
			],
		},
	},
	{
		name: 'toon_ramp', extension: 'BAKER_toon_ramp', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_toon.glsl', key: 'toon', wgsl: 'baker_toon.wgsl' },
		switches: [{ name: 'toon', label: 'toon ramp' }],
		attributes: [],
		textures: [{ name: 'u_bakerToonRamp', from: 'rampTexture', sampling: 'data' }],
		uniforms: [
			// a float: an int in Babylon's uniform block would differ in precision between the stages
			{ name: 'u_bakerToonXtoon', type: 'float', from: 'xtoon', default: 'none', enum: { none: 0, depth: 1, orientation: 2 } },
			{ name: 'u_bakerToonDepthRange', type: 'vec2', from: 'depthRange', default: [1, 100] },
			{ name: 'u_bakerToonOrientationPower', type: 'float', from: 'orientationPower', default: 1 },
		],
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["toon ramps, X-Toon (Barla et al. 2006), hue-preserving posterization, RTR4 15.1", "[`BAKER_toon_ramp`](../schemas/BAKER_toon_ramp/README.md)", "`tests/gl/twins_toon.py`, `tests/gl/test_hatching.py`"],
			three: [
				["`BAKER_toon_ramp`", "`BakerToonRampPlugin`", "the Lambert term through the baked ramp (`baker_toon_ramp`) or X-Toon map (`baker_xtoon`, depth or orientation detail); with skin on, indexed by the skin-lit shade"],
			],
			babylon: [
				["`BAKER_toon_ramp`", "toon ramp / X-Toon (`toon`) of the lit shade", "same plugin, per light"],
			],
			gltfTransform: [
				["`BAKER_toon_ramp`", "`BakerToonRamp`", "`ToonRamp` (material)", "`rampTexture`"],
			],
		},
	},
	{
		name: 'tonal_art_map', extension: 'BAKER_tonal_art_map', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_hatching.glsl', key: 'hatching', wgsl: 'baker_hatching.wgsl' },
		surface: { stage: 'surface_hatching', point: 'outgoing' },
		switches: [{ name: 'tam', label: 'hatching (TAM)' }],
		attributes: [],
		// the packed layout's two textures per level, uploaded as the mip levels of two textures (a host's own code)
		textures: [{ name: 'u_bakerTam012', from: 'levels' }, { name: 'u_bakerTam345', from: 'levels' }],
		uniforms: [
			{ name: 'u_bakerTamScale', type: 'float', from: ['scale', 'levels.0.size'] },
			{ name: 'u_bakerTamFinestSize', type: 'float', from: 'levels.0.size' },
			{ name: 'u_bakerTamLevels', type: 'float', from: 'levels', count: true },
			{ name: 'u_bakerTamTonesA', type: 'vec3', from: 'tones', slice: [0, 3] },
			{ name: 'u_bakerTamTonesB', type: 'vec3', from: 'tones', slice: [3, 6] },
		],
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["real-time hatching with tonal art maps (Praun et al. 2001; volume TAM, Webb et al. 2002), RTR4 15.3", "[`BAKER_tonal_art_map`](../schemas/BAKER_tonal_art_map/README.md)", "`tests/gl/twins_hatching.py`, `tests/gl/test_hatching.py`"],
			three: [
				["`BAKER_tonal_art_map` (packed)", "`BakerTonalArtMapPlugin`", "Praun et al. hatching (`baker_hatching`): the TAM levels uploaded as each texture's own mip chain (`tamTextures()`: `texture.mipmaps`, `LinearMipmapLinear`, no generated mips), LOD by `baker_tam_lod`, tone from the key light; multiplies the lit colour"],
			],
			babylon: [
				["`BAKER_tonal_art_map` (packed)", "TAM hatching (`tam`), Praun et al. 2001, tone from the first directional light", "same plugin, on the lit colour before image processing; the TAM levels are the textures' mip levels"],
			],
			gltfTransform: [
				["`BAKER_tonal_art_map`", "`BakerTonalArtMap`", "`TonalArtMap` (material)", "`levels[i].textures[j]` / `levels[i].texture`; the UV set (`texCoord`) is kept in each TextureInfo"],
			],
		},
	},
	{
		name: 'edges', extension: 'BAKER_edges', on: ['mesh.primitive'], kind: 'geometry',
		modules: { glsl: 'baker_edges.glsl', key: 'edges', wgsl: 'baker_edges.wgsl' },
		switches: [
			{ name: 'fins', label: 'edge fins' },
			{ name: 'outline', label: 'shell outline' },
			{ name: 'wireframe', label: 'wireframe', defaultOff: true },
		],
		attributes: [
			{ name: '_FIN_V0', type: 'vec3' }, { name: '_FIN_V1', type: 'vec3' }, { name: '_FIN_V2', type: 'vec3' },
			{ name: '_FIN_V3', type: 'vec3' }, { name: '_FIN_CORNER', type: 'float' }, { name: '_FIN_FLAGS', type: 'float' },
			{ name: 'outlineNormal', from: 'outlineNormal', default: '_OUTLINE_NORMAL', type: 'vec3' },
		],
		textures: [],
		uniforms: [],
		// line style: colours linear RGB, widths in pixels; classes: the fin classes drawn (1 contour, 2 ridge,
		// 4 valley, 8 boundary)
		options: { color: [0.02, 0.02, 0.03], finWidth: 2.5, outlineWidth: 3, wireframeWidth: 1.25,
			wireframeColor: [0.95, 0.75, 0.2], classes: 1 | 2 | 4 | 8 },
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["fins (McGuire & Hughes 2004), shell outline (RTR4 15.2.2), single-pass wireframe (Bærentzen et al. 2006)", "[`BAKER_edges`](../schemas/BAKER_edges/README.md) + `EXT_mesh_primitive_edge_visibility`", "`tests/gl/twins_edges.py`, `tests/gl/test_edges.py`"],
			three: [
				["`BAKER_edges` fin primitive", "`BakerEdgesPlugin`", "McGuire & Hughes fins: `baker_fin_classify` (contours, ridges, valleys, boundaries) and `baker_fin_position` (constant pixel width) in the vertex shader"],
				["`BAKER_edges` `_OUTLINE_NORMAL`", "`BakerEdgesPlugin`", "shell outline (RTR4 15.2.2): back faces pushed out by `baker_shell_position`, a constant pixel width; an open primitive (zero normals on its rims) with a single-sided material gets a depth-only back-face mesh (`baker outline occluder`, renderOrder 0.5, shell 0.75) so no ink shows through its openings"],
				["`BAKER_edges` `wireframeMask`", "`BakerEdgesPlugin`", "single-pass wireframe (Bærentzen et al. 2006, `baker_wireframe`) on a non-indexed copy with per-corner barycentrics; quad diagonals hidden by the mask"],
			],
			babylon: [
				["`BAKER_edges` fin primitive", "edge fins (`fins`), McGuire & Hughes 2004: contour, ridge, valley, boundary", "`ShaderMaterial` on the loaded fin mesh"],
				["`BAKER_edges.outlineNormal`", "shell outline (`outline`), RTR4 15.2.2", "a back-face shell mesh, `ShaderMaterial`; an open primitive (zero normals on its rims) with a single-sided material first gets a depth-only back-face mesh (`baker outline occluder`, `disableColorWrite`) so no ink shows through its openings"],
				["`BAKER_edges.wireframeMask`", "single-pass wireframe (`wireframe`, off by default), Bærentzen et al. 2006", "a non-indexed mesh with barycentrics, premultiplied `ShaderMaterial`"],
				["`EXT_mesh_primitive_edge_visibility`", "its visible edges as the wireframe's mask when `BAKER_edges` has none (or the file has only this extension)", "as above"],
			],
			gltfTransform: [
				["`BAKER_edges`", "`BakerEdges`", "`Edges` (primitive)", "accessors `edges`, `oppositeVertices`, `flags`, `dihedralAngles`, `wireframeMask`; on a fin primitive `finsOf` (Primitive); the source's `fins` is derived from it when writing"],
				["`EXT_mesh_primitive_edge_visibility`", "`EXTMeshPrimitiveEdgeVisibility`", "`EdgeVisibility` (primitive)", "accessors `visibility`, `silhouetteMates`, `lineStrings[i].indices`; `lineStrings[i].material` (Material)"],
			],
		},
	},
	{
		name: 'fur', extension: 'BAKER_fur', on: ['material', 'mesh.primitive'], kind: 'geometry',
		modules: { glsl: 'baker_fur.glsl', key: 'fur', wgsl: 'baker_fur.wgsl' },
		switches: [{ name: 'fur', label: 'fur shells + fins' }],
		attributes: [
			{ name: '_FIN_V0', type: 'vec3' }, { name: '_FIN_V1', type: 'vec3' }, { name: '_FIN_V2', type: 'vec3' },
			{ name: '_FIN_V3', type: 'vec3' }, { name: '_FIN_CORNER', type: 'float' }, { name: '_FUR_FIN_NORMAL', type: 'vec3' },
			{ name: '_FUR_FIN_UV', type: 'vec2' },
		],
		// one shell mesh per shell texture, the fin texture on the fin primitive (each as its coverageMips chain if any)
		textures: [{ name: 'u_texture', from: 'shellTextures', sampling: 'file' }, { name: 'u_texture', from: 'finTexture', sampling: 'data' }],
		uniforms: [],
		// finThreshold: |N.V| where the fins fade out
		options: { finThreshold: 0.4 },
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["fur shells and fins (Lengyel et al. 2001)", "[`BAKER_fur`](../schemas/BAKER_fur/README.md)", "`tests/gl/twins_fur.py`, `tests/gl/test_hair.py`"],
			three: [
				["`BAKER_fur`", "`BakerFurPlugin`", "Lengyel shells (one pass per shell texture, `baker_fur_shell_position` / `_shade`) and fins (`baker_fur_fin_position`, silhouette fade `baker_fur_fin_weight`); each texture with a `coverageMips` chain (Castaño 2010) is a `DataTexture` whose `mipmaps` are the KTX2's levels (uploaded as given, no generated mips) and is alpha-tested at its `alphaCutoff` (shells opaque with depth writes); without chains the shells are blended"],
			],
			babylon: [
				["`BAKER_fur`", "fur shells + fins (`fur`), Lengyel et al. 2001", "one shell mesh per shell texture, `ShaderMaterial` on the fur fin mesh; a texture with a `coverageMips` chain (Castaño 2010) is a `RawTexture` holding the KTX2's levels (created with mip storage, every level above 0 then uploaded from the chain with `engine.updateTextureData`) and alpha-tested at its `alphaCutoff` (shells opaque); without chains the shells are blended"],
			],
			gltfTransform: [
				["`BAKER_fur`", "`BakerFur`", "`Fur` (material), `FurFins` (fin primitive)", "`shellTextures[i]`, `finTexture`; `finsOf` (Primitive); the material's `fins` list is derived when writing"],
			],
		},
	},
	{
		name: 'hair', extension: 'BAKER_hair', on: ['mesh.primitive'], kind: 'geometry',
		modules: { glsl: 'baker_hair.glsl', key: 'hair', wgsl: 'baker_hair.wgsl' },
		switches: [{ name: 'hair', label: 'hair ribbons' }],
		attributes: [
			{ name: 'tangent', from: 'tangentAttribute', default: '_STRAND_TANGENT', type: 'vec3' },
			{ name: 'param', from: 'paramAttribute', default: '_STRAND_PARAM', type: 'float' },
		],
		textures: [],
		uniforms: [],
		// Kajiya-Kay's specular colour (linear RGB) and exponent (options.hair.shading: 'fibre', the default, draws
		// BAKER_hair_shading where the material has it); lod: the level of `lods` drawn at load
		options: { specular: [0.3, 0.28, 0.25], exponent: 60, lod: 0 },
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["hair ribbons (view-facing expansion, thin tip, pixel-coverage opacity), Kajiya-Kay, Scheuermann two-lobe, Marschner-style R/TT/TRT (RTR4 14.7); children from 3 guides (`baker_hair_offset_child`, `interpolation: \"offset\"`) and LODs drawn as prefixes (`baker_hair_lod_index_count`, `baker_hair_lod_width`)", "[`BAKER_hair`](../schemas/BAKER_hair/README.md)", "`tests/gl/twins_hair.py`, `tests/gl/test_hair.py`"],
			three: [
				["`BAKER_hair`", "`BakerHairPlugin`", "view-facing ribbons from `ribbonIndices` (ribbon vertex r = line vertex r/2, side r%2), extruded in the vertex shader (`baker_hair_ribbon_position`, TressFX pixel coverage); where the material has `BAKER_hair_shading`, shaded as fibres (`baker_hair_shading`: Chiang et al. 2016 from the file's tables, uploaded as half-float `DataTexture`s from their accessors, plus Zinke's dual scattering with the fibres toward each light from the strand's baked ambient cube, per-strand melanin, the rest-pose occlusion on the ambient term), else or with `options.hair.shading = 'kajiyaKay'` Kajiya-Kay; off shows glTF's plain lines. `lods` (from `baker guides`): `setHairLod(ribbons, k)` draws level k as a prefix of the ribbon indices with widths x `widthScale` (option `hairLod`: the level drawn at load)"],
			],
			babylon: [
				["`BAKER_hair`", "hair ribbons (`hair`), view-facing, pixel coverage; shaded as fibres where the material has `BAKER_hair_shading` (`baker_hair_shading.glsl` / `.wgsl`, the tables as half-float `RawTexture`s, dual scattering with the baked fibre counts, per-strand melanin, occlusion), else or with `options.hair.shading = 'kajiyaKay'` Kajiya-Kay", "a ribbon mesh (`ribbonIndices`) replacing the glTF lines, `ShaderMaterial` (WebGL2 and WebGPUEngine)"],
			],
			gltfTransform: [
				["`BAKER_hair`", "`BakerHair`", "`Hair` (primitive)", "accessors `widthScale`, `ribbonIndices`, `guides.ids`, `guides.weights`; `guides.primitive` (Primitive)"],
			],
		},
	},
	{
		name: 'text', extension: 'BAKER_text', on: ['node'], kind: 'geometry', uses: ['BAKER_glyph_atlas'],
		modules: { glsl: 'baker_text.glsl', key: 'text', wgsl: 'baker_text.wgsl' },
		switches: [{ name: 'text', label: 'MSDF text' }],
		attributes: [],
		// the atlas of BAKER_glyph_atlas.fonts[font]
		textures: [{ name: 'u_atlas', from: 'font', sampling: 'data' }],
		uniforms: [],
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["distance-field text (RTR4 15.5; Green 2007; Chlumsky MSDF/MTSDF): median, screen-pixel range, soft edge, outline, glow, drop shadow", "[`BAKER_glyph_atlas`](../schemas/BAKER_glyph_atlas/README.md), [`BAKER_text`](../schemas/BAKER_text/README.md)", "`tests/gl/twins_text.py`, `tests/gl/test_text.py`"],
			three: [
				["`BAKER_text` + `BAKER_glyph_atlas`", "`BakerTextPlugin` (`BakerGlyphAtlasPlugin`)", "the label's glyph quads drawn with `baker_text_shade` (MSDF median, screen-pixel range, outline, glow, shadow; premultiplied); off shows glTF's alpha-tested fallback"],
			],
			babylon: [
				["`BAKER_glyph_atlas` + `BAKER_text`", "MSDF text (`text`): fill, outline, glow, shadow", "premultiplied `ShaderMaterial` on the label's quads (off: glTF's alpha-tested fallback)"],
			],
			gltfTransform: [
				["`BAKER_glyph_atlas`", "`BakerGlyphAtlas`", "`GlyphAtlas` (root)", "per font: `texture` (a bare texture index; its sampler is kept), accessors `glyphs.unicode/advance/planeBounds/atlasBounds`, `kerning.pairs/advance`"],
				["`BAKER_text`", "`BakerText`", "`Text` (node)", "none (`font` indexes `BAKER_glyph_atlas.fonts`, which no transform reorders)"],
			],
		},
	},
	{
		name: 'caustics', extension: 'BAKER_caustics', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_caustics.glsl', key: 'caustics', wgsl: 'baker_caustics.wgsl' },
		surface: { stage: 'surface_caustics', point: 'afterLights' },
		switches: [{ name: 'caustics', label: 'caustics' }],
		attributes: [],
		// the two frames of the current time (GLSL ES 3.00 cannot index a sampler array with a variable)
		textures: [{ name: 'u_bakerCausticsFirst', from: 'frameTextures', sampling: 'file' },
			{ name: 'u_bakerCausticsNext', from: 'frameTextures', sampling: 'file' }],
		uniforms: [
			{ name: 'u_bakerCausticsBlend', type: 'float', default: 0 },
			{ name: 'u_bakerCausticsProjection', type: 'vec3', from: 'projectionDirection', default: [0, -1, 0] },
			{ name: 'u_bakerCausticsWaterLevel', type: 'float', from: 'waterLevel', default: 0 },
			{ name: 'u_bakerCausticsDepth', type: 'float', from: 'depth' },
			{ name: 'u_bakerCausticsTileSize', type: 'float', from: 'tileSize' },
			{ name: 'u_bakerCausticsScale', type: 'float', from: 'intensityScale' },
			{ name: 'u_bakerCausticsStrength', type: 'float', from: 'strength', default: 1 },
			{ name: 'u_bakerCausticsFadeDistance', type: 'float', from: 'fadeDistance', default: 1 },
		],
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["offline caustics as an animated light map (RTR4 14.5.3): world-space projection along the refracted sun, depth fade, two frames blended by time, the sunlit colour scaled by the irradiance", "[`BAKER_caustics`](../schemas/BAKER_caustics/README.md)", "`tests/gl/twins_caustics.py`, `tests/gl/test_caustics.py`"],
			three: [
				["`BAKER_caustics`", "`BakerCausticsPlugin`", "the baked caustic frames projected from the world position along `projectionDirection` (`baker_caustics_uv`), faded by depth (`baker_caustics_fade`); before each draw the two frames of the current time (`causticsFrame`, as `baker_caustics_frame`) are bound to two samplers and blended (`baker_caustics_irradiance`); the directional lights' Lambert light on the base colour is scaled by E (`baker_caustics_apply`). Clock: `options.caustics.time`, else the page's"],
			],
			babylon: [
				["`BAKER_caustics`", "animated caustics (`caustics`), RTR4 14.5.3: the frames projected from the world position along the refracted sun, faded by depth, scaling the directional lights' Lambert light on the base colour", "same plugin; at every bind the two frames of the current time go to its two samplers with their blend weight (GLSL ES cannot index a sampler array)"],
			],
			gltfTransform: [
				["`BAKER_caustics`", "`BakerCaustics`", "`Caustics` (material)", "`frameTextures[i]`"],
			],
		},
	},
	{
		name: 'hair_cards', extension: 'BAKER_hair_cards', on: ['material', 'mesh.primitive'], kind: 'surface',
		modules: { glsl: 'baker_hair_cards.glsl', key: 'cards', wgsl: 'baker_hair_cards.wgsl' },
		switches: [{ name: 'cards', label: 'hair cards (Kajiya-Kay)' }],
		attributes: [],
		textures: [{ name: 'u_bakerCardsData', from: 'dataTexture', sampling: 'data' },
			{ name: 'u_bakerCardsFlow', from: 'flowTexture', sampling: 'data' }],
		uniforms: [],
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["alpha-tested hair cards (RTR4 14.7.1): the alpha test, the flow texture decoded in the card's frame (TANGENT, or the derivative cotangent frame where a host has none), the depth offset, Kajiya-Kay along the flow with a per-strand shifted highlight and root darkening", "[`BAKER_hair_cards`](../schemas/BAKER_hair_cards/README.md)", "`tests/gl/twins_hair_cards.py`, `tests/gl/test_hair_cards.py`"],
			three: [
				["`BAKER_hair_cards`", "`BakerHairCardsPlugin`", "the loader's own material draws the cards alpha-tested (base colour, `alphaTest` = alphaCutoff, double-sided); with a `coverageMips` chain (Castaño 2010) the plugin replaces the material's `map` by a `DataTexture` whose `mipmaps` are the KTX2's levels (sRGB, no generated mips), so the loader's alpha test keeps the cards' coverage with distance; the plugin decodes the flow texture in the card's frame from screen-space derivatives (`baker_hair_cards_frame`: three.js passes no TANGENT without a normal map) and, per directional light, replaces Lambert's term by Kajiya-Kay along it (`baker_hair_cards_shade`, with the data texture's root-to-tip and strand random values). The viewer's `?distance=K` puts the camera K times farther"],
			],
			babylon: [
				["`BAKER_hair_cards`", "hair cards (`cards`), RTR4 14.7.1: Kajiya-Kay along the flow texture on the loader's alpha-tested PBR material", "same plugin; with a `coverageMips` chain (Castaño 2010) the material's `albedoTexture` becomes a `RawTexture` holding the KTX2's levels (`gammaSpace`, `hasAlpha`), so the loader's alpha test keeps the cards' coverage with distance; the flow decoded in the derivative frame of `vPositionW` and the UV; per light the change from Lambert's term to `baker_hair_cards_shade`"],
			],
			gltfTransform: [
				["`BAKER_hair_cards`", "`BakerHairCards`", "`HairCardsMaterial` (material), `HairCards` (cards primitive)", "`dataTexture`, `flowTexture`, `coverageMips[i].texture` / `.accessor` on the material; the card regions and first indices (accessors) on the primitive"],
			],
		},
	},
	{
		name: 'normal_blur', extension: 'BAKER_normal_blur', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_normal_blur.glsl', key: 'normalBlur', wgsl: 'baker_normal_blur.wgsl' },
		switches: [{ name: 'normalBlur', label: 'blurred diffuse normals' }],
		attributes: [],
		textures: [{ name: 'u_bakerNormalBlurRed', from: 'diffuseNormalTextures.0', sampling: 'file' },
			{ name: 'u_bakerNormalBlurGreen', from: 'diffuseNormalTextures.1', sampling: 'file' },
			{ name: 'u_bakerNormalBlurBlue', from: 'diffuseNormalTextures.2', sampling: 'file' }],
		uniforms: [],
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			shaders: ["per-channel diffuse normals blurred on the surface (Ma et al. 2007, Penner 2011, RTR4 14.6.2): decode, per-channel N.L and Lambert, Penner's smoothed-map blend, a derivative tangent frame; a stretch-scaled texture-space diffusion step (d'Eon & Luebke's 7 taps, RTR4 14.6.4); `baker_skin.glsl`'s `baker_skin_diffuse_normals` reads the LUT with the per-channel N.L", "[`BAKER_normal_blur`](../schemas/BAKER_normal_blur/README.md)", "`tests/gl/twins_normal_blur.py`, `tests/gl/test_normal_blur.py`"],
			three: [
				["`BAKER_normal_blur`", "`BakerNormalBlurPlugin`", "the diffuse term per channel from the three blurred maps (`baker_normal_blur_decode` at `vNormalMapUv` through three's normal-map `tbn`, its Y sign following `normalScale`), `baker_normal_blur_ndotl` replacing Lambert's N.L per light; with `BAKER_skin_lut` on the material the LUT reads that per-channel N.L (`baker_skin_diffuse_normals`); the specular term keeps `normalMap`"],
			],
			babylon: [
				["`BAKER_normal_blur`", "blurred diffuse normals (`normalBlur`), RTR4 14.6.2: Lambert's N.L per channel from the three maps, read at `vBumpUV` through the bump texture's `TBN`; with `BAKER_skin_lut`, the LUT by that N.L", "same plugin, per light; the specular term keeps the bump texture"],
			],
			gltfTransform: [
				["`BAKER_normal_blur`", "`BakerNormalBlur`", "`NormalBlur` (material)", "`diffuseNormalTextures[i]`, the smoothed and stretch maps"],
			],
		},
	},
	{
		name: 'curvature', extension: 'BAKER_curvature', on: ['material'], kind: 'surface',
		modules: {},
		switches: [{ name: 'curvature', label: 'curvature view', defaultOff: true }],
		attributes: [{ name: 'curvature', from: 'attribute', type: 'float' }],
		textures: [],
		// the false-colour scale: 4 x |mean curvature|, at least half the range's top
		uniforms: [{ name: 'u_bakerCurvatureScale', type: 'float', compute: 'curvatureScale' }],
		// the rows of the READMEs' runtime tables (tools/readme_tables.mjs writes them; see the header)
		readme: {
			three: [
				["`BAKER_curvature`", "`BakerCurvaturePlugin`", "diverging false-colour view of the baked mean curvature"],
			],
			babylon: [
				["`BAKER_curvature`", "false-colour curvature (`curvature`, off by default)", "same plugin"],
			],
			gltfTransform: [
				["`BAKER_curvature`", "`BakerCurvature`", "`Curvature` (material)", "`curvatureTexture` (Texture + TextureInfo)"],
			],
		},
	},
];

/** The descriptor of technique `name` (throws on an unknown name). */
export function runtime(name) {
	const found = RUNTIMES.find((r) => r.name === name);
	if (!found) throw new Error(`@baker/shared: no runtime descriptor named ${name}`);
	return found;
}

/** The descriptor of the technique a switch belongs to. */
export function runtimeOfSwitch(switchName) {
	return RUNTIMES.find((r) => r.switches.some((s) => s.name === switchName)) ?? null;
}
