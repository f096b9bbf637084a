// The viewer on Babylon.js: the same asset, switches and URL parameters as the three.js page (main.js), with the
// loader extensions of @baker/babylon (runtime-shaders/babylon). ?view=JSON (what the three.js page publishes as
// window.__bakerView: eye, target, near, far, lights) draws the very view the three.js page drew.
// ?engine=babylon-webgpu: the same page on Babylon's WebGPUEngine (WGSL materials: @baker/babylon's WGSL parts, from
// runtime-shaders/*.wgsl); window.__bakerBackend names the backend the engine draws with ('webgpu' or 'webgl2').
import { Engine } from '@babylonjs/core/Engines/engine.js';
import { WebGPUEngine } from '@babylonjs/core/Engines/webgpuEngine.js';
import { Scene } from '@babylonjs/core/scene.js';
import { ArcRotateCamera } from '@babylonjs/core/Cameras/arcRotateCamera.js';
import { HemisphericLight } from '@babylonjs/core/Lights/hemisphericLight.js';
import { DirectionalLight } from '@babylonjs/core/Lights/directionalLight.js';
import { Color3, Color4 } from '@babylonjs/core/Maths/math.color.js';
import { Vector3 } from '@babylonjs/core/Maths/math.vector.js';
import { ImportMeshAsync } from '@babylonjs/core/Loading/sceneLoader.js';
import '@babylonjs/loaders/glTF/glTFFileLoader.js';
import '@babylonjs/loaders/glTF/2.0/index.js';
import { MeshoptCompression } from '@babylonjs/core/Meshes/Compression/meshoptCompression.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { DracoDecoder } from '@babylonjs/core/Meshes/Compression/dracoDecoder.js';
import { TECHNIQUES, bakerControls, registerBakerExtensions, unregisterBakerExtensions } from '../../../runtime-shaders/babylon/src/index.js';
import {
	BACK_LIT, BACKGROUND, FILL_CAMERA_POSITION, FILL_INTENSITY, FOV_DEGREES, HEMI, KEY_INTENSITY, addToggle, bakerOn, caustics, hair,
	engineSwitch, fail, frameDirection, frameDistance, frontSwitch, keyDirection, listParam, onDroppedFile, params,
	showToggles, status, switchTechniques,
} from './ui.js';
import { shaders } from './shaders.js';
import hairShadingWgsl from '../../../runtime-shaders/baker_hair_shading.wgsl';
import { RUNTIMES } from '@baker/shared';

// EXT_meshopt_compression: Babylon.js loads meshoptimizer's decoder script from its CDN into the global
// MeshoptDecoder; the viewer bundles that decoder (three's copy of it) so it decodes offline, and names an empty
// script for Babylon.js to load
globalThis.MeshoptDecoder = MeshoptDecoder;
MeshoptCompression.Configuration.decoder.url = 'data:text/javascript,';
// KHR_draco_mesh_compression: Google's glTF decoder (three's copy), which the build puts in dist/draco/, not the CDN's
const dracoFile = (name) => new URL(`dist/draco/${name}`, document.baseURI).href;
DracoDecoder.DefaultConfiguration = {
	wasmUrl: dracoFile('draco_wasm_wrapper.js'), wasmBinaryUrl: dracoFile('draco_decoder.wasm'),
	fallbackUrl: dracoFile('draco_decoder.js'),
};

// the runtime-shaders/ WGSL twins as text, under the options.shaders keys (the descriptors name them; esbuild bundles
// every file the template can name, as text by the import attribute)
const wgslStem = (file) => file.replace(/^baker_/, '').replace(/\.wgsl$/, '');
async function wgslModules() {
	const modules = Object.fromEntries(await Promise.all(RUNTIMES.filter((r) => r.modules.wgsl).map(async (r) =>
		[r.modules.key, (await import(`../../../runtime-shaders/baker_${wgslStem(r.modules.wgsl)}.wgsl`, { with: { type: 'text' } })).default])));
	return { ...modules, hairShading: hairShadingWgsl }; // BAKER_hair_shading's module (no descriptor of its own)
}

