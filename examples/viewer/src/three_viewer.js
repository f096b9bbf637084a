// The three.js viewer page, shared by the WebGLRenderer page (main.js, ?engine=three) and the WebGPURenderer page
// (three_webgpu.js, ?engine=three-webgpu): the scene, the framing and lights, the technique toggles and the test
// hooks (window.__bakerReady, __bakerTechniques, __bakerSwitch, __bakerView, __bakerBackend).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { TECHNIQUES } from '@baker/shared';
import {
	BACK_LIT, BACKGROUND, FILL_CAMERA_POSITION, FILL_INTENSITY, FOV_DEGREES, HEMI, KEY_INTENSITY, addToggle, engineSwitch, fail,
	frameDirection, frameDistance, frontSwitch, keyDirection, listParam, onDroppedFile, params, showToggles, status,
	switchTechniques,
} from './ui.js';

/**
 * The three.js viewer on `renderer` (a WebGLRenderer or a WebGPURenderer, already initialised and in the page):
 * `load(url)` loads a GLB with the baker plugins for that renderer, `engine` is the engine select's value and
 * `backend` the backend drawing ('webgl2' or 'webgpu', window.__bakerBackend).
 */
export function runThreeViewer({ renderer, load, engine, backend }) {
	engineSwitch(engine);
	window.__bakerBackend = backend;
	const scene = new THREE.Scene();
	scene.background = new THREE.Color().setRGB(...BACKGROUND, THREE.SRGBColorSpace);
	const camera = new THREE.PerspectiveCamera(FOV_DEGREES, 1, 0.01, 1000);
	const controls = new OrbitControls(camera, renderer.domElement);
	scene.add(new THREE.HemisphereLight(new THREE.Color().setRGB(...HEMI.sky, THREE.SRGBColorSpace),
		new THREE.Color().setRGB(...HEMI.groundSrgb, THREE.SRGBColorSpace), HEMI.intensity));
	const key = new THREE.DirectionalLight(0xffffff, KEY_INTENSITY);
	scene.add(key, key.target);
	const fill = new THREE.DirectionalLight(0xffffff, FILL_INTENSITY); // from the upper left of the camera, moves with it
	fill.position.set(...FILL_CAMERA_POSITION);
	camera.add(fill);
	scene.add(camera);
	let root = null;

	// the canvas fills #view, the page beside the side panel (the panel never covers the asset)
	const view = renderer.domElement.parentElement;
	function resize() {
		const width = Math.max(1, view.clientWidth), height = Math.max(1, view.clientHeight);
		renderer.setSize(width, height);
		camera.aspect = width / height;
		camera.updateProjectionMatrix();
	}
	addEventListener('resize', resize);
	resize();

	function frame(object) {
		const box = new THREE.Box3().setFromObject(object);
		const sphere = box.getBoundingSphere(new THREE.Sphere());
		const distance = frameDistance(sphere.radius, camera.aspect);
		camera.position.copy(sphere.center).add(new THREE.Vector3(...frameDirection()).multiplyScalar(distance));
		camera.near = distance / 100;
		camera.far = distance * 10;
		camera.updateProjectionMatrix();
		controls.target.copy(sphere.center);
		controls.update();
		return sphere;
	}

	function setBackLight(on, sphere) {
		// the key light from the front (above and right of the camera), or behind the object as seen from the
		// camera (so translucency shows)
		const toEye = new THREE.Vector3().subVectors(camera.position, controls.target).normalize();
		const dir = new THREE.Vector3(...keyDirection(toEye.toArray(), on));
		key.position.copy(sphere.center).addScaledVector(dir, sphere.radius * 4);
		key.target.position.copy(sphere.center);
	}

	const on = listParam('on');
	// the view and lights drawn, world space (towards the light), for a page of the other engine (?view=)
	function publishView() {
		scene.updateMatrixWorld(true);
		const towards = (light) => new THREE.Vector3().setFromMatrixPosition(light.matrixWorld)
			.sub(new THREE.Vector3().setFromMatrixPosition(light.target.matrixWorld)).normalize().toArray();
		window.__bakerView = { eye: camera.position.toArray(), target: controls.target.toArray(), near: camera.near,
			far: camera.far, key: towards(key), fill: towards(fill) };
	}

	async function show(url, name) {
		try {
			const gltf = await load(url);
			if (root) scene.remove(root);
			root = gltf.scene;
			scene.add(root);
			let sphere = frame(root);
			const baker = gltf.userData.baker;
			const found = baker ? baker.techniques : [];
			showToggles(baker, found, TECHNIQUES);
			// the light from behind (translucency; hair's forward scattering) only when asked for: ?on=backlight or
			// its checkbox
			const backLit = BACK_LIT.some((t) => found.includes(t));
			let back = backLit && on.has('backlight');
			setBackLight(back, sphere);
			if (backLit) addToggle('light from behind', 'backlight', back, (v) => { back = v; setBackLight(v, sphere); publishView(); });
			reframe = () => { sphere = frame(root); setBackLight(back, sphere); publishView(); };
			publishView();
			const missing = baker?.unsupported?.length ? ` (not drawn by this renderer: ${baker.unsupported.join(', ')})` : '';
			status.textContent = `${name}: ${found.length ? found.join(', ') : 'no baked data found'}${missing}`;
			window.__bakerTechniques = found;
			window.__bakerSwitch = (names, v) => switchTechniques(baker, names, v); // for tests
			window.__bakerReadyMs = performance.now();
			window.__bakerReady = true;
		} catch (e) {
			fail(`cannot load ${name}: ${e.message || e}`);
		}
	}

	let reframe = () => {};
	frontSwitch(() => reframe());
	onDroppedFile((file) => show(URL.createObjectURL(file), file.name));
	if (params.get('src')) show(params.get('src'), params.get('src'));
	// for benchmarks/three_webgpu.py: the renderer and scene, and when the first frame with the asset was drawn
	window.__bakerThree = { renderer, scene, camera };
	renderer.setAnimationLoop(() => {
		renderer.render(scene, camera);
		if (window.__bakerReadyMs !== undefined && window.__bakerFirstFrameMs === undefined) window.__bakerFirstFrameMs = performance.now();
	});
}
