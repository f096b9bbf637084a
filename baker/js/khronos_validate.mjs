// Run Khronos' glTF-Validator (npm package `gltf-validator`) on one asset and print its JSON report to stdout.
//
// Usage: node khronos_validate.mjs ASSET [NODE_MODULES]
//   ASSET         a .gltf or .glb file; external buffers and images are read relative to it
//   NODE_MODULES  the node_modules folder holding gltf-validator (else $BAKER_NODE_MODULES, else normal resolution)
// Exit codes: 0 a report was printed (it may contain errors), 2 the validator could not run.
import { readFile, realpath } from "node:fs/promises";
import { createRequire } from "node:module";
import path from "node:path";

const [asset, nodeModules = process.env.BAKER_NODE_MODULES] = process.argv.slice(2);
if (!asset) {
  console.error("usage: node khronos_validate.mjs ASSET [NODE_MODULES]");
  process.exit(2);
}

// createRequire anchors module resolution in the given node_modules, wherever this script lives
const require = createRequire(nodeModules ? path.join(path.resolve(nodeModules), "_") : import.meta.url);
let validator;
try {
  validator = require("gltf-validator");
} catch (err) {
  console.error(`gltf-validator not found (${nodeModules || "default resolution"}): ${err.message}`);
  process.exit(2);
}

const fullPath = path.resolve(asset);
const base = path.dirname(fullPath);

try {
  const bytes = await readFile(fullPath);
  const report = await validator.validateBytes(new Uint8Array(bytes), {
    uri: path.basename(fullPath),
    maxIssues: 0, // unlimited: baker decides what to show
    writeTimestamp: false, // byte-stable reports
    externalResourceFunction: async (uri) => {
      // the validator hands over the URI as written in the asset (percent-encoded, relative); baker's URI policy:
      // only inside the asset's folder (or a $BAKER_ALLOW_OUTSIDE root), never a scheme, never an absolute path
      if (/^[A-Za-z][A-Za-z0-9+.-]*:/.test(uri)) throw new Error(`URI '${uri}' refused (a scheme)`);
      const target = path.resolve(base, decodeURIComponent(uri).replaceAll("\\", "/"));
      const roots = [base, ...(process.env.BAKER_ALLOW_OUTSIDE || "").split(path.delimiter).filter(Boolean)];
      const inside = (p, root) => p === root || p.startsWith(root.endsWith(path.sep) ? root : root + path.sep);
      let allowed = false;
      for (const root of roots.map((r) => path.resolve(r))) {
        if (inside(target, root) && inside(await realpath(target).catch(() => target), await realpath(root))) {
          allowed = true;
        }
      }
      if (!allowed || path.isAbsolute(decodeURIComponent(uri))) {
        throw new Error(`URI '${uri}' leaves the asset's folder (refused)`);
      }
      const data = await readFile(target);
      return new Uint8Array(data);
    },
  });
  process.stdout.write(JSON.stringify(report) + "\n");
} catch (err) {
  console.error(`gltf-validator failed on ${fullPath}: ${err}`);
  process.exit(2);
}
