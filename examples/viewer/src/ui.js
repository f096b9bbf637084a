// What both engines' viewers share: URL parameters, the engine switch, the technique toggles, the framing and
// lights (so the two engines draw the same view: the Babylon.js page can take the three.js page's ?view=).
export const params = new URLSearchParams(location.search);
export const status = document.getElementById('status');
export const toggles = document.getElementById('toggles');
export const BACKGROUND = [0x29 / 255, 0x2b / 255, 0x30 / 255];
export const FOV_DEGREES = 35;
// The exposure: a white (glTF default) Lambert surface facing the key light, lit by the fill and the sky too, comes
// to about 0.8 linear (three.js divides a light's irradiance by pi in its Lambert BRDF: (1.6 + 0.4 x ~0.6 + 0.8 x
// ~0.8) / pi), so the lit side keeps its shading below white and the specular highlight stays under 1; the side away
// from the key gets the fill and the sky (about a quarter of it), never black.
// HemisphereLight(0xffffff, 0x404040, 0.8), key DirectionalLight 1.6 (from the front), fill DirectionalLight 0.4
export const HEMI = { sky: [1, 1, 1], groundSrgb: [0x40 / 255, 0x40 / 255, 0x40 / 255], intensity: 0.8 };
export const KEY_INTENSITY = 1.6;
export const FILL_INTENSITY = 0.4;
export const FILL_CAMERA_POSITION = [-1, 1.5, 2];
// The key light comes from the front, above and to the right of the camera (camera space: x right, y up, z towards
// the viewer), fixed in the world when the asset is framed; the back light (translucency) is off until asked for.
export const KEY_CAMERA_DIRECTION = [0.6, 0.8, 1];
// the techniques whose assets get the "light from behind" switch: translucency, and hair (strands and cards) that
// glows lit from behind (forward scattering, BAKER_hair_shading)
export const BACK_LIT = ['translucency', 'hair', 'cards'];

/**
 * The key light's world direction (towards the light) for a camera looking at the target from the unit vector
 * `toEye`: KEY_CAMERA_DIRECTION in the camera's frame (y up); `back`: behind the object, facing the camera.
 */
export function keyDirection(toEye, back = false) {
	if (back) return toEye.map((x) => -x);
	const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
	const unit = (v) => { const n = Math.hypot(...v) || 1; return v.map((x) => x / n); };
	const right = unit(cross([0, 1, 0], toEye));
	const up = cross(toEye, right);
	const [x, y, z] = KEY_CAMERA_DIRECTION;
	return unit([0, 1, 2].map((i) => x * right[i] + y * up[i] + z * toEye[i]));
}

export function fail(message) {
	status.textContent = message;
	console.error(message);
	window.__bakerError = message;
}

export const listParam = (key) => new Set((params.get(key) || '').split(',').map((x) => x.trim()).filter(Boolean));

/** The engine select: reloads the page with ?engine=, the same asset (?src=) and the same switches. */
export function engineSwitch(current) {
	const el = document.createElement('label');
	el.innerHTML = 'engine <select id="engine"><option value="three">three.js</option><option value="babylon">Babylon.js</option></select>';
	const select = el.querySelector('select');
	select.value = current;
	select.addEventListener('change', () => {
		const next = new URLSearchParams(location.search);
		next.set('engine', select.value);
		if (!next.get('src')) {
			status.textContent = 'switching engines keeps ?src= assets; drop the file again after the switch';
		}
		location.search = next.toString();
	});
	document.getElementById('panel').insertBefore(el, status);
}

/**
 * ?start=: which techniques are on when an asset loads: 'first' (the default: the first technique of the list that
 * is not a debug view, so the first picture shows one technique, not all of them stacked), 'none', or 'all' (every
 * technique but the debug views, the runtimes' own default). ?off= / ?on= are applied after it.
 */
export const START = ['first', 'none', 'all'].includes(params.get('start')) ? params.get('start') : 'first';

/** The techniques on at load: `found` (in list order) under ?start=, then ?off= / ?on=. */
export function startingTechniques(found, labels) {
	const off = listParam('off');
	const on = listParam('on');
	const shown = found.filter((t) => !labels[t]?.defaultOff);
	const start = START === 'all' ? shown : START === 'first' ? shown.slice(0, 1) : [];
	return found.filter((t) => (start.includes(t) && !off.has(t)) || on.has(t));
}

/**
 * One checkbox per technique found, in the runtimes' list order, on or off as startingTechniques says; returns the
 * list shown in the status. window.__bakerEnabled follows the switches (for tests).
 */
