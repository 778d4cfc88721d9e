// Runs the Khronos glTF-Validator (npm gltf-validator) on one .gltf with
// its external resources: node validate_gltf.js VALIDATOR_DIR FILE.gltf.
// Prints the validator's counts (report.issues) and every error and warning; exit 1 on errors.
const fs = require('fs');
const path = require('path');
const validator = require(process.argv[2]);
const file = process.argv[3];
const dir = path.dirname(file);
validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
  uri: path.basename(file),
  externalResourceFunction: (uri) => new Promise((resolve, reject) => {
    fs.readFile(path.join(dir, decodeURIComponent(uri)), (err, data) => err ? reject(err.toString()) : resolve(new Uint8Array(data)));
  }),
}).then((report) => {
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  for (const m of i.messages) if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer || ''}: ${m.message}`);
  process.exit(i.numErrors ? 1 : 0);
}, (err) => { console.log(`${file}: validator failed: ${err}`); process.exit(2); });
