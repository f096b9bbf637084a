// Screenshot several viewer pages in one headless Chromium (Debian's): one browser launch for a whole test.
//   node test/screenshots.mjs JOBS.json       JOBS.json: [{"url": ..., "out": ..., "width": 480, "height": 360}, ...]
//   a job may add "shots": [{"on": [techniques], "off": [techniques], "out": ...}, ...]: switched in the loaded page
// Prints one JSON line per job, {url, errors, warnings, status, techniques, ready, view, backend, error}. Used by tests/test_viewer.py and tests/test_babylon.py.
import { readFileSync } from 'node:fs';
import { chromium } from 'playwright-core';

const jobs = JSON.parse(readFileSync(process.argv[2], 'utf8'));
// BAKER_WEBGPU=1: a browser with a WebGPU adapter (SwiftShader on Vulkan: all four flags are needed), whose WebGL2
// pages draw through ANGLE's SwiftShader as well, so one run shoots both backends
const GPU_ARGS = process.env.BAKER_WEBGPU === '1'
	? ['--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader', '--use-angle=swiftshader']
	: ['--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];
const browser = await chromium.launch({
	executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
	args: ['--headless', '--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking',
		'--disable-component-update', '--disable-sync', ...GPU_ARGS],
});
try {
	for (const job of jobs) {
		const errors = [];
		const warnings = [];
		const page = await browser.newPage({ viewport: { width: job.width || 480, height: job.height || 360 }, deviceScaleFactor: 1 });
		page.on('console', (msg) => {
			if (msg.type() === 'error') errors.push(msg.text());
			// three.js reports shader problems as errors, program info logs that are not fatal as warnings; Babylon.js
			// logs its warnings as "BJS - ..."; Chromium relays WebGL warnings as "[.WebGL-...]" or "WebGL: ..."
			// (not the driver's "GPU stall due to ReadPixels" performance note: that is the screenshot reading pixels back)
			const text = msg.text();
			if (msg.type() === 'warning' && /THREE\.WebGL(Program|Shader)|^BJS -|WebGL|WebGPU|WGSL/.test(text) &&
				!/GL Driver Message \(OpenGL, Performance/.test(text)) warnings.push(text);
		});
		page.on('pageerror', (err) => errors.push(String(err)));
		await page.goto(job.url);
		await page.waitForFunction(() => window.__bakerReady || window.__bakerError, null, { timeout: 60000 });
		await page.waitForTimeout(300); // let the animation loop draw a frame
		const status = await page.evaluate(() => document.getElementById('status').textContent);
		const techniques = await page.evaluate(() => window.__bakerTechniques || []);
		const ready = await page.evaluate(() => Boolean(window.__bakerReady));
		const view = await page.evaluate(() => window.__bakerView || null);
		const backend = await page.evaluate(() => window.__bakerBackend || null);
		const error = await page.evaluate(() => window.__bakerError || null);
		if (job.out) await page.locator('canvas').screenshot({ path: job.out });
		// shots: the same page with techniques switched (window.__bakerSwitch) between screenshots, one load for all
		for (const shot of job.shots || []) {
			await page.evaluate(({ on, off }) => { window.__bakerSwitch(off, false); window.__bakerSwitch(on, true); }, shot);
			await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
			await page.waitForTimeout(100);
			await page.locator('canvas').screenshot({ path: shot.out });
		}
		console.log(JSON.stringify({ url: job.url, errors, warnings, status, techniques, ready, view, backend, error }));
		await page.close();
	}
} finally {
	await browser.close();
}
