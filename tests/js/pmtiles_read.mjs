// pmtiles_read.mjs - the tests' independent PMTiles reader: npm pmtiles
// (protomaps' own decoder, the one MapLibre's pmtiles protocol uses)
// reads ARCHIVE through a Source on Node's file API and checks it
// against the z/x/y tree TREE: every tile of the tree read by getZxy is
// byte-identical to its file, and the tiles its directories list (root
// and leaves walked through the reader's cache, runs expanded) are
// exactly the tree's. Prints one JSON object: the header, the metadata,
// the counts and the first differences; exit 0 when there are none.
//
// usage: node pmtiles_read.mjs ARCHIVE TREE
import fs from "node:fs";
import path from "node:path";
import { PMTiles, tileIdToZxy } from "pmtiles";

class NodeFileSource {
	constructor(file) {
		this.file = file;
		this.fd = fs.openSync(file, "r");
	}
	getKey() {
		return this.file;
	}
	async getBytes(offset, length) {
		const buf = Buffer.alloc(length);
		const n = fs.readSync(this.fd, buf, 0, length, offset);
		return { data: buf.buffer.slice(buf.byteOffset, buf.byteOffset + n) };
	}
}

// "z/x/y" -> file, for every Z/X/Y.ext under tree
function treeTiles(tree) {
	const tiles = new Map();
	for (const z of fs.readdirSync(tree)) {
		if (!/^\d+$/.test(z)) continue;
		for (const x of fs.readdirSync(path.join(tree, z))) {
			for (const f of fs.readdirSync(path.join(tree, z, x))) {
				const m = /^(\d+)\.[a-z]+$/.exec(f);
				if (m) tiles.set(`${z}/${x}/${m[1]}`, path.join(tree, z, x, f));
			}
		}
	}
	return tiles;
}

// every tile id the directories list, and the number of leaves
async function archiveTiles(p, source, header) {
	const ids = [];
	let leaves = 0;
	const walk = async (offset, length) => {
		const dir = await p.cache.getDirectory(source, offset, length, header);
		for (const e of dir) {
			if (e.runLength === 0) {
				leaves++;
				await walk(header.leafDirectoryOffset + e.offset, e.length);
			} else {
				for (let k = 0; k < e.runLength; k++) ids.push(e.tileId + k);
			}
		}
	};
	await walk(header.rootDirectoryOffset, header.rootDirectoryLength);
	return { ids, leaves };
}

async function main() {
	const [archive, tree] = process.argv.slice(2);
	if (!archive || !tree) {
		console.error("usage: node pmtiles_read.mjs ARCHIVE TREE");
		process.exit(2);
	}
	const source = new NodeFileSource(archive);
	const p = new PMTiles(source);
	const header = await p.getHeader();
	delete header.etag;
	const metadata = await p.getMetadata();
	const want = treeTiles(tree);
	const out = { header, metadata, tree: want.size, read: 0, different: [],
		absent: [], extra: [] };
	for (const [key, file] of want) {
		const [z, x, y] = key.split("/").map(Number);
		const r = await p.getZxy(z, x, y);
		if (!r) {
			out.absent.push(key);
			continue;
		}
		out.read++;
		if (!Buffer.from(r.data).equals(fs.readFileSync(file))) out.different.push(key);
	}
	const { ids, leaves } = await archiveTiles(p, source, header);
	out.listed = ids.length;
	out.leaves = leaves;
	for (const id of ids) {
		const key = tileIdToZxy(id).join("/");
		if (!want.has(key)) out.extra.push(key);
	}
	const bad = out.different.length + out.absent.length + out.extra.length;
	for (const k of ["different", "absent", "extra"]) out[k] = out[k].slice(0, 5);
	console.log(JSON.stringify(out));
	process.exit(bad || ids.length !== want.size ? 1 : 0);
}

main().catch((e) => {
	console.error(`pmtiles_read: ${e.message}`);
	process.exit(1);
});
