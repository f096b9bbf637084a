// A descriptor uniform's value read from an extension's JSON (techniques.js says how), the same for every host:
// numbers for float/int, arrays of numbers for vecN. Each host turns them into its engine's values.

const SIZES = { float: 1, int: 1, vec2: 2, vec3: 3, vec4: 4 };

// 'levels.0.size' -> ext.levels[0].size
function at(ext, path) {
	return path.split('.').reduce((value, key) => (value == null ? undefined : value[key]), ext);
}

// values that are a formula of several properties
const COMPUTED = {
	// BAKER_curvature's false-colour scale: 4 x |mean curvature|, at least half the range's top
	curvatureScale: (ext) => Math.max(Math.abs(ext.meanCurvature ?? 0) * 4, Math.abs((ext.range ?? [-1, 1])[1]) * 0.5, 1e-6),
};

/** The value of descriptor uniform `spec` for the extension object `ext` (the extension's default when absent). */
export function uniformValue(spec, ext) {
	if (spec.compute) return COMPUTED[spec.compute](ext);
	const sources = spec.from === undefined ? [] : [].concat(spec.from);
	let value = sources.map((path) => at(ext, path)).find((v) => v !== undefined && v !== null);
	if (spec.count && Array.isArray(value)) value = value.length;
	if (value === undefined) value = spec.default;
	if (spec.enum) value = spec.enum[value] ?? spec.enum[spec.default];
	if (spec.slice) value = value.slice(...spec.slice);
	const size = SIZES[spec.type];
	if (size > 1) return value.slice(0, size);
	return value;
}

/** { uniform name: value } of every uniform of a descriptor, for one extension object. */
export function uniformValues(descriptor, ext) {
	return Object.fromEntries(descriptor.uniforms.map((spec) => [spec.name, uniformValue(spec, ext)]));
}

/** The GLSL expression that builds a descriptor's parameter struct from its uniforms (`BakerSkin(u_..., ...)`). */
export function structExpression(descriptor) {
	const s = descriptor.struct;
	return s ? `${s.type}(${s.fields.join(', ')})` : '';
}
