// BAKER_hair_shading for the web runtimes (schemas/BAKER_hair_shading): what a host needs to draw a hair material
// with runtime-shaders/baker_hair_shading.glsl / .wgsl: the fibre parameters of the material (the module's
// BakerHairShading struct, field for field) and the three tables of the root extension it names, as half-float
// RGBA texel arrays (the accessors' UNSIGNED_SHORT elements are the halves' bits). No engine import: each runtime
// reads the accessors and uploads the tables itself.
export const BAKER_HAIR_SHADING = 'BAKER_hair_shading';

// Chiang et al. 2016's map from longitudinal roughness to d'Eon's variance v per lobe (R, TT, TRT, residual), as
// baker.techniques.hair_shading.kernel.longitudinal_variances writes it.
export function longitudinalVariances(betaM) {
	const v = (0.726 * betaM + 0.812 * betaM ** 2 + 3.7 * betaM ** 20) ** 2;
	return [v, 0.25 * v, 4 * v, 4 * v];
}

/**
 * The BAKER_hair_shading of glTF material `materialIndex` of document `json`, resolved for a shader, or null when it
 * has none (or its table set is missing): { ext, tables: { longitudinal, azimuthal, dualScattering } (each
 * { accessor, width, height }), variances [4], params [tilt radians, slices, alphaF, betaF], sigmaA [3],
 * melaninAttribute, occlusionAttribute, fibresPositive, fibresNegative (attribute names or undefined) }.
 */
export function hairShadingOf(json, materialIndex) {
	const ext = materialIndex !== undefined ? json.materials?.[materialIndex]?.extensions?.[BAKER_HAIR_SHADING] : null;
	const set = ext && json.extensions?.[BAKER_HAIR_SHADING]?.tables?.[ext.tables];
	if (!set) return null;
	return {
		ext,
		tables: { longitudinal: set.longitudinal, azimuthal: set.azimuthal, dualScattering: set.dualScattering },
		variances: longitudinalVariances(ext.betaM),
		params: [ext.alpha * Math.PI / 180, set.azimuthal.slices, set.dualScattering.alphaF, set.dualScattering.betaF],
		sigmaA: ext.sigmaA,
		melaninAttribute: ext.melaninAttribute,
		occlusionAttribute: ext.occlusion?.attribute,
		fibresPositive: ext.fibreCount?.positive,
		fibresNegative: ext.fibreCount?.negative,
	};
}

/**
 * The texels of table `table` ({ accessor, width, height }) from its accessor's elements (any array of the
 * UNSIGNED_SHORT values, VEC4 flattened): a Uint16Array of half-float bits, width x height x 4.
 */
export function hairTableTexels(table, values) {
	const count = table.width * table.height * 4;
	if (values.length !== count) throw new Error(`BAKER_hair_shading: accessor ${table.accessor} holds ${values.length} values, not ${table.width} x ${table.height} x 4`);
	return values instanceof Uint16Array ? values : Uint16Array.from(values);
}

// Fibre shading of strands, ribbons and cards: 'fibre' (BAKER_hair_shading, the default where the material has it)
// or 'kajiyaKay' (Kajiya & Kay 1989, what the runtimes drew before; also the fallback without the extension).
export const HAIR_SHADINGS = ['fibre', 'kajiyaKay'];
export function hairShadingChoice(options) {
	const shading = options?.hair?.shading ?? 'fibre';
	if (!HAIR_SHADINGS.includes(shading)) throw new Error(`options.hair.shading must be one of ${HAIR_SHADINGS.join(', ')}, not ${shading}`);
	return shading;
}

/**
 * baker_hair_shading.glsl as a host pastes it after its own prelude: three.js's <common> chunk (and other hosts')
 * define PI as a macro, which would rewrite the module's local `const float PI`; the macro is lifted around the module
 * and restored after it.
 */
export function hairShadingGlsl(text) {
	return `#ifdef PI\n#undef PI\n#define BAKER_HAIR_SHADING_RESTORE_PI\n#endif\n${text}\n`
		+ '#ifdef BAKER_HAIR_SHADING_RESTORE_PI\n#define PI 3.141592653589793\n#undef BAKER_HAIR_SHADING_RESTORE_PI\n#endif\n';
}
