// cesium.js [--noskirts] [--sse N] [--fovy DEG] [--shot OUT.png] TILESET VIEW...:
// CesiumJS (Build/Cesium of npm cesium) in headless Chromium, served
// with cesium.html and the tileset directory TILESET from a free
// localhost port, draws the tileset from each VIEW (heading,pitch,range
// [,levels]: degrees, degrees, range in root bounding-sphere radii,
// least count of distinct levels drawn, default 1) once every tile it
// wants is loaded, and checks the picture: no console errors; background
// (exact magenta) at the frame's border; the terrain (every other pixel)
// covers a fifth of the frame and, where the tileset's root bounding box
// projects whole, lies within it and covers half of it; no background
// pixel is enclosed by terrain (a crack). One line per view on stdout;
// exit 1 when a check fails, 2 on usage or a broken browser.
// --shot writes the first view's picture; --fovy sets the vertical field
// of view (Cesium's default: 60 degrees across the wider side); each line
// ends with the triangles drawn and the camera (eye and target, lon lat
// h) for scripts/bench-cesium. CHROMIUM: the browser (default
// /usr/bin/chromium).
'use strict';
const http = require('http');
const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');

const usage = 'usage: cesium.js [--noskirts] [--sse N] [--fovy DEG] [--shot OUT.png] TILESET VIEW...';
const a = process.argv.slice(2);
const opt = { noskirts: false, sse: 16, shot: null, fovy: 0 };
while (a.length && a[0].startsWith('--')) {
	const o = a.shift();
	if (o === '--noskirts') opt.noskirts = true;
	else if (o === '--sse' && a.length) opt.sse = Number(a.shift());
	else if (o === '--shot' && a.length) opt.shot = a.shift();
	else if (o === '--fovy' && a.length) opt.fovy = Number(a.shift());
	else { console.error(usage); process.exit(2); }
}
if (a.length < 2 || !fs.existsSync(path.join(a[0], 'tileset.json'))) {
	console.error(usage); process.exit(2);
}
const tiles = path.resolve(a[0]);
const views = a.slice(1).map((v) => v.split(',').map(Number));
if (views.some((v) => v.length < 3 || v.length > 4 || v.some(isNaN))) {
	console.error(usage); process.exit(2);
}

// A static server, three roots, nothing outside them.
const roots = { '/tiles/': tiles,
    '/cesium/': path.join(__dirname, 'node_modules/cesium/Build/Cesium') };
const types = { '.html': 'text/html', '.js': 'text/javascript',
    '.json': 'application/json', '.glb': 'model/gltf-binary',
    '.css': 'text/css', '.wasm': 'application/wasm', '.png': 'image/png',
    '.svg': 'image/svg+xml', '.xml': 'text/xml' };
const server = http.createServer((req, res) => {
	const u = decodeURIComponent(new URL(req.url, 'http://x').pathname);
	let f = u === '/' ? path.join(__dirname, 'cesium.html') : null;
	for (const r in roots)
		if (u.startsWith(r)) {
			f = path.join(roots[r], path.normalize(u.slice(r.length)));
			if (!f.startsWith(roots[r] + path.sep)) f = null;
		}
	fs.readFile(f || '', (err, data) => {
		if (err) { res.writeHead(404); res.end(); return; }
		res.writeHead(200, { 'Content-Type':
		    types[path.extname(f)] || 'application/octet-stream' });
		res.end(data);
	});
});

// Pixels of the terrain: anything but the background's exact colour.
function terrain(rgb, n) {
	const t = new Uint8Array(n);
	for (let i = 0; i < n; i++)
		t[i] = !(rgb[3 * i] === 255 && rgb[3 * i + 1] === 0 &&
		    rgb[3 * i + 2] === 255);
	return t;
}

// Background pixels not reached by a 4-connected fill from the border.
function holes(t, w, h) {
	const seen = new Uint8Array(w * h), stack = [];
	const push = (i) => { if (!t[i] && !seen[i]) { seen[i] = 1; stack.push(i); } };
	for (let x = 0; x < w; x++) push(x), push((h - 1) * w + x);
	for (let y = 0; y < h; y++) push(y * w), push(y * w + w - 1);
	while (stack.length) {
		const i = stack.pop(), x = i % w;
		if (x > 0) push(i - 1);
		if (x < w - 1) push(i + 1);
		if (i >= w) push(i - w);
		if (i < w * (h - 1)) push(i + w);
	}
	let n = 0;
	for (let i = 0; i < w * h; i++) n += !t[i] && !seen[i];
	return n;
}

// Convex hull (monotone chain) of points, counter-clockwise.
function hull(p) {
	p = p.slice().sort((u, v) => u[0] - v[0] || u[1] - v[1]);
	const cr = (o, u, v) => (u[0] - o[0]) * (v[1] - o[1]) - (u[1] - o[1]) * (v[0] - o[0]);
	const lo = [], up = [];
	for (const q of p) {
		while (lo.length > 1 && cr(lo[lo.length - 2], lo[lo.length - 1], q) <= 0) lo.pop();
		lo.push(q);
	}
	for (const q of p.reverse()) {
		while (up.length > 1 && cr(up[up.length - 2], up[up.length - 1], q) <= 0) up.pop();
		up.push(q);
	}
	return lo.slice(0, -1).concat(up.slice(0, -1));
}

