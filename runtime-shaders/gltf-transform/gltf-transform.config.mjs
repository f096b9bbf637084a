// glTF-Transform CLI config that keeps baker's bake through the CLI's steps:
//   gltf-transform optimize in.glb out.glb --compress meshopt \
//     --config runtime-shaders/gltf-transform/gltf-transform.config.mjs
// The CLI replaces its extension list with this one, so Khronos' extensions are listed next to baker's; and
// EXT_meshopt_compression is told to store byte-sized extension data as it is (src/meshopt.js).
import { ALL_EXTENSIONS, EXTMeshoptCompression } from '@gltf-transform/extensions';
import { BAKER_EXTENSIONS } from './src/index.js';
import { keepBytesUncompressed } from './src/meshopt.js';

keepBytesUncompressed(EXTMeshoptCompression);

export default { extensions: [...ALL_EXTENSIONS, ...BAKER_EXTENSIONS] };
