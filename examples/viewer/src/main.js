// baker viewer: drag and drop a baked .glb; one toggle per baked technique found in it.
// ?src=URL loads an asset; ?off=tam,fins switches techniques off and ?on=curvature on (names: TECHNIQUES of
// @baker/three), so a test can render the same view with and without one technique; ?time=SECONDS holds the
// caustic animation at that time; ?distance=K puts the camera K times as far as the framing distance.
// Test mode (?panel=FRAGMENT_URL&setup=JSON_URL&src=GLB_URL): renders the asset with one of `baker preview`'s
// panel shaders and the camera/uniforms the test passes, so the page can be compared with `baker preview`.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { registerBakerPlugins, TECHNIQUES } from '../../../runtime-shaders/three/src/index.js';
import { shaders } from './shaders.js';
import {
	BACKGROUND, FILL_CAMERA_POSITION, FILL_INTENSITY, FOV_DEGREES, FRAME_DIRECTION, HEMI, KEY_INTENSITY, addToggle,
	bakerOn, caustics, engineSwitch, fail, frameDistance, listParam, onDroppedFile, params, showToggles, status,
} from './ui.js';

const view = document.getElementById('view');

let renderer = null;
function createRenderer() {
	renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
	renderer.setPixelRatio(1);
	view.appendChild(renderer.domElement);
}

async function loadGLB(url) {
	const loader = bakerOn ? registerBakerPlugins(new GLTFLoader(), { shaders, caustics }) : new GLTFLoader();
	return loader.loadAsync(url);
}

// ------------------------------------------------------------------------------------------------ viewer mode
async function viewer() {
	createRenderer();
	engineSwitch('three');
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

	function resize() {
		renderer.setSize(innerWidth, innerHeight);
		camera.aspect = innerWidth / innerHeight;
		camera.updateProjectionMatrix();
	}
	addEventListener('resize', resize);
	resize();

	function frame(object) {
		const box = new THREE.Box3().setFromObject(object);
		const sphere = box.getBoundingSphere(new THREE.Sphere());
		const distance = frameDistance(sphere.radius);
		camera.position.copy(sphere.center).add(new THREE.Vector3(...FRAME_DIRECTION).multiplyScalar(distance));
		camera.near = distance / 100;
		camera.far = distance * 10;
		camera.updateProjectionMatrix();
		controls.target.copy(sphere.center);
		controls.update();
		return sphere;
	}

	function setBackLight(on, sphere) {
		// back light: behind the object as seen from the camera, so translucency shows
		const dir = new THREE.Vector3().subVectors(camera.position, controls.target).normalize();
		key.position.copy(sphere.center).addScaledVector(dir, on ? -sphere.radius * 4 : sphere.radius * 4);
		key.target.position.copy(sphere.center);
	}

	const off = listParam('off');
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
			const gltf = await loadGLB(url);
			if (root) scene.remove(root);
			root = gltf.scene;
			scene.add(root);
			const sphere = frame(root);
			const baker = gltf.userData.baker;
			const found = baker ? baker.techniques : [];
			showToggles(baker, found, TECHNIQUES);
			const back = found.includes('translucency') && !off.has('backlight');
			setBackLight(back, sphere);
			if (found.includes('translucency')) addToggle('light from behind', 'backlight', back, (v) => setBackLight(v, sphere));
			publishView();
			status.textContent = `${name}: ${found.length ? found.join(', ') : 'no baked data found'}`;
			window.__bakerTechniques = found;
			window.__bakerSwitch = (names, on) => { for (const t of names) baker?.setEnabled(t, on); }; // for tests
			window.__bakerReady = true;
		} catch (e) {
			fail(`cannot load ${name}: ${e.message || e}`);
		}
	}

	onDroppedFile((file) => show(URL.createObjectURL(file), file.name));
	if (params.get('src')) show(params.get('src'), params.get('src'));
	renderer.setAnimationLoop(() => renderer.render(scene, camera));
}

// ------------------------------------------------------------------------------------------------ panel mode
const PANEL_VERTEX = `uniform mat4 u_viewProjection;
uniform mat4 modelMatrix;
in vec3 position;
in vec3 normal;
in float a_scalar;
out vec3 v_position;
out vec3 v_normal;
out float v_scalar;
// the preview's material inputs (base colour and normal map texture coordinates, tangent): unused without textures
out vec2 v_baseUV;
out vec2 v_normalUV;
out vec4 v_tangent;
void main() {
	vec4 world = modelMatrix * vec4(position, 1.0);
	v_position = world.xyz;
	v_normal = transpose(inverse(mat3(modelMatrix))) * normal;
	v_scalar = a_scalar;
	v_baseUV = vec2(0.0);
	v_normalUV = vec2(0.0);
	v_tangent = vec4(0.0);
	gl_Position = u_viewProjection * world;
}`;

// three.js writes the #version line itself (glslVersion: GLSL3) ahead of its defines
function toES(fragment) {
	return fragment.replace('#version 330 core', 'precision highp float;\nprecision highp int;');
}

async function panel() {
	createRenderer();
	document.getElementById('panel').style.display = 'none'; // the screenshot is compared pixel by pixel
	THREE.ColorManagement.enabled = false;
	renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
	const [fragment, setup] = await Promise.all([
		fetch(params.get('panel')).then((r) => r.text()),
		fetch(params.get('setup')).then((r) => r.json()),
	]);
	const gltf = await loadGLB(params.get('src'));
	const size = setup.size;
	renderer.setSize(size, size);
	renderer.setClearColor(new THREE.Color(...setup.background), 1);
	const scene = new THREE.Scene();
	scene.add(gltf.scene);
	gltf.scene.updateMatrixWorld(true);
	const uniforms = {
		u_viewProjection: { value: new THREE.Matrix4().fromArray(setup.viewProjection) },
		u_eye: { value: new THREE.Vector3(...setup.eye) },
		u_light: { value: new THREE.Vector3(...setup.light) },
	};
	for (const [name, value] of Object.entries(setup.uniforms)) {
		const [struct, field] = name.split('.');
		const v = Array.isArray(value) ? new THREE.Vector3(...value) : value;
		if (field) (uniforms[struct] ??= { value: {} }).value[field] = v;
		else if (Array.isArray(value) && value.length === 4) uniforms[name] = { value: new THREE.Vector4(...value) };
		else uniforms[name] = { value: Array.isArray(value) && value.length === 2 ? new THREE.Vector2(...value) : v };
	}
	const material = new THREE.RawShaderMaterial({
		vertexShader: PANEL_VERTEX, fragmentShader: toES(fragment), uniforms, side: THREE.DoubleSide,
		glslVersion: THREE.GLSL3,
	});
	gltf.scene.traverse((o) => {
		if (!o.isMesh) return;
		const scalar = setup.attribute && o.geometry.getAttribute(setup.attribute.toLowerCase());
		o.geometry.setAttribute('a_scalar', scalar || new THREE.Float32BufferAttribute(new Float32Array(o.geometry.attributes.position.count), 1));
		o.material = material;
		o.frustumCulled = false; // the placeholder camera below has no frustum
	});
	const camera = new THREE.Camera(); // unused: the shader takes u_viewProjection
	renderer.render(scene, camera);
	window.__bakerReady = true;
}

const engine = ['babylon', 'babylon-webgpu'].includes(params.get('engine')) ? 'babylon' : 'three';
// the Babylon.js page is its own bundle (dist/babylon.js), loaded only when asked for
const start = params.get('panel') ? panel : engine === 'babylon' ? () => import(new URL('./babylon.js', import.meta.url).href) : viewer;
start().catch((e) => fail(String(e && e.stack || e)));
