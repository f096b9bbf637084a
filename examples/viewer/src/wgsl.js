// The runtime-shaders/ WGSL twins as text, under the same keys as shaders.js' GLSL (options.wgsl of
// @baker/three's node entry): esbuild bundles every baker_*.wgsl the template can name (the text loader for .wgsl).
import { RUNTIMES } from '@baker/shared';
import hairShading from '../../../runtime-shaders/baker_hair_shading.wgsl';

// 'baker_<stem>.glsl' -> the module's WGSL twin beside it, baker_<stem>.wgsl
const stem = (file) => file.replace(/^baker_/, '').replace(/\.glsl$/, '');

export const wgsl = Object.fromEntries(await Promise.all(RUNTIMES.filter((r) => r.modules.glsl).map(async (r) =>
	[r.modules.key, (await import(`../../../runtime-shaders/baker_${stem(r.modules.glsl)}.wgsl`)).default])));
// the fibre model of BAKER_hair_shading, which the hair and cards techniques include (no descriptor of its own)
wgsl.hairShading = hairShading;
