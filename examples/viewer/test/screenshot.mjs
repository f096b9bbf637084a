// Open a page in headless Chromium (Debian's), wait for the viewer to finish, save a screenshot of its canvas.
//   node test/screenshot.mjs URL OUT.png [WIDTH HEIGHT]
// Prints a JSON line {errors, status, ready}. Used by tests/test_viewer.py.
import { chromium } from 'playwright-core';

const [url, out, width = '512', height = '512'] = process.argv.slice(2);
const browser = await chromium.launch({
	executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
	args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
		'--disable-background-networking', '--disable-component-update', '--disable-sync', '--use-angle=swiftshader',
		'--enable-unsafe-swiftshader'],
});
const errors = [];
try {
	const page = await browser.newPage({ viewport: { width: Number(width), height: Number(height) }, deviceScaleFactor: 1 });
	page.on('console', (msg) => { if (msg.type() === 'error') errors.push(msg.text()); });
	page.on('pageerror', (err) => errors.push(String(err)));
	await page.goto(url);
	await page.waitForFunction(() => window.__bakerReady || window.__bakerError, null, { timeout: 60000 });
	await page.waitForTimeout(300); // let the animation loop draw a frame in viewer mode
	const status = await page.evaluate(() => document.getElementById('status').textContent);
	const ready = await page.evaluate(() => Boolean(window.__bakerReady));
	await page.locator('canvas').screenshot({ path: out });
	console.log(JSON.stringify({ errors, status, ready }));
} finally {
	await browser.close();
}
