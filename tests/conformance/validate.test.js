'use strict';
// Khronos glTF-Validator on every GLB the suite left in $MER_ARTIFACTS:
// 0 errors, and no warning unless it is listed below with the reason to keep it.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const validator = require('gltf-validator');

// code → why it is right to keep. Empty: every warning is a failure.
const ACCEPTED_WARNINGS = {};

const dir = process.env.MER_ARTIFACTS;
const files = fs.existsSync(dir) ? fs.readdirSync(dir).filter((f) => /\.(glb|gltf)$/.test(f)).sort() : [];

test('the suite produced GLBs to validate', () => {
  assert.ok(files.length > 0, `no .glb files in ${dir}`);
});

for (const file of files) {
  test(`gltf-validator: ${file}`, async () => {
    const bytes = new Uint8Array(fs.readFileSync(path.join(dir, file)));
    const report = await validator.validateBytes(bytes, { maxIssues: 100 });
    const messages = report.issues.messages.map((m) => `${m.code} ${m.pointer || ''}: ${m.message}`);
    assert.equal(report.issues.numErrors, 0, messages.join('\n'));
    const unexpected = report.issues.messages
      .filter((m) => m.severity === 1 && !(m.code in ACCEPTED_WARNINGS));
    assert.deepEqual(unexpected.map((m) => m.code), [], messages.join('\n'));
  });
}
