'use strict';
// Renders a GLB to a PNG in headless Chromium with three.js, the way a person
// would look at it in a viewer: node render-glb.js TREE.glb OUT.png [azimuth°]
// Serves a temporary web root through meristemd (three.js from the build's webroot).
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { chromium } = require('playwright-core');
const { startDaemon } = require('./daemon.js');

const VIEWER = `<!doctype html><html><head><meta charset="utf-8"><title>glb</title>
<style>html,body{margin:0;height:100%;background:#e8ede4}</style>
<script type="importmap">{"imports":{"three":"./node_modules/three/build/three.module.js",
"three/addons/":"./node_modules/three/examples/jsm/"}}</script></head><body>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
const az = Number(new URLSearchParams(location.search).get('az') || 30) * Math.PI / 180;
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setSize(innerWidth, innerHeight);
document.body.append(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xe8ede4);
scene.add(new THREE.HemisphereLight(0xffffff, 0x667755, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 2.2); sun.position.set(3, 5, 2); scene.add(sun);
const gltf = await new GLTFLoader().setMeshoptDecoder(MeshoptDecoder).loadAsync('tree.glb');
scene.add(gltf.scene);
const box = new THREE.Box3().setFromObject(gltf.scene);
const size = box.getSize(new THREE.Vector3()), c = box.getCenter(new THREE.Vector3());
const r = Math.max(size.x, size.y, size.z);
scene.add(new THREE.GridHelper(r * 1.5, 20, 0x99aa88, 0xc8d2c0));
const camera = new THREE.PerspectiveCamera(35, innerWidth / innerHeight, r / 100, r * 20);
camera.position.set(c.x + Math.sin(az) * r * 1.9, c.y + r * 0.25, c.z + Math.cos(az) * r * 1.9);
camera.lookAt(c);
renderer.render(scene, camera);
window.done = { triangles: renderer.info.render.triangles };
</script></body></html>`;

(async () => {
  const [glb, out, az = '30'] = process.argv.slice(2);
  const root = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-view-'));
  fs.cpSync(path.join(process.env.MER_WEB_ROOT, 'node_modules'), path.join(root, 'node_modules'), { recursive: true });
  fs.writeFileSync(path.join(root, 'index.html'), VIEWER);
  fs.copyFileSync(glb, path.join(root, 'tree.glb'));
  const d = await startDaemon(['--web-root', root, '--quiet']);
  const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'] });
  try {
    const page = await browser.newPage({ viewport: { width: 900, height: 900 } });
    page.on('pageerror', (e) => console.error(String(e)));
    await page.goto(`${d.url}/?az=${az}`);
    await page.waitForFunction(() => window.done, null, { timeout: 60000 });
    console.log(JSON.stringify(await page.evaluate(() => window.done)));
    await page.screenshot({ path: out });
  } finally {
    await browser.close();
    await d.stop();
    fs.rmSync(root, { recursive: true, force: true });
  }
})().catch((e) => { console.error(e); process.exit(1); });
