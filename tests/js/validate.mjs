// The Khronos glTF validator (npm gltf-validator) on one .gltf or .glb file: prints its JSON
// report (issues by severity: 0 error, 1 warning, 2 information, 3 hint) on stdout.
// Used by tests/test_export_gltf.py: `node validate.mjs FILE`.
import { readFile } from "node:fs/promises";
import validator from "gltf-validator";

const path = process.argv[2];
const report = await validator.validateBytes(new Uint8Array(await readFile(path)), {
  uri: path,
  maxIssues: 0,  // every issue
  externalResourceFunction: (uri) =>
    Promise.reject(new Error(`${uri}: the exported file refers to no other file`)),
});
process.stdout.write(JSON.stringify(report, null, 1) + "\n");
