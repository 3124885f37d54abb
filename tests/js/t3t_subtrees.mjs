// t3t_subtrees.mjs - CesiumJS's own implicit-tiling reader (npm cesium,
// ImplicitTileset and ImplicitSubtree, as Cesium3DTilesTerrainProvider
// uses them) on vgis2terrain -f 3dtiles output:
//   node t3t_subtrees.mjs OUTDIR
// Walks both roots' subtrees from level 0 as the provider does (a child
// subtree where its parent says so): every tile CesiumJS finds available
// has its glb and every glb is found available; every child subtree it
// finds available exists, and no other; each available tile's
// TILE_MINIMUM_HEIGHT <= TILE_MAXIMUM_HEIGHT, TILE_BOUNDING_SPHERE of 4
// numbers with a positive radius, TILE_HORIZON_OCCLUSION_POINT defined.
// Prints a summary; exit 0 when all holds, 1 otherwise.
import fs from 'fs';
import path from 'path';
import { createRequire } from 'module';
import { fileURLToPath } from 'url';

const require = createRequire(import.meta.url);
const here = path.dirname(fileURLToPath(import.meta.url));
const C = require(require.resolve('cesium/Build/CesiumUnminified/index.cjs',
    { paths: [here, ...(process.env.NODE_PATH || '').split(':')] }));

const dir = path.resolve(process.argv[2]);
const ts = JSON.parse(fs.readFileSync(path.join(dir, 'tileset.json')));
const schema = C.MetadataSchema.fromJson(ts.schema);
const res = new C.Resource({ url: 'file://' + dir + '/tileset.json' });
let bad = 0, tiles = 0, subtrees = 0;
const seen = new Set();

function fail(m) {
	if (bad++ < 10)
		console.log('bad ' + m);
}

function fill(t, v) {
	return t.replace('{level}', v.level).replace('{x}', v.x)
	    .replace('{y}', v.y);
}

async function walk(r, json) {
	const it = new C.ImplicitTileset(res, json, schema);
	const k = it.subtreeLevels;
	const coord = (level, x, y) => new C.ImplicitTileCoordinates({
		subdivisionScheme: it.subdivisionScheme, subtreeLevels: k,
		level, x, y });
	const todo = [coord(0, 0, 0)];
	while (todo.length) {
		const sc = todo.pop();
		const f = path.join(dir, fill(json.implicitTiling.subtrees.uri, sc));
		seen.add(f), subtrees++;
		const st = await C.ImplicitSubtree.fromSubtreeJson(res, undefined,
		    new Uint8Array(fs.readFileSync(f)), it, sc);
		for (let d = 0; d < k; d++)
			for (let y = 0; y < 1 << d; y++)
				for (let x = 0; x < 1 << d; x++) {
					const c = sc.getDescendantCoordinates(
					    coord(d, x, y));
					const g = path.join(dir, fill(json.content.uri, c));
					const a = st.tileIsAvailableAtCoordinates(c);
					if (a !== fs.existsSync(g))
						fail(g + ': available ' + a);
					if (!a)
						continue;
					seen.add(g), tiles++;
					const v = st.getTileMetadataView(c);
					const lo = v.getPropertyBySemantic('TILE_MINIMUM_HEIGHT');
					const hi = v.getPropertyBySemantic('TILE_MAXIMUM_HEIGHT');
					const s = v.getPropertyBySemantic('TILE_BOUNDING_SPHERE');
					const h = v.getPropertyBySemantic(
					    'TILE_HORIZON_OCCLUSION_POINT');
					if (!(lo <= hi) || !s || s.length !== 4 ||
					    !(s[3] > 0) || h === undefined)
						fail(g + ': metadata');
				}
		for (let y = 0; y < 1 << k; y++)
			for (let x = 0; x < 1 << k; x++) {
				const c = sc.getDescendantCoordinates(coord(k, x, y));
				const g = path.join(dir,
				    fill(json.implicitTiling.subtrees.uri, c));
				const a = st.childSubtreeIsAvailableAtCoordinates(c);
				if (a !== fs.existsSync(g))
					fail(g + ': child subtree available ' + a);
				if (a)
					todo.push(c);
			}
	}
}

function files(d) {
	let out = [];
	for (const e of fs.readdirSync(d, { withFileTypes: true })) {
		const p = path.join(d, e.name);
		out = e.isDirectory() ? out.concat(files(p)) :
		    e.name === 'tileset.json' ? out : out.concat([p]);
	}
	return out;
}

const kids = ts.root.children;
if (kids.length !== 2)
	fail('not two root tiles');
for (let r = 0; r < kids.length; r++)
	await walk(r, kids[r]);
for (const f of files(dir))
	if (!seen.has(f))
		fail(f + ': not announced');
console.log(`${subtrees} subtrees, ${tiles} tiles read by CesiumJS ${C.VERSION}`);
process.exit(bad ? 1 : 0);
