// node gltf_validate.js FILE.glb... - runs the Khronos glTF validator (the npm
// package gltf-validator, found through NODE_PATH) on each file; prints its
// report's counts and messages; exit 1 when a file has errors, warnings or
// infos (such as an unused object);
// 77 when the package is not installed (the test skips).
'use strict';
let validator;
try {
    validator = require('gltf-validator');
} catch (e) {
    console.log('skip: the npm package gltf-validator is not installed (npm install gltf-validator; NODE_PATH)');
    process.exit(77);
}
const fs = require('fs');
(async () => {
    let bad = 0;
    for (const path of process.argv.slice(2)) {
        const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(path)), {maxIssues: 20});
        const i = report.issues;
        console.log(`${path}: validator ${report.validatorVersion}: ${i.numErrors} errors, ${i.numWarnings} warnings, ` +
                    `${i.numInfos} infos, ${i.numHints} hints`);
        for (const m of i.messages) console.log(`  ${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code} ${m.pointer || ''}: ${m.message}`);
        if (i.numErrors || i.numWarnings || i.numInfos) bad++;
    }
    process.exit(bad ? 1 : 0);
})().catch((e) => {
    console.log(`gltf_validate: ${e}`);
    process.exit(1);
});
