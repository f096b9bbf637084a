// Screenshot several viewer pages in one headless Chromium (Debian's): one browser launch for a whole test.
//   node test/screenshots.mjs JOBS.json       JOBS.json: [{"url": ..., "out": ..., "width": 480, "height": 360}, ...]
//   a job may add "pageOut": a screenshot of the whole page (the panel included), and "shots": [{"on": [techniques], "off": [techniques], "out": ...}, ...]: switched in the loaded page
// Prints one JSON line per job, {url, errors, warnings, status, techniques, enabled, ready, view, backend, error, rects}. Used by the
// tests/ of the web hosts (tests/browser.py shoot); BAKER_WEBGPU=1 for the WebGPU pages.
import { readFileSync } from 'node:fs';
import { launchChromium } from './chromium.mjs';

const jobs = JSON.parse(readFileSync(process.argv[2], 'utf8'));
// BAKER_WEBGPU=1: a browser with a WebGPU adapter (./chromium.mjs), for the ?engine=*-webgpu pages and their WebGL2
// twins in one run
const webgpu = process.env.BAKER_WEBGPU === '1';
const browser = await launchChromium({ webgpu });
// what counts as a warning: three.js's WebGL programs' info logs, Babylon.js's "BJS - ..." and Chromium's relayed
// WebGL/WebGPU/WGSL messages; with WebGPU also three.js's node builders ("THREE.", "TSL"); never the driver's
// "GPU stall due to ReadPixels" performance note (that is the screenshot reading pixels back)
const WARNING = webgpu ? /THREE\.|TSL|^BJS -|WebGL|WebGPU|WGSL/ : /THREE\.WebGL(Program|Shader)|^BJS -|WebGL|WebGPU|WGSL/;
try {
	for (const job of jobs) {
		const errors = [];
		const warnings = [];
		const page = await browser.newPage({ viewport: { width: job.width || 480, height: job.height || 360 }, deviceScaleFactor: 1 });
		page.on('console', (msg) => {
			const text = msg.text();
			if (msg.type() === 'error') errors.push(text);
			if (msg.type() === 'warning' && WARNING.test(text) && !/GL Driver Message \(OpenGL, Performance/.test(text)) warnings.push(text);
		});
		page.on('pageerror', (err) => errors.push(String(err)));
		await page.goto(job.url);
		await page.waitForFunction(() => window.__bakerReady || window.__bakerError, null, { timeout: webgpu ? 120000 : 60000 });
		// let the animation loop compile and draw (WebGPURenderer compiles its pipelines on the first frames)
		await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
		await page.waitForTimeout(job.wait ?? 300);
		const info = await page.evaluate(() => ({
			status: document.getElementById('status').textContent, techniques: window.__bakerTechniques || [],
			ready: Boolean(window.__bakerReady), view: window.__bakerView || null, backend: window.__bakerBackend || null,
			error: window.__bakerError || null, enabled: window.__bakerEnabled || null,
			// page rectangles (CSS pixels) of the side panel and the canvas: the panel must leave the canvas clear
			rects: Object.fromEntries([['panel', document.getElementById('panel')], ['canvas', document.querySelector('canvas')]]
				.map(([k, el]) => { const r = el?.getBoundingClientRect(); return [k, r && getComputedStyle(el).visibility !== 'hidden' && getComputedStyle(el).display !== 'none' ? [r.left, r.top, r.width, r.height] : null]; })),
		}));
		if (job.out) await page.locator('canvas').screenshot({ path: job.out });
		if (job.pageOut) await page.screenshot({ path: job.pageOut }); // the whole page, panel included
		// shots: the same page with techniques switched (window.__bakerSwitch) between screenshots, one load for all
		for (const shot of job.shots || []) {
			await page.evaluate(({ on, off }) => { window.__bakerSwitch(off, false); window.__bakerSwitch(on, true); }, shot);
			await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
			await page.waitForTimeout(webgpu ? job.wait ?? 300 : 100);
			await page.locator('canvas').screenshot({ path: shot.out });
		}
		console.log(JSON.stringify({ url: job.url, errors, warnings, ...info }));
		await page.close();
	}
} finally {
	await browser.close();
}
