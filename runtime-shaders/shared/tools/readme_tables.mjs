#!/usr/bin/env node
// Writes the READMEs' runtime tables from the runtime descriptors (src/techniques.js), so adding a technique means
// its descriptor, not four READMEs edited by hand. Per table, a row per descriptor in the descriptors' order: the
// cells the descriptor gives (a module's file, a switch's name and whether it is off by default, the GLSL module a
// Babylon.js row draws with) from its fields, the prose from its `readme` entry.
//
//   node runtime-shaders/shared/tools/readme_tables.mjs           rewrite the tables
//   node runtime-shaders/shared/tools/readme_tables.mjs --check   exit 1 when a README's table is not what it gives
//
// Only the rows are written: the header and separator lines, and the text around a table, stay the README's.
import { readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { RUNTIMES } from '../src/techniques.js';

const SHADERS = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const code = (text) => `\`${text}\``;
const row = (cells) => `| ${cells.join(' | ')} |`;
const switchCell = (s) => code(s.name) + (s.defaultOff ? ' (off by default)' : '');

/** [{ path, header (the start of the header row), rows() }] */
const TABLES = [
	{
		path: 'README.md', header: '| Module |',
		rows: () => RUNTIMES.filter((r) => r.modules.glsl).map((r) => {
			const [technique, extension, twins] = r.readme.shaders;
			return row([`[${code(r.modules.glsl)}](${r.modules.glsl})`, technique, extension, twins]);
		}),
	},
	{
		path: 'three/README.md', header: '| extension | plugin | switch |',
		rows: () => RUNTIMES.flatMap((r) => r.readme.three.map(([extension, plugin, what], i) => {
			if (!r.switches[i]) throw new Error(`${r.name}: readme.three has a row for no switch`);
			return row([extension, plugin, switchCell(r.switches[i]), what]);
		})),
	},
	{
		path: 'babylon/README.md', header: '| Extension | Technique (switch) |',
		rows: () => RUNTIMES.flatMap((r) => r.readme.babylon.map((cells) =>
			row([...cells, r.modules.glsl ? code(r.modules.glsl) : '—']))),
	},
	{
		path: 'gltf-transform/README.md', header: '| extension | class |',
		rows: () => RUNTIMES.flatMap((r) => r.readme.gltfTransform.map(row)),
	},
];

/** The README's text with the rows of its table replaced by `rows`. */
function withRows(text, header, rows) {
	const lines = text.split('\n');
	const start = lines.findIndex((line) => line.startsWith(header));
	if (start < 0) throw new Error(`no table starting ${header}`);
	let end = start + 2;
	while (end < lines.length && lines[end].startsWith('|')) end++;
	return [...lines.slice(0, start + 2), ...rows, ...lines.slice(end)].join('\n');
}

const check = process.argv.includes('--check');
let stale = [];
for (const table of TABLES) {
	const path = join(SHADERS, table.path);
	const current = readFileSync(path, 'utf8');
	const wanted = withRows(current, table.header, table.rows());
	if (current === wanted) continue;
	if (check) stale.push(table.path);
	else writeFileSync(path, wanted);
}
if (stale.length) {
	console.error(`runtime tables out of date in ${stale.join(', ')}: run node runtime-shaders/shared/tools/readme_tables.mjs`);
	process.exit(1);
}