export function showToggles(baker, techniques, labels) {
	toggles.innerHTML = '';
	const found = baker ? baker.techniques : [];
	const enabled = new Set(startingTechniques(found, labels));
	const publish = () => { window.__bakerEnabled = found.filter((t) => baker.isEnabled(t)); };
	for (const technique of found) {
		baker.setEnabled(technique, enabled.has(technique));
		const info = labels[technique] || { label: technique, extension: '' };
		addToggle(`${info.label} (${info.extension})`, technique, baker.isEnabled(technique),
			(v) => { baker.setEnabled(technique, v); publish(); });
	}
	publish();
	return found;
}

/** window.__bakerSwitch: switch techniques in the loaded page (tests), keeping the checkboxes and __bakerEnabled. */
export function switchTechniques(baker, names, on) {
	for (const t of names) {
		baker?.setEnabled(t, on);
		const box = toggles.querySelector(`input[data-technique="${t}"]`);
		if (box && baker?.has(t)) box.checked = on;
	}
	if (baker) window.__bakerEnabled = baker.techniques.filter((t) => baker.isEnabled(t));
}

export function addToggle(label, key, checked, onChange) {
	const el = document.createElement('label');
	el.innerHTML = `<input type="checkbox" ${checked ? 'checked' : ''}> ${label}`;
	el.firstChild.dataset.technique = key;
	el.firstChild.addEventListener('change', (e) => onChange(e.target.checked));
	toggles.appendChild(el);
}

/** ?distance=K: the camera K times farther than the framing distance (e.g. alpha-tested hair cards far away). */
export const DISTANCE_SCALE = Number(params.get('distance')) > 0 ? Number(params.get('distance')) : 1;

/**
 * Camera distance that fits a bounding sphere in the field of view, the narrower of the vertical and the horizontal
 * one at the canvas' `aspect` (width / height), times ?distance=.
 */
export function frameDistance(radius, aspect = 1) {
	const half = (FOV_DEGREES / 2) * Math.PI / 180;
	const narrowest = Math.min(half, Math.atan(Math.tan(half) * aspect));
	return radius / Math.sin(narrowest) * 1.05 * DISTANCE_SCALE;
}
// glTF's front faces +Z: the camera looks down -Z at the asset, from 30 degrees to its right and 14 above
export const FRAME_DIRECTION = (() => {
	const v = [0.5, 0.25, 0.85];
	const n = Math.hypot(...v);
	return v.map((x) => x / n);
})();
/**
 * ?front=+z (glTF's convention, the default), -z, +x or -x: the axis the asset's front faces (a mesh made facing -Z
 * is seen from its front with ?front=-z); the front select of the panel changes it live.
 */
export const FRONTS = { '+z': (v) => v, '-z': ([x, y, z]) => [-x, y, -z], '+x': ([x, y, z]) => [z, y, -x],
	'-x': ([x, y, z]) => [-z, y, x] };
export let front = Object.hasOwn(FRONTS, (params.get('front') || '').replace(' ', '+')) ? params.get('front').replace(' ', '+') : '+z';
/** The unit direction from the asset's centre to the camera. */
export function frameDirection() {
	return FRONTS[front](FRAME_DIRECTION);
}

/** The front select of the panel: onChange() re-frames the asset. */
export function frontSwitch(onChange) {
	const el = document.createElement('label');
	el.innerHTML = 'front faces <select id="front">' + Object.keys(FRONTS).map((k) =>
		`<option value="${k}">${k.toUpperCase()}${k === '+z' ? ' (glTF)' : ''}</option>`).join('') + '</select>';
	const select = el.querySelector('select');
	select.value = front;
	select.addEventListener('change', () => { front = select.value; onChange(); });
	document.getElementById('panel').insertBefore(el, status);
}

/** ?time=SECONDS: the caustic animation held at that time of its loop (a still a test can compare); else it runs. */
export const caustics = params.has('time') ? { time: Number(params.get('time')) } : {};
/** ?hairShading=kajiyaKay: strands and cards shaded Kajiya-Kay instead of the fibre model (options.hair.shading). */
export const hair = params.has('hairShading') ? { shading: params.get('hairShading') } : {};

/** ?baker=0: no baker plugins/extensions, the asset as glTF's standard PBR. */
export const bakerOn = params.get('baker') !== '0';

/** Drag and drop of a .glb on the page: fn(file). */
export function onDroppedFile(fn) {
	addEventListener('dragover', (e) => { e.preventDefault(); document.body.classList.add('dragging'); });
	addEventListener('dragleave', () => document.body.classList.remove('dragging'));
	addEventListener('drop', (e) => {
		e.preventDefault();
		document.body.classList.remove('dragging');
		const file = e.dataTransfer.files[0];
		if (file) fn(file);
	});
}
