'use strict';
// The offline command line as a pipeline engineer uses it: grow from a preset,
// read the summary JSON, write the GLB (validated later by the conformance test).
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const { spawnSync } = require('node:child_process');

const exe = path.join(process.env.MER_BUILDDIR, 'server', 'meristem');
const out = (name) => path.join(process.env.MER_ARTIFACTS, name);
const run = (args) => spawnSync(exe, args, { encoding: 'utf8' });

test('meristem grow prints the summary and writes a GLB', () => {
  const r = run(['grow', '--preset', 'fig7-bh-0.54', '--steps', '12', '--seed', '3', '--leaves',
    '-o', out('cli-fig7.glb')]);
  assert.equal(r.status, 0, r.stderr);
  const s = JSON.parse(r.stdout);
  assert.equal(s.step, 12);
  assert.equal(s.preset, 'fig7-bh-0.54');
  assert.equal(s.seed, 3);
  assert.ok(s.internodes > 100, `${s.internodes} internodes`);
  assert.ok(s.height > 5);
  const glb = fs.readFileSync(out('cli-fig7.glb'));
  assert.equal(glb.subarray(0, 4).toString('latin1'), 'glTF');
  assert.equal(glb.length, s.bytes);
});

test('the same preset, seed and steps give byte-identical GLBs', () => {
  for (const name of ['cli-same-a.glb', 'cli-same-b.glb'])
    assert.equal(run(['grow', '--steps', '10', '--seed', '5', '-o', out(name)]).status, 0);
  assert.ok(fs.readFileSync(out('cli-same-a.glb')).equals(fs.readFileSync(out('cli-same-b.glb'))));
  fs.rmSync(out('cli-same-b.glb'));
});

test('--junctions implicit reports its patches in the summary; tubes report none', () => {
  const r = run(['grow', '--preset', 'fig7-bh-0.54', '--steps', '12', '--seed', '1', '--junctions', 'implicit',
    '-o', out('cli-junctions.glb')]);
  assert.equal(r.status, 0, r.stderr);
  const j = JSON.parse(r.stdout).junctions;
  assert.ok(j.patches > 20, JSON.stringify(j));
  assert.equal(j.open, 0);
  assert.ok(j.smooth <= j.patches);
  // The thick forks of a trunk whose internodes are shorter than their cuts need.
  assert.ok(j.unfit > 0 && j.unfit < j.patches, JSON.stringify(j));
  const tubes = run(['grow', '--preset', 'fig7-bh-0.54', '--steps', '12', '--seed', '1', '-o', out('cli-tubes.glb')]);
  assert.equal(JSON.parse(tubes.stdout).junctions, undefined);
  fs.rmSync(out('cli-tubes.glb'));
});

test('--set overrides a parameter and --color, --markers, .gltf work', () => {
  const r = run(['grow', '--preset', 'fig4-colonization', '--steps', '10', '--set', 'theta=120',
    '--markers', '--color', 'light', '-o', out('cli-colonization.gltf')]);
  assert.equal(r.status, 0, r.stderr);
  const doc = JSON.parse(fs.readFileSync(out('cli-colonization.gltf'), 'utf8'));
  assert.equal(doc.asset.extras.preset, 'fig4-colonization');
  assert.ok(doc.nodes.some((n) => n.name === 'markers'));
  assert.ok('COLOR_0' in doc.meshes[0].primitives[0].attributes);
});

test('--quantize --compress=meshopt --no-texcoords writes the compact GLB the brush client reads', () => {
  const args = ['grow', '--preset', 'fig7-bh-0.54', '--steps', '12', '--seed', '3', '--leaves'];
  assert.equal(run([...args, '-o', out('cli-plain.tmp.glb')]).status, 0);
  const r = run([...args, '--quantize', '--compress', 'meshopt', '--no-texcoords', '-o', out('cli-meshopt.glb')]);
  assert.equal(r.status, 0, r.stderr);
  const glb = fs.readFileSync(out('cli-meshopt.glb'));
  const doc = JSON.parse(glb.subarray(20, 20 + glb.readUInt32LE(12)).toString('utf8'));
  assert.ok(doc.extensionsRequired.includes('EXT_meshopt_compression'));
  assert.ok(doc.meshes[0].primitives.every((p) => !('TEXCOORD_0' in p.attributes)));
  const plain = fs.readFileSync(out('cli-plain.tmp.glb'));
  fs.rmSync(out('cli-plain.tmp.glb'));
  assert.ok(glb.length * 2.5 < plain.length, `${glb.length} vs ${plain.length} bytes`);
  // --twig-lines: as the brush client asks for them, a LINES primitive after each twig chunk.
  assert.equal(run([...args, '--quantize', '--compress', 'meshopt', '--no-texcoords', '--twig-lines', '-o', out('cli-twig-lines.glb')]).status, 0);
  const lod = fs.readFileSync(out('cli-twig-lines.glb'));
  const lodDoc = JSON.parse(lod.subarray(20, 20 + lod.readUInt32LE(12)).toString('utf8'));
  assert.ok(lodDoc.meshes[0].primitives.some((p) => p.mode === 1 && lodDoc.materials[p.material].name === 'twig'));
  const bad = run(['grow', '--compress', 'zip']);
  assert.equal(bad.status, 2);
  assert.match(bad.stderr, /--compress wants none or meshopt/);
  const gltf = run(['grow', '--compress', 'meshopt', '-o', out('cli-meshopt.tmp.gltf')]);
  assert.equal(gltf.status, 1);
  assert.match(gltf.stderr, /binary glTF \(\.glb\) only/);
  assert.ok(!fs.existsSync(out('cli-meshopt.tmp.gltf')));
});

test('mistakes are named with the allowed range', () => {
  let r = run(['grow', '--preset', 'nope']);
  assert.equal(r.status, 1);
  assert.match(r.stderr, /unknown preset 'nope'/);
  r = run(['grow', '--set', 'lambda=2']);
  assert.equal(r.status, 1);
  assert.match(r.stderr, /lambda/);
  r = run(['grow', '--detail', '9']);
  assert.equal(r.status, 2);
  assert.match(r.stderr, /--detail wants an integer from 1 to 5/);
  r = run(['grow', '--color', 'purple']);
  assert.equal(r.status, 2);
  r = run(['grow', '--model', 'lsys']);
  assert.equal(r.status, 1);
  assert.match(r.stderr, /unknown model 'lsys'; use one of p09/);
});

test('--model p09 is the default model', () => {
  const a = run(['grow', '--steps', '4']), b = run(['grow', '--steps', '4', '--model', 'p09']);
  assert.equal(a.status, 0, a.stderr);
  assert.equal(b.status, 0, b.stderr);
  assert.equal(JSON.parse(b.stdout).hash, JSON.parse(a.stdout).hash);
});

test('meristem presets lists every preset with a description', () => {
  const r = run(['presets']);
  assert.equal(r.status, 0);
  const list = JSON.parse(r.stdout);
  assert.ok(list.length >= 10);
  for (const p of list) assert.ok(p.name && p.description);
  assert.ok(list.some((p) => p.name === 'default'));
});
