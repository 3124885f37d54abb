// validate.js - make check's validators, offline:
//   node validate.js tileset TILESET.json   3D Tiles 1.1 JSON schema (ajv)
//   node validate.js glb FILE.glb...        the Khronos glTF validator
// One line per file, "ok FILE" or "bad FILE: ..." with the messages;
// exit 0 when every file passes (0 errors), 1 otherwise.
'use strict';
const fs = require('fs');
const path = require('path');

function schemaFiles(dir) {
	let out = [];
	for (const e of fs.readdirSync(dir, { withFileTypes: true })) {
		const p = path.join(dir, e.name);
		if (e.isDirectory())
			out = out.concat(schemaFiles(p));
		else if (e.name.endsWith('.schema.json'))
			out.push(p);
	}
	return out.sort();
}

// The schema's $ids are bare file names resolved against their folder:
// register each under its path relative to the schema root.
function tileset(files) {
	const Ajv2020 = require('ajv/dist/2020');
	const addFormats = require('ajv-formats');
	const root = path.join(__dirname, '3dtiles-schema');
	const ajv = new Ajv2020({ strict: false, allErrors: true });
	addFormats(ajv);
	// ajv-formats has no IRIs; URIs in a tileset are plain relative paths here
	ajv.addFormat('iri', true);
	ajv.addFormat('iri-reference', true);
	for (const f of schemaFiles(root)) {
		const s = JSON.parse(fs.readFileSync(f, 'utf8'));
		s.$id = 'https://3dtiles.test/' + path.relative(root, f);
		ajv.addSchema(s);
	}
	const check = ajv.getSchema('https://3dtiles.test/tileset.schema.json');
	let bad = 0;
	for (const f of files) {
		if (check(JSON.parse(fs.readFileSync(f, 'utf8')))) {
			console.log('ok ' + f);
		} else {
			bad++;
			console.log('bad ' + f + ': ' + ajv.errorsText(check.errors));
		}
	}
	return bad;
}

async function glb(files) {
	const validator = require('gltf-validator');
	let bad = 0;
	for (const f of files) {
		const r = await validator.validateBytes(
		    new Uint8Array(fs.readFileSync(f)), { uri: f, maxIssues: 20 });
		const n = r.issues;
		if (n.numErrors === 0) {
			console.log('ok ' + f + ' (' + n.numWarnings + ' warnings, ' +
			    n.numInfos + ' infos)' + n.messages.filter(m =>
			    m.severity === 1).map(m => ' ' + m.code).join(''));
		} else {
			bad++;
			console.log('bad ' + f + ': ' + n.messages.filter(m =>
			    m.severity === 0).map(m => m.code + ' ' + m.pointer +
			    ' ' + m.message).join('; '));
		}
	}
	return bad;
}

async function main() {
	const [what, ...files] = process.argv.slice(2);
	let bad;
	if (what === 'tileset')
		bad = tileset(files);
	else if (what === 'glb')
		bad = await glb(files);
	else {
		console.error('usage: node validate.js tileset|glb file...');
		process.exit(2);
	}
	process.exit(bad ? 1 : 0);
}
main().catch(e => { console.error('validate.js: ' + e.message); process.exit(1); });
