// Driver of benchmarks/babylon_backends.py: one headless Chromium with a WebGPU adapter (SwiftShader on Vulkan; the
// four flags), each job a viewer page (?engine=babylon or babylon-webgpu); per job the page's own timings
// (window.__bakerTimings: load, ready = materials compiled and two frames drawn) and the mean time of `frames`
// frames each waited for on the device (WebGL2: a 1-pixel readPixels; WebGPU: queue.onSubmittedWorkDone()).
//   node benchmarks/babylon_backends.mjs JOBS.json     JOBS: [{url, width, height, frames}]; one JSON line per job
import { readFileSync } from 'node:fs';
import { launchChromium } from '../examples/viewer/test/chromium.mjs';

const jobs = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const browser = await launchChromium({ webgpu: true });
try {
	for (const job of jobs) {
		const page = await browser.newPage({ viewport: { width: job.width, height: job.height }, deviceScaleFactor: 1 });
		await page.goto(job.url);
		await page.waitForFunction(() => window.__bakerReady || window.__bakerError, null, { timeout: 120000 });
		const result = await page.evaluate(async (frames) => {
			if (window.__bakerError) return { error: window.__bakerError };
			const scene = window.__bakerScene;
			const engine = scene.getEngine();
			engine.stopRenderLoop();
			const pixel = new Uint8Array(4);
			const drawn = async () => {
				if (engine.isWebGPU) await engine._device.queue.onSubmittedWorkDone();
				else engine._gl.readPixels(0, 0, 1, 1, engine._gl.RGBA, engine._gl.UNSIGNED_BYTE, pixel);
			};
			const frame = async () => { engine.beginFrame(); scene.render(); engine.endFrame(); await drawn(); };
			for (let i = 0; i < 3; i++) await frame();
			const start = performance.now();
			for (let i = 0; i < frames; i++) await frame();
			return { backend: window.__bakerBackend, ...window.__bakerTimings, frame: (performance.now() - start) / frames };
		}, job.frames);
		console.log(JSON.stringify({ url: job.url, ...result }));
		await page.close();
	}
} finally {
	await browser.close();
}
