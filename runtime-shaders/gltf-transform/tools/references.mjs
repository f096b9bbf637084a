#!/usr/bin/env node
// Derives src/references.js, where each extension references other glTF objects, from baker's extension schemas
// (schemas/<EXT>/schema/<object>.<EXT>.schema.json), so the glTF-Transform classes do not keep their own list.
//
//   node tools/references.mjs           rewrite src/references.js
//   node tools/references.mjs --check   exit 1 when src/references.js is not what the schemas give
//   node tools/references.mjs --json    print the table as JSON
//
// The schemas mark references by convention (the one baker/validate.py's extension_references reads):
// - `accessor`: an integer property whose description starts with "Accessor";
// - `texture`: an object with an integer `index` (a glTF textureInfo, `{index, texCoord}`); when that object has no
//   `texCoord` but the extension has a top-level integer `texCoord` (BAKER_tonal_art_map), option
//   `texCoordFrom: 'texCoord'` says the UV set is the extension's;
// - `texture-index`: an integer whose description starts with "Index of the texture" (a bare texture index);
// - `primitive`: an integer whose description says "index, in the same mesh," or "index, in this mesh," (a
//   primitive of the mesh the extension's primitive belongs to);
// - `mesh-primitive`: an object whose properties are the integers `mesh` and `primitive`;
// - `material`: an integer whose description starts with "Index of the material".
// Extensions baker writes but does not define (no schema in schemas/) are listed in OTHER, from their spec.
import { readdirSync, readFileSync, writeFileSync, existsSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const HERE = dirname(fileURLToPath(import.meta.url));
const SCHEMAS = join(HERE, '..', '..', '..', 'schemas');
const OUTPUT = join(HERE, '..', 'src', 'references.js');

/** Extensions without a schema in schemas/: their reference fields, from their specification. */
const OTHER = {
	// Bentley's EXT_mesh_primitive_edge_visibility (KhronosGroup/glTF extensions/2.0/Vendor/): baker writes it
	// next to BAKER_edges; `lineStrings` is the spec's, baker writes none
	EXT_mesh_primitive_edge_visibility: {
		'mesh.primitive': [
			['visibility', 'accessor'],
			['silhouetteMates', 'accessor'],
			['lineStrings/*/indices', 'accessor'],
			['lineStrings/*/material', 'material'],
		],
	},
};

function resolve(schema, root) {
	let out = schema || {};
	for (let guard = 0; guard < 16; guard++) {
		if (out.$ref) {
			if (!out.$ref.startsWith('#/')) throw new Error(`unsupported $ref ${out.$ref}`);
			const target = out.$ref.slice(2).split('/').reduce((value, key) => value?.[key], root);
			if (!target) throw new Error(`unresolved $ref ${out.$ref}`);
			const { $ref, ...rest } = out;
			out = { ...target, ...rest };
		} else if (Array.isArray(out.allOf)) {
			const { allOf, ...rest } = out;
			out = allOf.reduce((acc, part) => {
				const r = resolve(part, root);
				return { ...acc, ...r, properties: { ...acc.properties, ...r.properties } };
			}, rest);
		} else return out;
	}
	throw new Error('$ref loop');
}

const isInteger = (s) => s.type === 'integer';
const description = (s) => String(s.description || '');

/** [pattern, kind, options?] for every reference inside `schema` at `path`. */
function references(schema, root, path = []) {
	const s = resolve(schema, root);
	const props = s.properties || {};
	const here = path.join('/');
	if (props.index && isInteger(resolve(props.index, root))) {
		const topTexCoord = root.properties?.texCoord && isInteger(resolve(root.properties.texCoord, root));
		return [!props.texCoord && topTexCoord ? [here, 'texture', { texCoordFrom: 'texCoord' }] : [here, 'texture']];
	}
	const keys = Object.keys(props);
	if (keys.length === 2 && keys.includes('mesh') && keys.includes('primitive') &&
		keys.every((k) => isInteger(resolve(props[k], root)))) {
		return [[here, 'mesh-primitive']];
	}
	if (isInteger(s) && path.length) {
		const d = description(s);
		if (/^Accessor\b/.test(d)) return [[here, 'accessor']];
		if (/^Index of the texture\b/.test(d)) return [[here, 'texture-index']];
		if (/^Index of the material\b/.test(d)) return [[here, 'material']];
		if (/\bindex, in (the same|this) mesh,/i.test(d)) return [[here, 'primitive']];
		return [];
	}
	const out = [];
	for (const [key, sub] of Object.entries(props)) {
		if (key === 'extensions' || key === 'extras') continue;
		out.push(...references(sub, root, [...path, key]));
	}
	if (s.items && typeof s.items === 'object') out.push(...references(s.items, root, [...path, '*']));
	return out;
}

/** { extension: { glTF object kind ('material', 'mesh.primitive', 'node', 'glTF'): [[pattern, kind, options?]] } } */
export function deriveReferences(schemas = SCHEMAS) {
	const table = {};
	for (const ext of readdirSync(schemas).sort()) {
		const folder = join(schemas, ext, 'schema');
		if (!existsSync(folder)) continue;
		for (const file of readdirSync(folder).sort()) {
			const suffix = `.${ext}.schema.json`;
			if (!file.endsWith(suffix)) continue;
			const place = file.slice(0, -suffix.length);
			const root = JSON.parse(readFileSync(join(folder, file), 'utf8'));
			(table[ext] ??= {})[place] = references(root, root);
		}
	}
	for (const [ext, places] of Object.entries(OTHER)) {
		if (table[ext]) throw new Error(`${ext} has a schema now: drop it from OTHER`);
		table[ext] = places;
	}
	return table;
}

export function render(table) {
	const lines = [
		'// Generated by tools/references.mjs from schemas/*/schema/*.schema.json: do not edit, run',
		'// `node tools/references.mjs` (tests/test_gltf_transform.py checks it is up to date).',
		'//',
		'// Where each extension references other glTF objects: extension -> the glTF object it sits on -> [JSON path',
		"// in the extension ('*' = any array index), kind, options]. Kinds: accessor; texture (a textureInfo object;",
		'// texCoordFrom: the UV set is that property of the extension); texture-index (a bare texture index); primitive',
		'// (in the same mesh); mesh-primitive (a {mesh, primitive} pair); material.',
		'export const REFERENCES = {',
	];
	for (const [ext, places] of Object.entries(table)) {
		lines.push(`\t${JSON.stringify(ext)}: {`);
		for (const [place, refs] of Object.entries(places)) {
			if (!refs.length) {
				lines.push(`\t\t${JSON.stringify(place)}: [],`);
				continue;
			}
			lines.push(`\t\t${JSON.stringify(place)}: [`);
			for (const ref of refs) lines.push(`\t\t\t${JSON.stringify(ref).replace(/,/g, ', ').replace(/:/g, ': ')},`);
			lines.push('\t\t],');
		}
		lines.push('\t},');
	}
	lines.push('};');
	return lines.join('\n') + '\n';
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
	const table = deriveReferences();
	const mode = process.argv[2];
	if (mode === '--json') {
		process.stdout.write(JSON.stringify(table, null, 1) + '\n');
	} else if (mode === '--check') {
		const current = existsSync(OUTPUT) ? readFileSync(OUTPUT, 'utf8') : '';
		if (current !== render(table)) {
			process.stderr.write('src/references.js is out of date with schemas/: run `node tools/references.mjs`\n');
			process.exit(1);
		}
	} else if (mode === undefined) {
		writeFileSync(OUTPUT, render(table));
	} else {
		process.stderr.write('usage: node tools/references.mjs [--check | --json]\n');
		process.exit(2);
	}
}
