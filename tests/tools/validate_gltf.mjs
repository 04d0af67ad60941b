// Validates glTF/glb files with the Khronos glTF-Validator (npm `gltf-validator`, installed by scripts/setup.sh
// under build/npm). Prints the validator's issue counts and every error; exits 1 when a file has an error.
// Usage: node tests/tools/validate_gltf.mjs VALIDATOR_DIR FILE...
import { createRequire } from "node:module";
import { readFileSync } from "node:fs";
import path from "node:path";

const [validatorDir, ...files] = process.argv.slice(2);
const require = createRequire(path.resolve(validatorDir, "package.json"));
const validator = require("gltf-validator");
let failed = false;
for (const file of files) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    maxIssues: 100,
    externalResourceFunction: () => Promise.reject(new Error("no external resources")),
  });
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  for (const m of i.messages) if (m.severity <= 1) console.log(`  ${m.severity === 0 ? "error" : "warning"} ${m.code} ${m.pointer ?? ""}: ${m.message}`);
  failed ||= i.numErrors > 0;
}
process.exit(failed ? 1 : 0);
