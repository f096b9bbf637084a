// Screenshot viewer pages in one headless Chromium with WebGPU (SwiftShader on Vulkan): the four flags a canvas needs
// (--enable-unsafe-webgpu --enable-features=Vulkan --use-vulkan=swiftshader --use-angle=swiftshader; without them
// requestAdapter() returns null). Same jobs and output as screenshots.mjs, plus each page's window.__bakerBackend and
// window.__bakerError:
//   node test/webgpu_screenshots.mjs JOBS.json   JOBS.json: [{"url", "out", "width", "height", "shots": [...]}, ...]
// Used by tests/test_three_webgpu.py.
import { readFileSync } from 'node:fs';
import { chromium } from 'playwright-core';

const jobs = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const browser = await chromium.launch({
	executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
	args: ['--headless', '--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking',
		'--disable-component-update', '--disable-sync', '--enable-unsafe-webgpu', '--enable-features=Vulkan',
		'--use-vulkan=swiftshader', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
	for (const job of jobs) {
		const errors = [];
		const warnings = [];
		const page = await browser.newPage({ viewport: { width: job.width || 480, height: job.height || 360 }, deviceScaleFactor: 1 });
		page.on('console', (msg) => {
			const text = msg.text();
			if (msg.type() === 'error') errors.push(text);
			// three.js's node builders report through console.warn / console.error ("THREE.", "TSL:"), WebGPU's
			// validation as "WebGPU"/"WGSL"; not the driver's ReadPixels performance note
			if (msg.type() === 'warning' && /THREE\.|TSL|WebGPU|WGSL|WebGL/.test(text) &&
				!/GL Driver Message \(OpenGL, Performance/.test(text)) warnings.push(text);
		});
		page.on('pageerror', (err) => errors.push(String(err)));
		await page.goto(job.url);
		await page.waitForFunction(() => window.__bakerReady || window.__bakerError, null, { timeout: 120000 });
		// let the animation loop compile and draw (WebGPURenderer compiles the pipelines on the first frames)
		await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
		await page.waitForTimeout(job.wait ?? 500);
		const read = () => page.evaluate(() => ({
			status: document.getElementById('status').textContent, techniques: window.__bakerTechniques || [],
			ready: Boolean(window.__bakerReady), view: window.__bakerView || null, backend: window.__bakerBackend || null,
			error: window.__bakerError || null,
		}));
		const info = await read();
		if (job.out) await page.locator('canvas').screenshot({ path: job.out });
		for (const shot of job.shots || []) {
			await page.evaluate(({ on, off }) => { window.__bakerSwitch(off, false); window.__bakerSwitch(on, true); }, shot);
			await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
			await page.waitForTimeout(job.wait ?? 300);
			await page.locator('canvas').screenshot({ path: shot.out });
		}
		console.log(JSON.stringify({ url: job.url, errors, warnings, ...info }));
		await page.close();
	}
} finally {
	await browser.close();
}
