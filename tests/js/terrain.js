// terrain.js [--3dtiles] [--noskirts] [--imagery] [--lit] [--drape IMAGE]
//     [--sse N] [--size WxH] [--shot OUT.png] [--samples FILE]
//     TERRAIN W,S,E,N VIEW...:
// the quantized-mesh terrain directory TERRAIN (layer.json and
// {z}/{x}/{y}.terrain, served as plain files, no special headers) as
// CesiumJS's globe terrain (CesiumTerrainProvider.fromUrl) in headless
// Chromium, with a checkerboard draped on the rectangle W,S,E,N (degrees)
// through SingleTileImageryProvider (terrain.html); --drape: the image
// file IMAGE (PNG or JPEG, north up, covering W,S,E,N, e.g. gdaldem's
// hillshade or color-relief of the DEM) instead, for pictures. Each VIEW
// (lon,lat,height,heading,pitch[,levels]: degrees, metres above the
// ellipsoid, degrees; least count of distinct levels drawn, default 1)
// is drawn once every tile it wants is loaded and checked: no background
// pixel (exact magenta) enclosed by globe (a crack). --imagery: the
// first view is the imagery's: the checkerboard's colours cover at least
// half of the rectangle's projection and hardly anything outside it (the
// imagery on the terrain); the others must show background (the sky:
// else the crack check could not see one). --lit: lit by a low sun
// through the tiles' normals, on a dark sky, no checks (a picture).
// Over all views: every level 0 to layer.json's maxzoom fetched, no
// request failed, no console error. --samples: lines "lon lat height"
// (height above the ellipsoid, the DEM's); CesiumJS's
// sampleTerrainMostDetailed at each (a line "sample LON LAT HEIGHT
// level L CesiumJS H") must be at level maxzoom and agree within its
// E_L = 77067.34 m / 2^maxzoom. --3dtiles: TERRAIN is the 3D Tiles
// terrain profile (tileset.json, r0/ and r1/: vgis2terrain -f 3dtiles)
// through Cesium3DTilesTerrainProvider.fromUrl, the same checks, its
// levels' tiles its glbs, maxzoom its implicit tiling's availableLevels - 1,
// E_L its own 78271.52 m / 2^L. One line per check on stdout; exit 1
// when a check fails, 2 on usage or a broken browser. --shot writes the
// last view's picture; --size: the frame in pixels (default 480x270:
// SwiftShader's time goes with the pixels). CHROMIUM: the browser
// (default /usr/bin/chromium).
'use strict';
const http = require('http');
const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');

const usage = 'usage: terrain.js [--3dtiles] [--noskirts] [--imagery] [--lit] [--drape IMAGE] [--sse N] [--size WxH] [--shot OUT.png] [--samples FILE] TERRAIN W,S,E,N VIEW...';
const a = process.argv.slice(2);
const opt = { t3: false, noskirts: false, imagery: false, lit: false, drape: null, sse: 2, shot: null, samples: null, size: [480, 270] };
while (a.length && a[0].startsWith('--')) {
	const o = a.shift();
	if (o === '--3dtiles') opt.t3 = true;
	else if (o === '--noskirts') opt.noskirts = true;
	else if (o === '--imagery') opt.imagery = true;
	else if (o === '--lit') opt.lit = true;
	else if (o === '--drape' && a.length) opt.drape = path.resolve(a.shift());
	else if (o === '--sse' && a.length) opt.sse = Number(a.shift());
	else if (o === '--shot' && a.length) opt.shot = a.shift();
	else if (o === '--samples' && a.length) opt.samples = a.shift();
	else if (o === '--size' && a.length) opt.size = a.shift().split('x').map(Number);
	else { console.error(usage); process.exit(2); }
}
if (a.length < 3 ||
    !fs.existsSync(path.join(a[0], opt.t3 ? 'tileset.json' : 'layer.json'))) {
	console.error(usage); process.exit(2);
}
const terrainDir = path.resolve(a[0]);
const rect = a[1].split(',').map(Number);
const views = a.slice(2).map((v) => v.split(',').map(Number));
if (rect.length !== 4 || rect.some(isNaN) || opt.size.length !== 2 ||
    !opt.size.every((v) => v >= 16) ||
    views.some((v) => v.length < 5 || v.length > 6 || v.some(isNaN))) {
	console.error(usage); process.exit(2);
}
const samples = opt.samples ? fs.readFileSync(opt.samples, 'utf8').trim()
    .split('\n').map((l) => l.trim().split(/\s+/).map(Number)) : [];
