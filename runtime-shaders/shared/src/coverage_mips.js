// Coverage-preserving mip chains (Castaño 2010; RTR4 14.7.1): the `coverageMips` entries baker writes next to an
// alpha-tested texture (BAKER_fur, BAKER_hair_cards; schemas/BAKER_fur/README.md). Each holds an uncompressed RGBA8 KTX2 (every
// level down to 1 x 1, each level's alpha scaled so the alpha test passes on level 0's fraction of texels) as the
// bytes of an UNSIGNED_BYTE accessor. Both runtimes parse it here and upload the levels as the texture's mips.

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
