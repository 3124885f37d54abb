// maplibre.js [--pmtiles FILE.pmtiles] [--shot OUT.png] [--size WxH]
//     [--view ZOOM,PITCH,BEARING] [--samples FILE] TREE: raster-dem tiles as MapLibre GL JS's terrain
// (npm maplibre-gl, maplibre.html) in headless Chromium with software
// WebGL, served as plain files from a free localhost port: the tree TREE
// (tiles.json and its {z}/{x}/{y} tiles) and, with --pmtiles, the archive
// FILE through npm pmtiles' Protocol (HTTP range requests), each route
// checked alike. --samples: lines "lon lat zoom clon clat"; at each, the
// camera straight down on clon, clat at that zoom (moved only when these
// change: one view holds several samples), every tile loaded, a line
// "sample ROUTE LON LAT ZOOM HEIGHT DEMZOOM" on stdout: map.queryTerrainElevation there
// (exaggeration 1) and the zoom of the raster-dem tile it read (the
// caller compares them with the DEM). Checks, each route: the map loads,
// raster-dem tiles fetched, no failed request (HTTP >= 400 or network),
// no console error, no page error; each sample a number read from a
// loaded tile. One line per failure on stderr ("maplibre.js: ..."); exit
// 1 when a check fails, 2 on usage or a broken browser. --shot: a
// picture of the tree's terrain, pitched, hillshaded (--size, default
// 480x270; --view, default the maxzoom + 0.5, 60 and 30 degrees). CHROMIUM: the browser (default /usr/bin/chromium).
'use strict';
const http = require('http');
const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');

const usage = 'usage: maplibre.js [--pmtiles FILE] [--shot OUT.png] [--size WxH] [--view Z,P,B] [--samples FILE] TREE';
const a = process.argv.slice(2);
const opt = { pmtiles: null, shot: null, samples: null, size: [480, 270],
    view: null };
while (a.length && a[0].startsWith('--')) {
	const o = a.shift();
	if (o === '--pmtiles' && a.length) opt.pmtiles = path.resolve(a.shift());
	else if (o === '--shot' && a.length) opt.shot = a.shift();
	else if (o === '--samples' && a.length) opt.samples = a.shift();
	else if (o === '--size' && a.length) opt.size = a.shift().split('x').map(Number);
	else if (o === '--view' && a.length) opt.view = a.shift().split(',').map(Number);
	else { console.error(usage); process.exit(2); }
}
if (a.length !== 1 || !fs.existsSync(path.join(a[0], 'tiles.json')) ||
    (opt.pmtiles && !fs.existsSync(opt.pmtiles)) ||
    opt.size.length !== 2 || !opt.size.every((v) => v >= 16) ||
    (opt.view && (opt.view.length !== 3 || opt.view.some(isNaN)))) {
	console.error(usage); process.exit(2);
}
const tree = path.resolve(a[0]);
const tj = JSON.parse(fs.readFileSync(path.join(tree, 'tiles.json'), 'utf8'));
const samples = opt.samples ? fs.readFileSync(opt.samples, 'utf8').trim()
    .split('\n').map((l) => l.trim().split(/\s+/).map(Number)) : [];
if (samples.some((s) => s.length !== 5 || s.some(isNaN))) {
	console.error(usage); process.exit(2);
}

// A plain static server, nothing outside its roots, byte ranges for the
// archive (pmtiles reads it by ranges).
const roots = { '/tiles/': tree,
    '/maplibre/': path.join(__dirname, 'node_modules/maplibre-gl/dist'),
    '/pmtiles/': path.join(__dirname, 'node_modules/pmtiles/dist') };
const types = { '.html': 'text/html', '.js': 'text/javascript',
    '.mjs': 'text/javascript', '.json': 'application/json',
    '.css': 'text/css', '.png': 'image/png', '.webp': 'image/webp' };
