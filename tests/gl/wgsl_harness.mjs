// Evaluate WGSL in headless Chromium's WebGPU (SwiftShader on Vulkan): tests/gl/wgsl.py writes the jobs, this
// script runs them all in one page and prints one JSON line per job.
//   node tests/gl/wgsl_harness.mjs JOBS.json
// A job is {name, code, stage: "validate" | "compute" | "fragment", count, stride, inputs (base64 float32),
// width (fragment: fragments per row), textures: [{dimension: "2d" | "2d-array", width, height, layers,
// levels: [base64 float32 RGBA per mip level], address: "clamp-to-edge" | "repeat"}]}.
// "validate" compiles `code` alone and reports getCompilationInfo(); "compute" and "fragment" also run it: binding
// 0 holds `inputs`, binding 1 receives count x stride float32 outputs, texture k and its sampler are bindings
// 2 + 2k and 3 + 2k. The result is {name, messages: [{type, message, line, column}], outputs (base64 float32),
// error}. No adapter is an error for every job (the test fails, it never skips).
import { createRequire } from 'node:module';
import { readFileSync } from 'node:fs';

const require = createRequire(new URL('../../examples/viewer/package.json', import.meta.url));
const { chromium } = require('playwright-core');

const jobs = JSON.parse(readFileSync(process.argv[2], 'utf8'));
// All four are needed for a WebGPU adapter in headless Chromium here: without them requestAdapter() gives null.
const browser = await chromium.launch({
	executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
	args: ['--headless', '--no-sandbox', '--no-first-run', '--disable-background-networking', '--disable-component-update',
		'--disable-sync', '--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader',
		'--use-angle=swiftshader'],
});
try {
	const page = await browser.newPage();
	// navigator.gpu exists only in a secure context: localhost is one, served here without a server
	await page.route('http://localhost/**', (route) => route.fulfill({ body: '<!doctype html><title>wgsl</title>',
		contentType: 'text/html' }));
	await page.goto('http://localhost/');
	const results = await page.evaluate(runJobs, jobs);
	for (const result of results) console.log(JSON.stringify(result));
} finally {
	await browser.close();
}

async function runJobs(jobs) {
	const decode = (text) => {
		const bytes = Uint8Array.from(atob(text), (c) => c.charCodeAt(0));
		return new Float32Array(bytes.buffer);
	};
	const encode = (floats) => {
		const bytes = new Uint8Array(floats.buffer, floats.byteOffset, floats.byteLength);
		let text = '';
		for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
		return btoa(text);
	};
	const adapter = navigator.gpu ? await navigator.gpu.requestAdapter() : null;
	if (!adapter) return jobs.map((job) => ({ name: job.name, error: 'no WebGPU adapter (navigator.gpu.requestAdapter() gave null)' }));
	// rgba32float textures are filterable only with this feature (the twins sample float32 texels)
	if (!adapter.features.has('float32-filterable')) {
		return jobs.map((job) => ({ name: job.name, error: 'the WebGPU adapter lacks float32-filterable' }));
	}
	const device = await adapter.requestDevice({ requiredFeatures: ['float32-filterable'] });
	const results = [];
	for (const job of jobs) {
		const result = { name: job.name };
		try {
			const module = device.createShaderModule({ code: job.code });
			const info = await module.getCompilationInfo();
			result.messages = info.messages.map((m) => ({ type: m.type, message: m.message, line: m.lineNum, column: m.linePos }));
			if (job.stage !== 'validate' && !result.messages.some((m) => m.type === 'error')) {
				result.outputs = encode(await run(device, module, job, decode));
			}
		} catch (error) {
			result.error = String(error && error.message || error);
		}
		results.push(result);
	}
	return results;

	async function run(device, module, job, decode) {
		device.pushErrorScope('validation');
		const inputs = decode(job.inputs);
		const inputBuffer = device.createBuffer({ size: Math.max(inputs.byteLength, 16), usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_DST });
		device.queue.writeBuffer(inputBuffer, 0, inputs);
		const outputBytes = job.count * job.stride * 4;
		const outputBuffer = device.createBuffer({ size: outputBytes, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC });
		const readback = device.createBuffer({ size: outputBytes, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
		const entries = [{ binding: 0, resource: { buffer: inputBuffer } }, { binding: 1, resource: { buffer: outputBuffer } }];
		(job.textures || []).forEach((spec, k) => {
			const layers = spec.layers || 1;
			const texture = device.createTexture({
				size: [spec.width, spec.height, layers], format: 'rgba32float', mipLevelCount: spec.levels.length,
				usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST,
			});
			spec.levels.forEach((level, mip) => {
				const w = Math.max(spec.width >> mip, 1);
				const h = Math.max(spec.height >> mip, 1);
				device.queue.writeTexture({ texture, mipLevel: mip }, decode(level), { bytesPerRow: w * 16, rowsPerImage: h },
					[w, h, layers]);
			});
			const sampler = device.createSampler({
				addressModeU: spec.address, addressModeV: spec.address, magFilter: 'linear', minFilter: 'linear',
				mipmapFilter: 'linear',
			});
			entries.push({ binding: 2 + 2 * k, resource: texture.createView({ dimension: spec.dimension }) });
			entries.push({ binding: 3 + 2 * k, resource: sampler });
		});
		const encoder = device.createCommandEncoder();
		if (job.stage === 'compute') {
			const pipeline = device.createComputePipeline({ layout: 'auto', compute: { module, entryPoint: 'main' } });
			const pass = encoder.beginComputePass();
			pass.setPipeline(pipeline);
			pass.setBindGroup(0, device.createBindGroup({ layout: pipeline.getBindGroupLayout(0), entries }));
			pass.dispatchWorkgroups(Math.ceil(job.count / 64));
			pass.end();
		} else {
			// one fragment per sample: a full-viewport triangle over a width x (count / width) target
			const pipeline = device.createRenderPipeline({
				layout: 'auto', vertex: { module, entryPoint: 'vertex_main' },
				fragment: { module, entryPoint: 'fragment_main', targets: [{ format: 'rgba8unorm' }] },
			});
			const target = device.createTexture({ size: [job.width, job.count / job.width], format: 'rgba8unorm',
				usage: GPUTextureUsage.RENDER_ATTACHMENT });
			const pass = encoder.beginRenderPass({ colorAttachments: [{ view: target.createView(), loadOp: 'clear', storeOp: 'store',
				clearValue: [0, 0, 0, 0] }] });
			pass.setPipeline(pipeline);
			pass.setBindGroup(0, device.createBindGroup({ layout: pipeline.getBindGroupLayout(0), entries }));
			pass.draw(3);
			pass.end();
		}
		encoder.copyBufferToBuffer(outputBuffer, 0, readback, 0, outputBytes);
		device.queue.submit([encoder.finish()]);
		const failure = await device.popErrorScope();
		if (failure) throw new Error(`WebGPU validation: ${failure.message}`);
		await readback.mapAsync(GPUMapMode.READ);
		const outputs = new Float32Array(readback.getMappedRange().slice(0));
		readback.unmap();
		return outputs;
	}
}
