// BAKER_caustics: the parameters and the frame choice both runtimes give baker_caustics.glsl (RTR4 14.5.3).

/** The runtime parameters of a material's BAKER_caustics, with the extension's defaults filled in. */
export function causticsParameters(ext) {
	return {
		frameCount: (ext.frameTextures || []).length,
		tileSize: ext.tileSize, period: ext.period, intensityScale: ext.intensityScale, depth: ext.depth,
		waterLevel: ext.waterLevel ?? 0, fadeDistance: ext.fadeDistance ?? 1, strength: ext.strength ?? 1,
		projectionDirection: (ext.projectionDirection ?? [0, -1, 0]).slice(0, 3),
	};
}

/**
 * The frames to blend at `time` seconds, as baker_caustics_frame computes them: { first, blend, next } (the loop
 * wraps). The host binds frames `first` and `next` to the shader's two samplers: GLSL ES 3.00 cannot index an array
 * of samplers with a variable.
 */
export function causticsFrame(time, period, frameCount) {
	const loop = time / period;
	const f = (loop - Math.floor(loop)) * frameCount;
	const first = Math.min(Math.floor(f), frameCount - 1);
	const next = first + 1 >= frameCount ? 0 : first + 1;
	return { first, blend: f - first, next };
}

/**
 * The clock of the caustic animation, seconds: options.time (a number: a still at that time, or a function
 * returning seconds), else the page's clock.
 */
export function causticsClock(options = {}) {
	const given = options.time;
	if (typeof given === 'function') return given;
	if (typeof given === 'number') return () => given;
	return () => performance.now() / 1000;
}
