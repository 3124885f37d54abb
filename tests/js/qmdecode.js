// qmdecode.js DIR - a third-party decoder of quantized-mesh-1.0 tiles
// (loaders.gl's, @loaders.gl/terrain) over every DIR/{z}/{x}/{y}.terrain
// (gzip'd ones inflated), printing per tile, sorted by z, x, y,
//   z/x/y vertices N triangles T checksum XXXXXXXX
// as `tilecheck --terrain --dump DIR` prints it from its own decoder, so
// that a test can diff the two. The checksum is FNV-1a 32 of the decoded
// u, v, heights (2 bytes each, little-endian, all u, all v, all heights)
// then the triangle indices (4 bytes each). Each tile is also parsed by
// the public QuantizedMeshLoader, whose indices and texture coordinates
// must agree with the raw decode. Exit 0, or 1 on a tile that fails.
'use strict';
const fs = require('fs');
const path = require('path');
const zlib = require('zlib');
const { pathToFileURL } = require('url');
const { parse } = require('@loaders.gl/core');
const { QuantizedMeshLoader } = require('@loaders.gl/terrain');

function fnv(hash, byte) {
  return Math.imul(hash ^ byte, 16777619) >>> 0;
}

function checksum(vertexData, indices) {
  let h = 2166136261;
  for (const q of vertexData) h = fnv(fnv(h, q & 0xff), (q >> 8) & 0xff);
  for (const i of indices)
    for (let k = 0; k < 4; k++) h = fnv(h, (i >>> (8 * k)) & 0xff);
  return h.toString(16).padStart(8, '0');
}

function tiles(dir) {
  const num = (s) => /^(0|[1-9][0-9]*)$/.test(s);
  const out = [];
  for (const z of fs.readdirSync(dir).filter(num))
    for (const x of fs.readdirSync(path.join(dir, z)).filter(num))
      for (const f of fs.readdirSync(path.join(dir, z, x))) {
        const m = /^(0|[1-9][0-9]*)\.terrain$/.exec(f);
        if (m) out.push([+z, +x, +m[1]]);
      }
  return out.sort((a, b) => a[0] - b[0] || a[1] - b[1] || a[2] - b[2]);
}

async function main() {
  const dir = process.argv[2];
  if (!dir) {
    console.error('usage: node qmdecode.js DIR');
    process.exit(2);
  }
  // the raw decoder behind QuantizedMeshLoader, not exported by name
  const lib = path.join(path.dirname(require.resolve('@loaders.gl/terrain')),
      'lib', 'decode-quantized-mesh.js');
  const decode = (await import(pathToFileURL(lib).href)).default;
  let failed = 0;
  for (const [z, x, y] of tiles(dir)) {
    const name = `${z}/${x}/${y}`;
    try {
      let b = fs.readFileSync(path.join(dir, `${name}.terrain`));
      if (b[0] === 0x1f && b[1] === 0x8b) b = zlib.gunzipSync(b);
      const ab = () => b.buffer.slice(b.byteOffset, b.byteOffset + b.length);
      const d = decode(ab(), {});
      const n = d.vertexData.length / 3, tri = d.triangleIndices;
      const mesh = await parse(ab(), QuantizedMeshLoader, { worker: false });
      const idx = mesh.indices.value, tc = mesh.attributes.TEXCOORD_0.value;
      if (idx.length !== tri.length || idx.some((v, i) => v !== tri[i]))
        throw new Error('QuantizedMeshLoader: other indices');
      for (let i = 0; i < n; i++)
        if (Math.round(tc[2 * i] * 32767) !== d.vertexData[i] ||
            Math.round(tc[2 * i + 1] * 32767) !== d.vertexData[n + i])
          throw new Error(`QuantizedMeshLoader: vertex ${i}: other u, v`);
      console.log(`${name} vertices ${n} triangles ${tri.length / 3} ` +
          `checksum ${checksum(d.vertexData, tri)}`);
    } catch (e) {
      console.error(`qmdecode.js: ${name}: ${e.message}`);
      failed = 1;
    }
  }
  process.exit(failed);
}

main().catch((e) => {
  console.error(`qmdecode.js: ${e.message}`);
  process.exit(1);
});
