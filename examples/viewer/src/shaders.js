// The runtime-shaders/ modules as text, one per descriptor that names a GLSL module, under its options.shaders key:
// both engines inject these very files. esbuild bundles every file the template can name (its glob import, with
// the text loader for .glsl), so the list is the descriptors' and a new technique needs no line here.
import { RUNTIMES } from '@baker/shared';
import hairShading from '../../../runtime-shaders/baker_hair_shading.glsl';

// 'baker_<stem>.glsl' -> the import's template needs the fixed prefix and suffix to glob only the GLSL modules
const stem = (file) => file.replace(/^baker_/, '').replace(/\.glsl$/, '');

export const shaders = Object.fromEntries(await Promise.all(RUNTIMES.filter((r) => r.modules.glsl).map(async (r) =>
	[r.modules.key, (await import(`../../../runtime-shaders/baker_${stem(r.modules.glsl)}.glsl`)).default])));
// the fibre model of BAKER_hair_shading, which the hair and cards techniques include (no descriptor of its own)
shaders.hairShading = hairShading;