/**
 * The engine of the page: ?engine=babylon-webgpu a WebGPUEngine (null, with the reason on the page and in
 * window.__bakerError, when the browser has no WebGPU adapter), else the WebGL2 Engine.
 */
async function createEngine(canvas, webgpu) {
	if (!webgpu) {
		// exact sRGB encoding (three.js's), not Babylon's default pow(1/2.2) approximation
		return new Engine(canvas, true, { preserveDrawingBuffer: true, stencil: true, useExactSrgbConversions: true }, false);
	}
	if (!navigator.gpu || !(await navigator.gpu.requestAdapter())) {
		fail('WebGPU is not available in this browser (no adapter): open the page with ?engine=babylon for WebGL2');
		return null;
	}
	const engine = new WebGPUEngine(canvas, { antialias: true, stencil: true, useExactSrgbConversions: true,
		adaptToDeviceRatio: false });
	await engine.initAsync();
	return engine;
}

const srgbToLinear = (c) => (c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4);

export async function babylonViewer() {
	const webgpu = params.get('engine') === 'babylon-webgpu';
	engineSwitch(webgpu ? 'babylon-webgpu' : 'babylon');
	const select = document.getElementById('engine');
	if (select && ![...select.options].some((o) => o.value === 'babylon-webgpu')) {
		select.add(new Option('Babylon.js (WebGPU)', 'babylon-webgpu'));
		select.value = webgpu ? 'babylon-webgpu' : 'babylon';
	}
	const view = document.getElementById('view');
	const canvas = document.createElement('canvas');
	canvas.style.width = '100%';
	canvas.style.height = '100%';
	canvas.style.display = 'block';
	view.appendChild(canvas);
	const engine = await createEngine(canvas, webgpu);
	if (!engine) return;
	window.__bakerBackend = engine.isWebGPU ? 'webgpu' : 'webgl2'; // what draws, read from the engine
	engine.setHardwareScalingLevel(1);
	const scene = new Scene(engine);
	scene.useRightHandedSystem = true; // glTF's frame, as three.js: no mirroring root, same camera numbers
	scene.clearColor = new Color4(...BACKGROUND, 1);
	scene.ambientColor = new Color3(0, 0, 0);
	const camera = new ArcRotateCamera('camera', 0, 1, 1, Vector3.Zero(), scene);
	camera.fov = FOV_DEGREES * Math.PI / 180;
	camera.attachControl(canvas, true);
	camera.wheelPrecision = 50;
	// three.js's HemisphereLight irradiance goes through its Lambert BRDF (1/pi); Babylon's hemispheric term does not
	const hemi = new HemisphericLight('hemisphere', new Vector3(0, 1, 0), scene);
	hemi.diffuse = new Color3(...HEMI.sky);
	hemi.groundColor = new Color3(...HEMI.groundSrgb.map(srgbToLinear));
	hemi.specular = Color3.Black();
	hemi.intensity = HEMI.intensity / Math.PI;
	const key = new DirectionalLight('key', new Vector3(0, -1, 0), scene);
	key.intensity = KEY_INTENSITY;
	const fill = new DirectionalLight('fill', new Vector3(0, -1, 0), scene);
	fill.intensity = FILL_INTENSITY;

	// ?disable=BAKER_fur,...: extensions left to Babylon's loader (which ignores them)
	if (bakerOn) registerBakerExtensions({ shaders, wgsl: engine.isWebGPU ? await wgslModules() : {}, caustics, hair, disabled: [...listParam('disable')] });
	else unregisterBakerExtensions();

	const given = params.get('view') ? JSON.parse(params.get('view')) : null;
	let sphere = null;
	function place(v) {
		camera.setTarget(new Vector3(...v.target));
		camera.setPosition(new Vector3(...v.eye));
		camera.minZ = v.near;
		camera.maxZ = v.far;
		key.direction = new Vector3(...v.key.map((x) => -x));
		fill.direction = new Vector3(...v.fill.map((x) => -x));
	}
	function frame(root, back) {
		const { min, max } = root.getHierarchyBoundingVectors(true);
		const center = min.add(max).scale(0.5);
		const radius = max.subtract(min).length() / 2;
		const distance = frameDistance(radius, engine.getAspectRatio(camera));
		const eye = center.add(new Vector3(...frameDirection()).scale(distance));
		const toEye = eye.subtract(center).normalize();
		// fill: camera space (-1, 1.5, 2), aimed at the world origin as three.js's default light target
		camera.setTarget(center);
		camera.setPosition(eye);
		const m = camera.getWorldMatrix();
		const fillWorld = Vector3.TransformCoordinates(new Vector3(...FILL_CAMERA_POSITION), m);
		return { eye: eye.asArray(), target: center.asArray(), near: distance / 100, far: distance * 10,
			key: keyDirection(toEye.asArray(), back), fill: fillWorld.normalize().asArray() };
	}

	async function show(source, name) {
		try {
			const options = typeof source === 'string' ? {} : { pluginExtension: '.glb' };
			const started = performance.now();
			const result = await ImportMeshAsync(source, scene, options);
			const loaded = performance.now();
			const root = result.meshes[0];
			const baker = bakerControls(root);
			const found = showToggles(baker, null, TECHNIQUES);
			// the light from behind (translucency; hair's forward scattering) only when asked for: ?on=backlight or
			// its checkbox
			const backLit = BACK_LIT.some((t) => found.includes(t));
			let back = backLit && listParam('on').has('backlight');
			const v = given ?? frame(root, back);
			place(v);
			sphere = v;
			if (backLit) {
				addToggle('light from behind', 'backlight', back, (on) => {
					back = on;
					// the front key of the framing, or the camera's direction reversed
					const toEye = Vector3.FromArray(sphere.eye).subtract(Vector3.FromArray(sphere.target)).normalize();
					key.direction = new Vector3(...keyDirection(toEye.asArray(), on).map((x) => -x));
				});
			}
			reframe = () => { sphere = frame(root, back); place(sphere); window.__bakerView = sphere; };
			status.textContent = `${name}: ${found.length ? found.join(', ') : 'no baked data found'}`;
			await scene.whenReadyAsync();
			window.__bakerTechniques = found;
			window.__bakerSwitch = (names, on) => switchTechniques(baker, names, on); // for tests
			window.__bakerView = v;
			window.__bakerScene = scene; // for inspection from the console
			engine.stopRenderLoop();
			engine.runRenderLoop(() => scene.render());
			// two frames drawn before the page says it is ready (the screenshot reads the drawing buffer)
			await new Promise((resolve) => { let n = 0; scene.onAfterRenderObservable.add(() => { if (++n === 2) resolve(); }); });
			// ms: the load (file, extensions' data) and from then to two frames drawn (materials compiled, pipelines
			// made): what benchmarks/babylon_backends.py compares per backend
			window.__bakerTimings = { load: loaded - started, ready: performance.now() - loaded };
			window.__bakerReady = true;
		} catch (e) {
			fail(`cannot load ${name}: ${e.message || e}\n${e.stack || ''}`);
		}
	}
	let reframe = () => {};
	frontSwitch(() => reframe());
	addEventListener('resize', () => engine.resize());
	onDroppedFile((file) => {
		for (const m of [...scene.meshes]) m.dispose();
		show(file, file.name);
	});
	if (params.get('src')) await show(params.get('src'), params.get('src'));
	else engine.runRenderLoop(() => scene.render());
}

babylonViewer().catch((e) => fail(String(e && e.stack || e)));
