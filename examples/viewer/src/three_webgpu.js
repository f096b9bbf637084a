// The three.js viewer on WebGPURenderer (?engine=three-webgpu): @baker/three's node entry draws the surface
// techniques as node materials in TSL with the runtime-shaders/ WGSL (WebGPU) or GLSL (WebGL2) modules.
// ?backend=webgl2 forces WebGPURenderer's WebGL2 backend (forceWebGL), so a test can compare the two backends on one
// page. window.__bakerBackend is read from the renderer (renderer.backend.isWebGPUBackend), not from the URL. With
// no WebGPU adapter the page says so (and window.__bakerError) instead of falling back silently.
import { WebGPURenderer } from 'three/webgpu';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { registerBakerNodePlugins } from '../../../runtime-shaders/three/src/node/index.js';
import { shaders } from './shaders.js';
import { wgsl } from './wgsl.js';
import { runThreeViewer } from './three_viewer.js';
import { bakerOn, caustics, fail, hair, params } from './ui.js';

async function load(url) {
	const loader = bakerOn ? registerBakerNodePlugins(new GLTFLoader(), { shaders, wgsl, caustics, hair }) : new GLTFLoader();
	// the compressed forms the WebGL2 page decodes (main.js): meshopt, and Draco from dist/draco/
	loader.setMeshoptDecoder(MeshoptDecoder);
	loader.setDRACOLoader(new DRACOLoader().setDecoderPath(new URL('dist/draco/', document.baseURI).href));
	return loader.loadAsync(url);
}

async function start() {
	const forceWebGL = params.get('backend') === 'webgl2';
	if (!forceWebGL) {
		const adapter = navigator.gpu ? await navigator.gpu.requestAdapter() : null;
		if (!adapter) {
			fail(`no WebGPU adapter in this browser (navigator.gpu ${navigator.gpu ? 'has none' : 'is missing'}); ` +
				'open ?engine=three-webgpu&backend=webgl2 for the WebGL2 backend, or ?engine=three');
			return;
		}
	}
	const renderer = new WebGPURenderer({ antialias: true, forceWebGL });
	renderer.setPixelRatio(1);
	await renderer.init();
	document.getElementById('view').appendChild(renderer.domElement);
	const backend = renderer.backend.isWebGPUBackend ? 'webgpu' : 'webgl2';
	runThreeViewer({ renderer, load, engine: 'three-webgpu', backend });
	// the engine select (ui.js) lists three.js and Babylon.js; this page adds itself
	const select = document.getElementById('engine');
	if (select && ![...select.options].some((o) => o.value === 'three-webgpu')) {
		select.add(new Option(`three.js WebGPURenderer (${backend})`, 'three-webgpu'));
		select.value = 'three-webgpu';
	}
}

start().catch((e) => fail(String(e && e.stack || e)));
