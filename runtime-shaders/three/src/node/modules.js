// The runtime-shaders/ modules inside TSL: each module is pasted once per shader stage (a CodeNode, as the modules'
// README says to include them), WGSL on WebGPURenderer's WebGPU backend and GLSL on its WebGL2 backend, and a
// module function is called through a one-line wrapper (wgslFn / glslFn) that the backend's builder picks at build
// time. So the formulas are the modules' own; TSL only samples the textures (a wrapper takes no texture: GLSL's
// glslFn cannot pass a sampler2D) and composes the calls.
import { Fn, code, glslFn, wgslFn } from 'three/tsl';

// WGSL type -> GLSL type of a wrapper's parameters and result
const GLSL_TYPES = { f32: 'float', i32: 'int', bool: 'bool', vec2f: 'vec2', vec3f: 'vec3', vec4f: 'vec4', mat3x3f: 'mat3' };

/** The parameters [[name, wgslType], ...] and result type of `fn name(...) -> type` in a WGSL module. */
export function wgslSignature(source, name) {
	const match = source.match(new RegExp(`fn\\s+${name}\\s*\\(([^)]*)\\)\\s*(?:->\\s*([A-Za-z0-9_<>]+))?`));
	if (!match) throw new Error(`@baker/three: ${name} is not a function of the WGSL module`);
	const params = match[1].split(',').map((p) => p.trim()).filter(Boolean).map((p) => p.split(':').map((s) => s.trim()));
	return { params, result: match[2] ?? null };
}

/** True when the builder writes WGSL (WebGPU backend), false for GLSL (WebGL2 backend). */
export function isWgslBuilder(builder) {
	return builder.renderer?.backend?.isWebGPUBackend === true;
}

/**
 * The modules of one load: `wgsl` and `glsl` are options.wgsl / options.shaders (runtime-shaders/ text by key).
 * fn(key, name) is a TSL function calling the module function `name` with nodes, positional (pure functions of
 * scalars, vectors and matrices only); custom(key, wgsl, glsl) a wrapper written in both languages that calls the
 * module (for the functions with `ptr` / `out` parameters).
 */
export class BakerModules {
	constructor(wgsl = {}, glsl = {}) {
		this.wgsl = wgsl;
		this.glsl = glsl;
		this.codes = new Map();  // key -> { wgsl: CodeNode, glsl: CodeNode }
		this.functions = new Map();
	}

	module(key) {
		if (!this.codes.has(key)) {
			if (!this.wgsl[key]) throw new Error(`@baker/three: options.wgsl.${key} (the runtime-shaders/ WGSL module as text) is missing`);
			if (!this.glsl[key]) throw new Error(`@baker/three: options.shaders.${key} (the runtime-shaders/ GLSL module as text) is missing`);
			this.codes.set(key, { wgsl: code(this.wgsl[key], [], 'wgsl'), glsl: code(this.glsl[key], [], 'glsl') });
		}
		return this.codes.get(key);
	}

	custom(key, wgslSource, glslSource) {
		const id = `${key}:${wgslSource}`;
		if (!this.functions.has(id)) {
			const module = this.module(key);
			const wgsl = wgslFn(wgslSource, [module.wgsl]);
			const glsl = glslFn(glslSource, [module.glsl]);
			this.functions.set(id, (...args) => Fn((builder) => (isWgslBuilder(builder) ? wgsl : glsl)(...args))());
		}
		return this.functions.get(id);
	}

	fn(key, name) {
		this.module(key);  // throws on a missing module before its signature is read
		const { params, result } = wgslSignature(this.wgsl[key], name);
		const names = params.map(([n]) => n);
		const wgsl = `fn ${name}_node(${params.map(([n, t]) => `${n}: ${t}`).join(', ')}) -> ${result} {\n\treturn ${name}(${names.join(', ')});\n}`;
		const glsl = `${GLSL_TYPES[result]} ${name}_node(${params.map(([n, t]) => `${GLSL_TYPES[t]} ${n}`).join(', ')}) {\n\treturn ${name}(${names.join(', ')});\n}`;
		return this.custom(key, wgsl, glsl);
	}
}
