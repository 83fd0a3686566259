'use strict';
// The Khronos glTF validator (gltf-validator) as the suite asks it about a GLB.
const assert = require('node:assert/strict');
const validator = require('gltf-validator');

/**
 * Asserts that the validator finds no error in GLB `bytes` and no warning but
 * those whose code is a key of `accepted` (code → why it is right to keep); the
 * failure lists the validator's messages.
 */
async function validates(bytes, { accepted = {} } = {}) {
  // The accepted codes are muted in the validator itself, so the counts (which, unlike
  // the message list, are not capped at maxIssues) cover every other warning.
  const report = await validator.validateBytes(new Uint8Array(bytes),
    { maxIssues: 100, ignoredIssues: Object.keys(accepted) });
  const messages = report.issues.messages.map((m) => `${m.code} ${m.pointer || ''}: ${m.message}`);
  assert.equal(report.issues.numErrors, 0, messages.join('\n'));
  assert.equal(report.issues.numWarnings, 0, messages.join('\n'));
}

module.exports = { validates };
