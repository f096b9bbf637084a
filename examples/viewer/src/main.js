// baker viewer: drag and drop a baked .glb; one toggle per baked technique found in it.
// ?src=URL loads an asset; ?off=tam,fins switches techniques off and ?on=curvature on (names: TECHNIQUES of
// @baker/three), so a test can render the same view with and without one technique; ?time=SECONDS holds the
// caustic animation at that time; ?distance=K puts the camera K times as far as the framing distance.
// Test mode (?panel=FRAGMENT_URL&setup=JSON_URL&src=GLB_URL): renders the asset with one of `baker preview`'s
// panel shaders and the camera/uniforms the test passes, so the page can be compared with `baker preview`.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { registerBakerPlugins } from '../../../runtime-shaders/three/src/index.js';
import { shaders } from './shaders.js';
import { runThreeViewer } from './three_viewer.js';
import { bakerOn, caustics, fail, hair, params } from './ui.js';

const view = document.getElementById('view');

let renderer = null;
function createRenderer() {
	renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
	renderer.setPixelRatio(1);
	view.appendChild(renderer.domElement);
}

async function loadGLB(url) {
	const loader = bakerOn ? registerBakerPlugins(new GLTFLoader(), { shaders, caustics, hair }) : new GLTFLoader();
	// EXT_meshopt_compression (`baker bake --compress meshopt`, gltfpack, gltf-transform meshopt)
	loader.setMeshoptDecoder(MeshoptDecoder);
	// KHR_draco_mesh_compression (`gltf-transform draco`): Google's decoder, copied next to the bundles by the build
	loader.setDRACOLoader(dracoLoader());
	return loader.loadAsync(url);
}

let draco = null;
const dracoLoader = () => draco || (draco = new DRACOLoader().setDecoderPath(new URL('dist/draco/', document.baseURI).href));

// ------------------------------------------------------------------------------------------------ viewer mode
async function viewer() {
	createRenderer();
	runThreeViewer({ renderer, load: loadGLB, engine: 'three', backend: 'webgl2' });
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

const engine = params.get('engine');
// the Babylon.js pages (WebGL2 and WebGPUEngine) and the three.js WebGPURenderer page are bundles of their own
// (dist/babylon.js, dist/three_webgpu.js), loaded only when asked for
const start = params.get('panel') ? panel
	: ['babylon', 'babylon-webgpu'].includes(engine) ? () => import(new URL('./babylon.js', import.meta.url).href)
	: engine === 'three-webgpu' ? () => import(new URL('./three_webgpu.js', import.meta.url).href) : viewer;
start().catch((e) => fail(String(e && e.stack || e)));
