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
//   passes the GLSL as text; `wgsl`: the WGSL twin, none yet);
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
// - options: the defaults of options.<name> (a host's user overrides).

export const RUNTIMES = [
	{
		name: 'thickness', extension: 'BAKER_thickness', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_translucency.glsl', key: 'translucency', wgsl: null },
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
	},
	{
		name: 'skin_lut', extension: 'BAKER_skin_lut', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_skin.glsl', key: 'skin', wgsl: null },
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
	},
	{
		name: 'toon_ramp', extension: 'BAKER_toon_ramp', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_toon.glsl', key: 'toon', wgsl: null },
		switches: [{ name: 'toon', label: 'toon ramp' }],
		attributes: [],
		textures: [{ name: 'u_bakerToonRamp', from: 'rampTexture', sampling: 'data' }],
		uniforms: [
			// a float: an int in Babylon's uniform block would differ in precision between the stages
			{ name: 'u_bakerToonXtoon', type: 'float', from: 'xtoon', default: 'none', enum: { none: 0, depth: 1, orientation: 2 } },
			{ name: 'u_bakerToonDepthRange', type: 'vec2', from: 'depthRange', default: [1, 100] },
			{ name: 'u_bakerToonOrientationPower', type: 'float', from: 'orientationPower', default: 1 },
		],
	},
	{
		name: 'tonal_art_map', extension: 'BAKER_tonal_art_map', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_hatching.glsl', key: 'hatching', wgsl: null },
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
	},
	{
		name: 'edges', extension: 'BAKER_edges', on: ['mesh.primitive'], kind: 'geometry',
		modules: { glsl: 'baker_edges.glsl', key: 'edges', wgsl: null },
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
	},
	{
		name: 'fur', extension: 'BAKER_fur', on: ['material', 'mesh.primitive'], kind: 'geometry',
		modules: { glsl: 'baker_fur.glsl', key: 'fur', wgsl: null },
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
	},
	{
		name: 'hair', extension: 'BAKER_hair', on: ['mesh.primitive'], kind: 'geometry',
		modules: { glsl: 'baker_hair.glsl', key: 'hair', wgsl: null },
		switches: [{ name: 'hair', label: 'hair ribbons' }],
		attributes: [
			{ name: 'tangent', from: 'tangentAttribute', default: '_STRAND_TANGENT', type: 'vec3' },
			{ name: 'param', from: 'paramAttribute', default: '_STRAND_PARAM', type: 'float' },
		],
		textures: [],
		uniforms: [],
		// Kajiya-Kay's specular colour (linear RGB) and exponent; lod: the level of `lods` drawn at load
		options: { specular: [0.3, 0.28, 0.25], exponent: 60, lod: 0 },
	},
	{
		name: 'text', extension: 'BAKER_text', on: ['node'], kind: 'geometry', uses: ['BAKER_glyph_atlas'],
		modules: { glsl: 'baker_text.glsl', key: 'text', wgsl: null },
		switches: [{ name: 'text', label: 'MSDF text' }],
		attributes: [],
		// the atlas of BAKER_glyph_atlas.fonts[font]
		textures: [{ name: 'u_atlas', from: 'font', sampling: 'data' }],
		uniforms: [],
	},
	{
		name: 'caustics', extension: 'BAKER_caustics', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_caustics.glsl', key: 'caustics', wgsl: null },
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
	},
	{
		name: 'hair_cards', extension: 'BAKER_hair_cards', on: ['material', 'mesh.primitive'], kind: 'surface',
		modules: { glsl: 'baker_hair_cards.glsl', key: 'cards', wgsl: null },
		switches: [{ name: 'cards', label: 'hair cards (Kajiya-Kay)' }],
		attributes: [],
		textures: [{ name: 'u_bakerCardsData', from: 'dataTexture', sampling: 'data' },
			{ name: 'u_bakerCardsFlow', from: 'flowTexture', sampling: 'data' }],
		uniforms: [],
	},
	{
		name: 'normal_blur', extension: 'BAKER_normal_blur', on: ['material'], kind: 'surface',
		modules: { glsl: 'baker_normal_blur.glsl', key: 'normalBlur', wgsl: null },
		switches: [{ name: 'normalBlur', label: 'blurred diffuse normals' }],
		attributes: [],
		textures: [{ name: 'u_bakerNormalBlurRed', from: 'diffuseNormalTextures.0', sampling: 'file' },
			{ name: 'u_bakerNormalBlurGreen', from: 'diffuseNormalTextures.1', sampling: 'file' },
			{ name: 'u_bakerNormalBlurBlue', from: 'diffuseNormalTextures.2', sampling: 'file' }],
		uniforms: [],
	},
	{
		name: 'curvature', extension: 'BAKER_curvature', on: ['material'], kind: 'surface',
		modules: {},
		switches: [{ name: 'curvature', label: 'curvature view', defaultOff: true }],
		attributes: [{ name: 'curvature', from: 'attribute', type: 'float' }],
		textures: [],
		// the false-colour scale: 4 x |mean curvature|, at least half the range's top
		uniforms: [{ name: 'u_bakerCurvatureScale', type: 'float', compute: 'curvatureScale' }],
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
