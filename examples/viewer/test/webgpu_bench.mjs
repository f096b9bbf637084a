// Shader compile and frame time of the three.js pages per backend, in one headless Chromium with WebGPU
// (./chromium.mjs). Used by benchmarks/three_webgpu.py:
//   node test/webgpu_bench.mjs JOBS.json   JOBS.json: [{"url", "width", "height", "frames"}, ...]
// Prints one JSON line per job: {url, backend, loadMs (navigation to asset ready), firstFrameMs (the render call of
// the first frame with the asset: shader generation, program linking or pipeline creation, the draw's submission),
// frameMs (mean of `frames` frames after it, each waited for on the GPU)}.
import { readFileSync } from 'node:fs';
import { launchChromium } from './chromium.mjs';

const jobs = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const browser = await launchChromium({ webgpu: true });
try {
	for (const job of jobs) {
		const page = await browser.newPage({ viewport: { width: job.width || 320, height: job.height || 240 }, deviceScaleFactor: 1 });
		await page.goto(job.url);
		await page.waitForFunction(() => window.__bakerFirstFrameMs !== undefined || window.__bakerError, null, { timeout: 180000 });
		const result = await page.evaluate(async (frames) => {
			const { renderer, scene, camera } = window.__bakerThree;
			renderer.setAnimationLoop(null);
			// wait for the GPU: WebGPU's queue, or a 1-pixel read on WebGL (finish() does not block in ANGLE)
			const gl = renderer.backend?.gl ?? (renderer.isWebGLRenderer ? renderer.getContext() : null);
			const pixel = new Uint8Array(4);
			const sync = async () => {
				if (renderer.backend?.isWebGPUBackend) await renderer.backend.device.queue.onSubmittedWorkDone();
				else gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
			};
			await sync();
			const firstFrameMs = window.__bakerFirstFrameMs - window.__bakerReadyMs;
			const start = performance.now();
			for (let i = 0; i < frames; i++) {
				renderer.render(scene, camera);
				await sync();
			}
			return { backend: window.__bakerBackend, loadMs: window.__bakerReadyMs, firstFrameMs,
				frameMs: (performance.now() - start) / frames };
		}, job.frames || 20);
		console.log(JSON.stringify({ url: job.url, ...result }));
		await page.close();
	}
} finally {
	await browser.close();
}
