// Debian's Chromium, headless, as every viewer test and page benchmark launches it (playwright-core never downloads
// a browser). webgpu: a browser with a WebGPU adapter, SwiftShader on Vulkan; all four of
// --enable-unsafe-webgpu --enable-features=Vulkan --use-vulkan=swiftshader --use-angle=swiftshader are needed for a
// canvas (without them requestAdapter() returns null), and its WebGL2 pages draw through ANGLE's SwiftShader as well,
// so one browser shoots both backends. Otherwise WebGL2 only, on ANGLE's SwiftShader.
import { chromium } from 'playwright-core';

const WEBGPU_ARGS = ['--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader',
	'--use-angle=swiftshader', '--enable-unsafe-swiftshader'];
const WEBGL_ARGS = ['--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];

export function launchChromium({ webgpu = false } = {}) {
	return chromium.launch({
		executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
		args: ['--headless', '--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking',
			'--disable-component-update', '--disable-sync', ...(webgpu ? WEBGPU_ARGS : WEBGL_ARGS)],
	});
}
