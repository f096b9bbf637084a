// Coverage-preserving mip chains (Castaño 2010; RTR4 14.7.1): the `coverageMips` entries baker writes next to an
// alpha-tested texture (BAKER_fur, BAKER_hair_cards; schemas/BAKER_fur/README.md). Each holds an uncompressed RGBA8 KTX2 (every
// level down to 1 x 1, each level's alpha scaled so the alpha test passes on level 0's fraction of texels) as the
// bytes of an UNSIGNED_BYTE accessor; with `firstLevel` 1 (baker's default) the KTX2 starts at level 1 and level 0 is
// the texture's PNG, decoded here as stored. Both runtimes parse it here and upload the levels as the texture's mips.

const IDENTIFIER = [0xab, 0x4b, 0x54, 0x58, 0x20, 0x32, 0x30, 0xbb, 0x0d, 0x0a, 0x1a, 0x0a];
const VK_FORMAT_R8G8B8A8_UNORM = 37;

/** The coverageMips entry of `texture` (glTF texture index) in an extension object, or null. */
export function coverageMipsOf(ext, texture) {
	const index = typeof texture === 'number' ? texture : texture?.index;
	for (const entry of ext?.coverageMips || []) if (entry?.texture === index) return entry;
	return null;
}

/**
 * Parse an uncompressed RGBA8 KTX 2.0 file (KTX File Format 2.0: header, level index; no supercompression) into
 * { width, height, levels: [{ data: Uint8Array, width, height }] }, level 0 first. Throws on anything else: a
 * runtime falls back to the plain PNG.
 */
export function parseKtx2Rgba8(bytes) {
	if (bytes.byteLength < 80 || IDENTIFIER.some((b, i) => bytes[i] !== b)) throw new Error('not a KTX2 file');
	const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
	const u32 = (at) => view.getUint32(at, true);
	const u64 = (at) => view.getUint32(at, true) + view.getUint32(at + 4, true) * 2 ** 32;
	const [vkFormat, typeSize, width, height, depth, layers, faces, levelCount, scheme] =
		Array.from({ length: 9 }, (_, i) => u32(12 + 4 * i));
	if (vkFormat !== VK_FORMAT_R8G8B8A8_UNORM || typeSize !== 1 || depth || layers || faces !== 1 || scheme) {
		throw new Error(`KTX2 is not an uncompressed 2D RGBA8 texture (vkFormat ${vkFormat})`);
	}
	if (levelCount < 1 || 80 + 24 * levelCount > bytes.byteLength) throw new Error(`KTX2 levelCount ${levelCount}`);
	const levels = [];
	for (let i = 0; i < levelCount; i++) {
		const offset = u64(80 + 24 * i);
		const length = u64(88 + 24 * i);
		const w = Math.max(1, width >> i);
		const h = Math.max(1, height >> i);
		if (length !== w * h * 4 || offset + length > bytes.byteLength) throw new Error(`KTX2 level ${i}: bad byte range`);
		levels.push({ data: bytes.subarray(offset, offset + length), width: w, height: h });
	}
	return { width, height, levels };
}

const PNG_SIGNATURE = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a];

/**
 * Decode a non-interlaced 8-bit RGBA (or RGB) PNG into { data: Uint8Array (RGBA), width, height }, its bytes as
 * stored: no colour management, straight alpha (what a canvas would not give). Inflates with the browser's
 * DecompressionStream (zlib), then undoes the five row filters (PNG spec 9.2). Throws on other PNGs.
 */
export async function decodePngRgba8(bytes) {
	if (bytes.byteLength < 33 || PNG_SIGNATURE.some((b, i) => bytes[i] !== b)) throw new Error('not a PNG');
	const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
	let width = 0, height = 0, channels = 0;
	const idat = [];
	for (let at = 8; at + 8 <= bytes.byteLength;) {
		const length = view.getUint32(at);
		const type = String.fromCharCode(...bytes.subarray(at + 4, at + 8));
		const data = bytes.subarray(at + 8, at + 8 + length);
		if (type === 'IHDR') {
			width = view.getUint32(at + 8);
			height = view.getUint32(at + 12);
			const [depth, colorType, , , interlace] = data.subarray(8, 13);
			channels = { 6: 4, 2: 3 }[colorType] || 0;
			if (depth !== 8 || !channels || interlace) throw new Error(`PNG is not 8-bit RGBA/RGB (depth ${depth}, colour type ${colorType})`);
		} else if (type === 'IDAT') idat.push(data);
		else if (type === 'IEND') break;
		at += 12 + length;
	}
	if (!width || !height) throw new Error('PNG has no IHDR');
	const stream = new Blob(idat).stream().pipeThrough(new DecompressionStream('deflate'));
	const raw = new Uint8Array(await new Response(stream).arrayBuffer());
	const stride = width * channels;
	if (raw.byteLength < height * (stride + 1)) throw new Error('PNG data is short');
	const out = new Uint8Array(width * height * 4);
	let previous = new Uint8Array(stride);
	for (let y = 0; y < height; y++) {
		const filter = raw[y * (stride + 1)];
		const row = raw.slice(y * (stride + 1) + 1, (y + 1) * (stride + 1));
		for (let i = 0; i < stride; i++) {
			const a = i >= channels ? row[i - channels] : 0, b = previous[i], c = i >= channels ? previous[i - channels] : 0;
			let predictor = 0;
			if (filter === 1) predictor = a;
			else if (filter === 2) predictor = b;
			else if (filter === 3) predictor = (a + b) >> 1;
			else if (filter === 4) {
				const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
				predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
			} else if (filter !== 0) throw new Error(`PNG row filter ${filter}`);
			row[i] = (row[i] + predictor) & 0xff;
		}
		for (let x = 0; x < width; x++) {
			for (let k = 0; k < channels; k++) out[(y * width + x) * 4 + k] = row[x * channels + k];
			if (channels === 3) out[(y * width + x) * 4 + 3] = 255;
		}
		previous = row;
	}
	return { data: out, width, height };
}

/**
 * The whole chain of a `coverageMips` entry, level 0 first: the KTX2's levels (`ktx2`, its bytes), after level 0
 * decoded from the texture's PNG (`png()`, an async function giving its bytes) when the KTX2 starts at level 1
 * (`firstLevel` 1: baker stores the PNG's texels once). Throws when unreadable: a runtime falls back to the PNG.
 */
export async function coverageMipLevels(entry, ktx2, png) {
	const chain = parseKtx2Rgba8(ktx2);
	const first = entry?.firstLevel ?? 0;
	if (first === 0) return chain;
	if (first !== 1) throw new Error(`firstLevel ${first}`);
	const base = await decodePngRgba8(await png());
	if (chain.width !== Math.max(1, base.width >> 1) || chain.height !== Math.max(1, base.height >> 1)) {
		throw new Error(`KTX2 level 1 is ${chain.width} x ${chain.height}, the image ${base.width} x ${base.height}`);
	}
	return { width: base.width, height: base.height, levels: [base, ...chain.levels] };
}
