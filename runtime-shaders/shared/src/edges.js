// BAKER_edges: the wireframe's per-corner data both runtimes build (Baerentzen et al. 2006, single-pass wireframe).

/**
 * Per-corner barycentrics (corner k of each triangle: unit vector k) and the triangle's wireframe mask, for `count`
 * corners of a non-indexed triangle list (the method needs one vertex per corner). mask: one value per triangle (bit
 * k: edge k drawn), or null: all edges.
 */
export function wireframeCorners(count, mask) {
	const bary = new Float32Array(count * 3);
	const masks = new Float32Array(count);
	for (let v = 0; v < count; v++) {
		bary[v * 3 + (v % 3)] = 1;
		masks[v] = mask ? mask[Math.floor(v / 3)] : 7;
	}
	return { bary, masks };
}
