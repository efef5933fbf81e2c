// Validate a .glb with the Khronos glTF validator (npm gltf-validator, a library: see
// docs/pitfalls); prints the issue counts and the first message of each kind.
//   node gltf_validate.js TOOLS_DIR FILE.glb
const fs = require('fs');
const validator = require(process.argv[2] + '/node_modules/gltf-validator');
const data = new Uint8Array(fs.readFileSync(process.argv[3]));
validator.validateBytes(data, {maxIssues: 0, writeTimestamp: false}).then((report) => {
  const i = report.issues;
  console.log(`validator ${report.validatorVersion}: errors ${i.numErrors}, warnings ${i.numWarnings}, ` +
              `infos ${i.numInfos}, hints ${i.numHints}`);
  const seen = new Set();
  for (const m of i.messages) {
    if (seen.has(m.code)) continue;
    seen.add(m.code);
    console.log(`  severity ${m.severity} ${m.code}: ${m.message} (${m.pointer || ''})`);
  }
  process.exit(i.numErrors === 0 && i.numWarnings === 0 ? 0 : 1);
}, (error) => {
  console.error('validator failed:', error);
  process.exit(2);
});