const server = http.createServer((req, res) => {
	const u = decodeURIComponent(new URL(req.url, 'http://x').pathname);
	let f = u === '/' ? path.join(__dirname, 'maplibre.html') :
	    u === '/archive.pmtiles' ? opt.pmtiles : null;
	for (const r in roots)
		if (u.startsWith(r)) {
			f = path.join(roots[r], path.normalize(u.slice(r.length)));
			if (!f.startsWith(roots[r] + path.sep)) f = null;
		}
	fs.readFile(f || '', (err, data) => {
		if (err) { res.writeHead(404); res.end(); return; }
		const h = { 'Content-Type': types[path.extname(f)] ||
		    'application/octet-stream', 'Accept-Ranges': 'bytes' };
		const m = /^bytes=(\d+)-(\d*)$/.exec(req.headers.range || '');
		if (m) {
			const s = Number(m[1]);
			const e = Math.min(m[2] ? Number(m[2]) : data.length - 1, data.length - 1);
			if (s > e) { res.writeHead(416); res.end(); return; }
			h['Content-Range'] = `bytes ${s}-${e}/${data.length}`;
			res.writeHead(206, h);
			res.end(data.subarray(s, e + 1));
			return;
		}
		res.writeHead(200, h);
		res.end(data);
	});
});

// One route (tree or pmtiles): load, the samples, the picture.
async function route(browser, name) {
	const page = await browser.newPage({ viewport: { width: opt.size[0], height: opt.size[1] } });
	const errors = [];
	let fetched = 0;
	page.on('console', (m) => {
		if (m.type() === 'error') errors.push(`console error: ${m.text()}`);
		else if (m.type() === 'warning') console.log(`# warning: ${m.text()}`);
	});
	page.on('pageerror', (e) => errors.push(`page error: ${e}`));
	page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()} ${r.failure() ? r.failure().errorText : ''}`));
	page.on('response', (r) => {
		if (r.status() >= 400) errors.push(`${r.status()} ${r.url()}`);
		else if (/\/tiles\/\d+\/\d+\/\d+\.\w+$|\/archive\.pmtiles$/.test(r.url()))
			fetched++;
	});
	page.setDefaultTimeout(120000);
	const c = tj.center || [(tj.bounds[0] + tj.bounds[2]) / 2,
	    (tj.bounds[1] + tj.bounds[3]) / 2, tj.maxzoom];
	const pm = name === 'pmtiles' ? `&pmtiles=1&encoding=${tj.encoding || 'mapbox'}` +
	    `&tileSize=${tj.tileSize || 512}` : '';
	await page.goto(`http://127.0.0.1:${server.address().port}/` +
	    `?center=${c[0]},${c[1]},${tj.minzoom + 2}${pm}`);
	await page.evaluate(() => window.ready);
	let bad = 0;
	for (const [lon, lat, zoom, clon, clat] of samples) {
		const [h, dz] = await page.evaluate((s) => window.query(...s),
		    [lon, lat, zoom, clon, clat]);
		console.log(`sample ${name} ${lon} ${lat} ${zoom} ${h} ${dz}`);
		if (typeof h !== 'number' || !isFinite(h) || dz < 0) {
			bad++;
			console.error(`maplibre.js: ${name}: sample ${lon} ${lat} at zoom ${zoom}: ${h} from no loaded raster-dem tile`);
		}
	}
	if (opt.shot && name === 'tree') {
		const png = await page.evaluate((v) => window.picture(...v),
		    [c[0], c[1], ...(opt.view || [tj.maxzoom + 0.5, 60, 30])]);
		fs.writeFileSync(opt.shot, Buffer.from(png.split(',')[1], 'base64'));
	}
	console.log(`${name}: ${fetched} raster-dem responses, ${samples.length} samples, ${errors.length} errors`);
	if (!fetched) errors.push('no raster-dem tile fetched');
	for (const e of errors) console.error(`maplibre.js: ${name}: ${e}`);
	await page.close();
	return bad + errors.length;
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
		let failed = await route(browser, 'tree');
		if (opt.pmtiles) failed += await route(browser, 'pmtiles');
		return failed ? 1 : 0;
	} finally {
		await browser.close();
		server.close();
	}
}

main().then((s) => process.exit(s), (e) => {
	console.error(`maplibre.js: ${e.message || e}`);
	server.close();
	process.exit(2);
});
