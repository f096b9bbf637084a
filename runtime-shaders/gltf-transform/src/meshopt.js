// EXT_meshopt_compression that leaves byte-sized extension data uncompressed.
//
// glTF-Transform 4.5's meshopt writer (EXTMeshoptCompression) compresses every accessor, and pads elements whose
// size is not a multiple of 4 bytes to a 4-byte stride (meshopt's ATTRIBUTES mode needs it) without writing that
// stride where a reader of a non-vertex accessor looks (bufferView.byteStride is only allowed on vertex data): a
// tightly packed UNSIGNED_BYTE accessor held by an extension (EXT_mesh_primitive_edge_visibility's bits, BAKER_edges'
// flags and wireframe mask, BAKER_fur's KTX2 mip chains) then reads as the padding, mostly zeros.
// keepBytesUncompressed(EXTMeshoptCompression) patches the class (the `meshopt()` transform creates Khronos' class
// itself, so a subclass would not be used) to hide those accessors from the compressor: the writer stores them as
// they are, and everything else is compressed as before. gltf-transform.config.mjs calls it.
const PATCHED = Symbol('baker keeps byte-sized accessors uncompressed');

export function keepBytesUncompressed(EXTMeshoptCompression) {
	const proto = EXTMeshoptCompression.prototype;
	if (proto[PATCHED]) return EXTMeshoptCompression;
	const prewriteAccessors = proto._prewriteAccessors;
	if (typeof prewriteAccessors !== 'function') {
		throw new Error('@baker/gltf-transform: EXTMeshoptCompression has no _prewriteAccessors (glTF-Transform 4.5 expected)');
	}
	proto._prewriteAccessors = function (context) {
		const root = this.document.getRoot();
		const padded = new Set(root.listAccessors().filter((accessor) => context.getAccessorUsage(accessor) === 'OTHER' &&
			(accessor.getElementSize() * accessor.getComponentSize()) % 4 !== 0));
		const listAccessors = root.listAccessors;
		root.listAccessors = () => listAccessors.call(root).filter((accessor) => !padded.has(accessor));
		try {
			return prewriteAccessors.call(this, context);
		} finally {
			delete root.listAccessors;
		}
	};
	proto[PATCHED] = true;
	return EXTMeshoptCompression;
}
