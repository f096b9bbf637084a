// What both engines' viewers share: URL parameters, the engine switch, the technique toggles, the framing and
// lights (so the two engines draw the same view: the Babylon.js page can take the three.js page's ?view=).
export const params = new URLSearchParams(location.search);
export const status = document.getElementById('status');
export const toggles = document.getElementById('toggles');
export const BACKGROUND = [0x29 / 255, 0x2b / 255, 0x30 / 255];
export const FOV_DEGREES = 35;
// HemisphereLight(0xffffff, 0x404040, 0.6), key DirectionalLight 2.0, fill DirectionalLight 1.2 (camera space)
export const HEMI = { sky: [1, 1, 1], groundSrgb: [0x40 / 255, 0x40 / 255, 0x40 / 255], intensity: 0.6 };
export const KEY_INTENSITY = 2.0;
export const FILL_INTENSITY = 1.2;
export const FILL_CAMERA_POSITION = [-1, 1.5, 2];

export function fail(message) {
	status.textContent = message;
	console.error(message);
	window.__bakerError = message;
}

export const listParam = (key) => new Set((params.get(key) || '').split(',').map((x) => x.trim()).filter(Boolean));

/** The engine select: reloads the page with ?engine=, the same asset (?src=) and the same switches. */
export function engineSwitch(current) {
	if (params.get('hud') === '0') document.getElementById('panel').style.visibility = 'hidden'; // clean screenshots
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

/** One checkbox per technique found, the ?off= / ?on= switches applied first; returns the list shown in the status. */
export function showToggles(baker, techniques, labels) {
	const off = listParam('off');
	const on = listParam('on');
	toggles.innerHTML = '';
	const found = baker ? baker.techniques : [];
	for (const technique of found) {
		if (off.has(technique)) baker.setEnabled(technique, false);
		if (on.has(technique)) baker.setEnabled(technique, true);
		const info = labels[technique] || { label: technique, extension: '' };
		addToggle(`${info.label} (${info.extension})`, technique, baker.isEnabled(technique), (v) => baker.setEnabled(technique, v));
	}
	return found;
}

export function addToggle(label, key, checked, onChange) {
	const el = document.createElement('label');
	el.innerHTML = `<input type="checkbox" ${checked ? 'checked' : ''}> ${label}`;
	el.firstChild.dataset.technique = key;
	el.firstChild.addEventListener('change', (e) => onChange(e.target.checked));
	toggles.appendChild(el);
}

// ?distance=K: the camera K times as far as the framing distance (tests draw the same view from afar)
const DISTANCE_SCALE = Number(params.get('distance')) > 0 ? Number(params.get('distance')) : 1;

/** Camera distance that fits a bounding sphere in the vertical field of view (times ?distance=). */
export function frameDistance(radius) {
	return radius / Math.sin((FOV_DEGREES / 2) * Math.PI / 180) * 1.05 * DISTANCE_SCALE;
}
export const FRAME_DIRECTION = (() => {
	const v = [0.5, 0.25, 0.85];
	const n = Math.hypot(...v);
	return v.map((x) => x / n);
})();

/** ?time=SECONDS: the caustic animation held at that time of its loop (a still a test can compare); else it runs. */
export const caustics = params.has('time') ? { time: Number(params.get('time')) } : {};

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
