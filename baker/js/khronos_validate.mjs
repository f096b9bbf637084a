// Run Khronos' glTF-Validator (npm package `gltf-validator`) on one asset and print its JSON report to stdout.
//
// Usage: node khronos_validate.mjs ASSET [NODE_MODULES]
//   ASSET         a .gltf or .glb file; external buffers and images are read relative to it
//   NODE_MODULES  the node_modules folder holding gltf-validator (else $BAKER_NODE_MODULES, else normal resolution)
// Exit codes: 0 a report was printed (it may contain errors), 2 the validator could not run.
import { readFile } from "node:fs/promises";
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
      // the validator hands over the URI as written in the asset (percent-encoded, relative)
      const data = await readFile(path.resolve(base, decodeURIComponent(uri)));
      return new Uint8Array(data);
    },
  });
  process.stdout.write(JSON.stringify(report) + "\n");
} catch (err) {
  console.error(`gltf-validator failed on ${fullPath}: ${err}`);
  process.exit(2);
}