// Distance in pixels by which (x, y) lies outside the convex polygon c
// (0 inside).
function outside(c, x, y) {
	let d = 0;
	for (let i = 0; i < c.length; i++) {
		const [x0, y0] = c[i], [x1, y1] = c[(i + 1) % c.length];
		const ex = x1 - x0, ey = y1 - y0, l = Math.hypot(ex, ey);
		// counter-clockwise: inside is left of each edge
		d = Math.max(d, (ey * (x - x0) - ex * (y - y0)) / l);
	}
	return d;
}

// The checks of one picture; returns [line, failures].
function check(name, r, nlevels) {
	const w = r.width, h = r.height, n = w * h;
	const rgb = Buffer.from(r.rgb, 'base64');
	const t = terrain(rgb, n);
	const bad = [];
	let area = 0, x0 = w, x1 = -1, y0 = h, y1 = -1, out = 0;
	// the box's hull, when every corner is in front of the camera
	const c = r.corners.every(Boolean) ? hull(r.corners) : null;
	for (let i = 0; i < n; i++) {
		if (!t[i]) continue;
		const x = i % w, y = (i - x) / w;
		area++;
		x0 = Math.min(x0, x), x1 = Math.max(x1, x);
		y0 = Math.min(y0, y), y1 = Math.max(y1, y);
		if (c && outside(c, x + 0.5, y + 0.5) > 1.5) out++;
	}
	// the hull's area within the frame, counted on the pixel grid
	let inHull = 0;
	if (c)
		for (let y = 0; y < h; y++)
			for (let x = 0; x < w; x++)
				inHull += outside(c, x + 0.5, y + 0.5) <= 0;
	let edge = 0;	// background pixels on the border
	for (let x = 0; x < w; x++) edge += !t[x] + !t[n - w + x];
	for (let y = 0; y < h; y++) edge += !t[y * w] + !t[y * w + w - 1];
	const k = holes(t, w, h);
	const lv = r.levels.map(([l, m]) => `${l}:${m}`).join(' ');
	const line = `${name}: levels drawn (level:tiles) ${lv}; terrain ` +
	    `${(100 * area / n).toFixed(1)}% of ${w}x${h}, bbox ${x0}-${x1} x ` +
	    `${y0}-${y1}, ${c ? (100 * area / inHull).toFixed(1) : '-'}% of ` +
	    `the projected bounding box, ${out} pixels outside it; ${k} holes; ` +
	    `${r.triangles} triangles; camera ${r.camera.flat().map((v) => v.toFixed(7)).join(' ')}`;
	// else a wrong background colour would pass the crack test
	if (!edge)
		bad.push('no background on the frame\'s border: is it exact magenta?');
	if (r.levels.length < nlevels)
		bad.push(`${r.levels.length} levels drawn, < ${nlevels}`);
	if (area < 0.2 * n)
		bad.push(`terrain covers ${(100 * area / n).toFixed(1)}% of the frame, < 20%`);
	if (c && out > 0)
		bad.push(`${out} terrain pixels outside the projected bounding box`);
	// a bounding box of a terrain is not its hull, but most of it: a
	// tenth of it black would be tiles missing
	if (c && area < 0.5 * inHull)
		bad.push(`terrain covers ${(100 * area / inHull).toFixed(1)}% of the projected box, < 50%`);
	if (k > 0)
		bad.push(`${k} background pixels enclosed by terrain (cracks)`);
	return [line, bad];
}

async function main() {
	await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
	const url = `http://127.0.0.1:${server.address().port}/` +
	    `?sse=${opt.sse}${opt.noskirts ? '&noskirts=1' : ''}` +
	    `${opt.fovy ? '&fovy=' + opt.fovy : ''}`;
	// software WebGL 2 (SwiftShader through ANGLE); no sandbox: CI is root
	const browser = await chromium.launch({
		executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
		args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader',
		    '--no-sandbox', '--disable-gpu-sandbox'],
	});
	let failed = 0;
	try {
		const page = await browser.newPage({ viewport: { width: 800, height: 450 } });
		const errors = [];
		page.on('console', (m) => {
			if (m.type() === 'error') errors.push(m.text());
			else if (m.type() === 'warning') console.log(`# warning: ${m.text()}`);
		});
		page.on('pageerror', (e) => errors.push(String(e)));
		page.on('response', (r) => {
			if (r.status() >= 400) errors.push(`${r.status()} ${r.url()}`);
		});
		page.setDefaultTimeout(120000);
		await page.goto(url);
		await page.evaluate(() => window.ready);
		for (let i = 0; i < views.length; i++) {
			const r = await page.evaluate((v) => window.view(...v), views[i]);
			const [line, bad] = check(`view ${views[i].join(',')}`, r,
			    views[i][3] || 1);
			console.log(line);
			for (const b of bad) console.error(`cesium.js: view ${views[i].join(',')}: ${b}`);
			failed += bad.length;
			if (opt.shot && i === 0)
				fs.writeFileSync(opt.shot, Buffer.from(r.png.split(',')[1], 'base64'));
		}
		for (const e of errors) console.error(`cesium.js: console error: ${e}`);
		failed += errors.length;
	} finally {
		await browser.close();
		server.close();
	}
	return failed ? 1 : 0;
}

main().then((s) => process.exit(s), (e) => {
	console.error(`cesium.js: ${e.message || e}`);
	server.close();
	process.exit(2);
});