// the level-0 error each provider assumes (getLevelMaximumGeometricError):
// a 65-sample heightmap's for quantized-mesh, a 64-sample one's for 3D Tiles
const E0 = 6378137 * 2 * Math.PI * 0.25 / ((opt.t3 ? 64 : 65) * 2);

// A plain static server: two roots, nothing outside them, no encoding.
const roots = { '/terrain/': terrainDir,
    '/cesium/': path.join(__dirname, 'node_modules/cesium/Build/Cesium') };
const types = { '.html': 'text/html', '.js': 'text/javascript',
    '.json': 'application/json', '.css': 'text/css',
    '.wasm': 'application/wasm', '.png': 'image/png', '.jpg': 'image/jpeg',
    '.svg': 'image/svg+xml', '.xml': 'text/xml' };
const server = http.createServer((req, res) => {
	const u = decodeURIComponent(new URL(req.url, 'http://x').pathname);
	let f = u === '/' ? path.join(__dirname, 'terrain.html') :
	    u === '/drape' && opt.drape ? opt.drape : null;
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

// Inside the quadrilateral q (window pixels, either winding), by at
// least m pixels (m < 0: within -m pixels outside).
function inside(q, x, y, m) {
	let s = 0, d = Infinity;
	for (let i = 0; i < 4; i++) {
		const [x0, y0] = q[i], [x1, y1] = q[(i + 1) % 4];
		const ex = x1 - x0, ey = y1 - y0;
		const c = (ex * (y - y0) - ey * (x - x0)) / Math.hypot(ex, ey);
		s += Math.sign(c);
		d = Math.min(d, Math.abs(c));
	}
	const all = Math.abs(s) === 4;
	return m >= 0 ? all && d >= m : all || d <= -m;
}

// The checks of one picture; returns [line, failures].
function check(name, r, nlevels, imagery) {
	const w = r.width, h = r.height, n = w * h;
	const rgb = Buffer.from(r.rgb, 'base64');
	const near = (i, c) => Math.abs(rgb[3 * i] - c[0]) <= 16 &&
	    Math.abs(rgb[3 * i + 1] - c[1]) <= 16 &&
	    Math.abs(rgb[3 * i + 2] - c[2]) <= 16;
	const t = new Uint8Array(n);
	let area = 0, ca = 0, cb = 0, inq = 0, cin = 0, cout = 0;
	const q = r.corners.every(Boolean) ? r.corners : null;
	for (let i = 0; i < n; i++) {
		t[i] = !(rgb[3 * i] === 255 && rgb[3 * i + 1] === 0 &&
		    rgb[3 * i + 2] === 255);
		area += t[i];
		const a = near(i, r.colours.a), b = near(i, r.colours.b);
		ca += a, cb += b;
		if (!q) continue;
		const x = i % w + 0.5, y = (i - i % w) / w + 0.5;
		if (inside(q, x, y, 0)) {
			inq++;
			cin += a || b;
		} else if ((a || b) && !inside(q, x, y, -2))
			cout++;
	}
	const k = holes(t, w, h);
	const lv = r.levels.map(([l, m]) => `${l}:${m}`).join(' ');
	let line = `${name}: levels drawn (level:tiles) ${lv}; globe ` +
	    `${(100 * area / n).toFixed(1)}% of ${w}x${h}; checkerboard ` +
	    `${(100 * ca / n).toFixed(1)}% + ${(100 * cb / n).toFixed(1)}%`;
	if (q)
		line += `, ${(100 * cin / Math.max(inq, 1)).toFixed(1)}% of the ` +
		    `rectangle's projection, ${cout} pixels outside it`;
	line += `; ${k} holes`;
	const bad = [];
	if (!imagery && area === n)
		bad.push('no background in the frame: the crack check sees nothing');
	if (r.levels.length < nlevels)
		bad.push(`${r.levels.length} levels drawn, < ${nlevels}`);
	if (imagery) {
		if (!q || inq < 0.05 * n)
			bad.push('the draped rectangle is not in the frame');
		else if (cin < 0.5 * inq || cout > 0.01 * inq)
			bad.push(`checkerboard on ${(100 * cin / inq).toFixed(1)}% of ` +
			    `the rectangle (< 50%) or ${cout} pixels outside it`);
		if (Math.min(ca, cb) < 0.2 * Math.max(ca, cb))
			bad.push('one of the checkerboard\'s colours missing');
	}
	if (k > 0)
		bad.push(`${k} background pixels enclosed by terrain (cracks)`);
	return [line, bad];
}

// sampleTerrainMostDetailed against the DEM; returns failures.
async function heights(page, maxzoom) {
	if (!samples.length) return 0;
	const got = await page.evaluate((p) => window.sample(p),
	    samples.map(([lon, lat]) => [lon, lat]));
	const el = E0 / 2 ** maxzoom;
	let worst = 0, bad = 0;
	for (let i = 0; i < samples.length; i++) {
		const [z, l] = got[i], d = Math.abs(z - samples[i][2]);
		worst = Math.max(worst, d);
		console.log(`sample ${samples[i].join(' ')} level ${l} ` +
		    `CesiumJS ${z.toFixed(4)}`);
		if (!(d <= el) || l !== maxzoom) {
			bad++;
			console.error(`terrain.js: sample ${samples[i].join(' ')}: ` +
			    `CesiumJS ${z} at level ${l}, off by ${d} m; ` +
			    `E_${maxzoom} = ${el} m`);
		}
	}
	console.log(`sampleTerrainMostDetailed: ${samples.length} samples, ` +
	    `largest difference ${worst.toFixed(3)} m = ` +
	    `${(worst / el).toFixed(3)} E_${maxzoom} (${el.toFixed(3)} m)`);
	return bad;
}

// The levels of the tiles fetched against 0..maxzoom; returns failures.
function fetched(got, maxzoom) {
	const lv = [...got].sort((x, y) => x[0] - y[0]);
	console.log(`tiles fetched (level:tiles) ${lv.map(([l, m]) => `${l}:${m}`).join(' ')}`);
	const miss = [];
	for (let l = 0; l <= maxzoom; l++)
		if (!got.has(l)) miss.push(l);
	if (miss.length)
		console.error(`terrain.js: no tile fetched at level ${miss.join(' ')} (maxzoom ${maxzoom})`);
	return miss.length;
}

async function run(page, errors, got) {
	await page.goto(`http://127.0.0.1:${server.address().port}/` +
	    `?rect=${rect.join(',')}&sse=${opt.sse}${opt.t3 ? '&t3=1' : ''}` +
	    `${opt.noskirts ? '&noskirts=1' : ''}${opt.lit ? '&lit=1' : ''}` +
	    `${opt.drape ? '&drape=1' : ''}`);
	await page.evaluate(() => window.ready);
	const maxzoom = await page.evaluate(() => window.maxzoom);
	let failed = 0;
	for (let i = 0; i < views.length; i++) {
		const r = await page.evaluate((v) => window.view(...v), views[i]);
		const name = `view ${views[i].join(',')}`;
		const [line, bad] = check(name, r, views[i][5] || 1,
		    opt.imagery && i === 0);
		console.log(line);
		if (!opt.lit) {
			for (const b of bad)
				console.error(`terrain.js: ${name}: ${b}`);
			failed += bad.length;
		}
		if (opt.shot && i === views.length - 1)
			fs.writeFileSync(opt.shot, Buffer.from(r.png.split(',')[1], 'base64'));
	}
	failed += fetched(got, maxzoom);	// the views' fetches only
	failed += await heights(page, maxzoom);
	for (const e of errors) console.error(`terrain.js: ${e}`);
	return failed + errors.length;
}

async function main() {
	await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
	// software WebGL 2 (SwiftShader through ANGLE); no sandbox: CI is root
	const browser = await chromium.launch({
		executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
		args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader',
		    '--no-sandbox', '--disable-gpu-sandbox'],
	});
	try {
		const page = await browser.newPage({ viewport: { width: opt.size[0], height: opt.size[1] } });
		const errors = [], got = new Map();
		page.on('console', (m) => {
			// CesiumJS logs a tile provider's errors (a tile that
			// fails to load or decode) with console.log
			if (m.type() === 'error' ||
			    /An error occurred in|Could not load/.test(m.text()))
				errors.push(`console error: ${m.text()}`);
			else if (m.type() === 'warning') console.log(`# warning: ${m.text()}`);
		});
		page.on('pageerror', (e) => errors.push(`page error: ${e}`));
		page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
		page.on('response', (r) => {
			if (r.status() >= 400) errors.push(`${r.status()} ${r.url()}`);
			const m = r.url().match(opt.t3 ?
			    /\/terrain\/r[01]\/(\d+)\/\d+\/\d+\.glb/ :
			    /\/terrain\/(\d+)\/\d+\/\d+\.terrain/);
			if (m && r.status() === 200)
				got.set(Number(m[1]), (got.get(Number(m[1])) || 0) + 1);
		});
		page.setDefaultTimeout(120000);
		return await run(page, errors, got) ? 1 : 0;
	} finally {
		await browser.close();
		server.close();
	}
}

main().then((s) => process.exit(s), (e) => {
	console.error(`terrain.js: ${e.message || e}`);
	server.close();
	process.exit(2);
});
