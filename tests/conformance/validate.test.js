'use strict';
// Khronos glTF-Validator on every GLB the suite left in $MER_ARTIFACTS:
// 0 errors, and no warning unless it is listed below with the reason to keep it.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const { pathToFileURL } = require('node:url');
const { validates } = require('../support/gltf.js');

// code → why it is right to keep. Empty: every warning is a failure.
const ACCEPTED_WARNINGS = {};

const dir = process.env.MER_ARTIFACTS;
const files = fs.existsSync(dir) ? fs.readdirSync(dir).filter((f) => /\.(glb|gltf)$/.test(f)).sort() : [];

test('the suite produced GLBs to validate', () => {
  assert.ok(files.length > 0, `no .glb files in ${dir}`);
});

/** The JSON and BIN chunks of a GLB. */
function chunks(bytes) {
  const view = Buffer.from(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const jsonLength = view.readUInt32LE(12);
  const json = JSON.parse(view.subarray(20, 20 + jsonLength).toString('utf8'));
  const binAt = 20 + jsonLength;
  const bin = binAt < view.length ? view.subarray(binAt + 8, binAt + 8 + view.readUInt32LE(binAt)) : null;
  return { json, bin };
}

/** A GLB from a JSON document and one BIN buffer (glTF 2.0 §4.4). */
function glb(json, bin) {
  let text = Buffer.from(JSON.stringify(json));
  text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
  const head = Buffer.alloc(20);
  head.write('glTF', 0, 'latin1');
  head.writeUInt32LE(2, 4);
  head.writeUInt32LE(12 + 8 + text.length + 8 + bin.length, 8);
  head.writeUInt32LE(text.length, 12);
  head.write('JSON', 16, 'latin1');
  const binHead = Buffer.alloc(8);
  binHead.writeUInt32LE(bin.length, 0);
  binHead.write('BIN\0', 4, 'latin1');
  return new Uint8Array(Buffer.concat([head, text, binHead, bin]));
}

/**
 * The validator reads EXT_meshopt_compression's JSON but not its data, so a
 * compressed GLB is also decoded with the decoder the brush client uses (three.js's
 * MeshoptDecoder) into the plain GLB it stands for, which is validated in full.
 */
async function decodeMeshopt(bytes) {
  const decoder = path.join(process.env.MER_WEB_ROOT, 'node_modules/three/examples/jsm/libs/meshopt_decoder.module.js');
  const { MeshoptDecoder } = await import(pathToFileURL(decoder));
  await MeshoptDecoder.ready;
  const { json, bin } = chunks(bytes);
  const fallback = json.buffers.findIndex((b) => b.extensions?.EXT_meshopt_compression?.fallback);
  assert.ok(fallback > 0, 'a fallback buffer');
  const out = new Uint8Array(json.buffers[fallback].byteLength);
  for (const v of json.bufferViews) {
    const x = v.extensions.EXT_meshopt_compression;
    assert.equal(x.buffer, 0);
    assert.equal(v.buffer, fallback);
    const target = out.subarray(v.byteOffset || 0, (v.byteOffset || 0) + x.count * x.byteStride);
    MeshoptDecoder.decodeGltfBuffer(target, x.count, x.byteStride, bin.subarray(x.byteOffset, x.byteOffset + x.byteLength),
      x.mode, x.filter || 'NONE');
    v.buffer = 0;
    delete v.extensions;
  }
  json.buffers = [{ byteLength: out.length }];
  json.extensionsUsed = json.extensionsUsed.filter((e) => e !== 'EXT_meshopt_compression');
  json.extensionsRequired = json.extensionsRequired.filter((e) => e !== 'EXT_meshopt_compression');
  return glb(json, Buffer.from(out));
}

const usesMeshopt = (file, bytes) => file.endsWith('.glb') &&
  (chunks(bytes).json.extensionsUsed || []).includes('EXT_meshopt_compression');

test('compressed snapshots are among them (decoded, then validated in full)', () => {
  const packed = files.filter((f) => usesMeshopt(f, new Uint8Array(fs.readFileSync(path.join(dir, f)))));
  assert.ok(packed.length > 0, 'no EXT_meshopt_compression GLB to decode');
});

for (const file of files) {
  test(`gltf-validator: ${file}`, async () => {
    let bytes = new Uint8Array(fs.readFileSync(path.join(dir, file)));
    if (usesMeshopt(file, bytes)) bytes = await decodeMeshopt(bytes);
    await validates(bytes, { accepted: ACCEPTED_WARNINGS });
  });
}
