// glTF-Transform CLI config that keeps baker's bake through the CLI's steps:
//   gltf-transform optimize in.glb out.glb --compress meshopt \
//     --config runtime-shaders/gltf-transform/gltf-transform.config.mjs
// The CLI replaces its extension list with this one, so Khronos' extensions are listed next to baker's; and
// EXT_meshopt_compression is told to store byte-sized extension data as it is (src/meshopt.js) and the edge data
// follows the triangle rotation meshopt's index codec makes and the vertex order of Draco's streams (src/topology.js).
import { ALL_EXTENSIONS, EXTMeshoptCompression } from '@gltf-transform/extensions';
import { BAKER_EXTENSIONS } from './src/index.js';
import { MeshoptDecoder, MeshoptEncoder } from 'meshoptimizer';
import { keepBytesUncompressed } from './src/meshopt.js';
import { setDracoDecoder, setMeshoptIndexCodec } from './src/topology.js';
import draco3d from 'draco3dgltf';

keepBytesUncompressed(EXTMeshoptCompression);
// meshopt's index codec may rotate triangles: the edge data follows the rotation it will make
await Promise.all([MeshoptEncoder.ready, MeshoptDecoder.ready]);
setMeshoptIndexCodec({ encoder: MeshoptEncoder, decoder: MeshoptDecoder });
// Draco renumbers vertices inside its stream: the edge data follows the order the stream decodes to
setDracoDecoder(await draco3d.createDecoderModule());

export default { extensions: [...ALL_EXTENSIONS, ...BAKER_EXTENSIONS] };
