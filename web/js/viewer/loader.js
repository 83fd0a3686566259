// Snapshot loading: fetch a GLB (KHR_mesh_quantization, EXT_meshopt_compression and a
// per-vertex _NODE_ID), parse it, sort its parts (bark, leaves, twig lines, markers) onto
// the viewer's materials and draw it; a prefetch at startup and a shader warm-up make the
// first load cost fetch + parse + draw and no more.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { fetchSnapshot } from '../api.js';
import { NODE_ID, RIDGE } from './picking.js';

/** A glTF loader that decodes EXT_meshopt_compression. */
export const createLoader = () => new GLTFLoader().setMeshoptDecoder(MeshoptDecoder);

/**
 * Makes a snapshot's geometry cheap to upload and draw, in place, and returns it:
 * - SHORT positions and BYTE normals come padded to 4 components (glTF aligns vertex
 *   attributes to 4 bytes); handing the padding to WebGL as a 4th component gives
 *   formats the GPU reads as they are, where 3-component ones are converted on every
 *   upload (the shaders read xyz either way; ~10 ms less per 10k-internode load);
 * - the `_NODE_ID` attribute moves to `userData.nodeIds`: only picking and highlights
 *   read it, on the CPU, so it is never uploaded; `_RIDGE` (implicit junctions) moves
 *   to `userData.ridge` likewise (install() turns it into colour).
 * An attribute two primitives share (a twig chunk and its lines) stays one attribute,
 * uploaded once.
 */
const padded = new WeakMap();
export function gpuReady(geometry) {
  for (const name of ['position', 'normal']) {
    const a = geometry.attributes[name];
    if (padded.has(a)) {
      geometry.setAttribute(name, padded.get(a));
    } else if (a?.isInterleavedBufferAttribute && a.itemSize === 3 && a.offset === 0 && a.data.stride === 4 &&
        a.data.array.BYTES_PER_ELEMENT <= 2 && a.data.count === a.count) {
      const b = new THREE.BufferAttribute(a.data.array, 4, a.normalized);
      padded.set(a, b);
      geometry.setAttribute(name, b);
    }
  }
  const ids = geometry.attributes[NODE_ID];
  if (ids) {
    geometry.userData.nodeIds = ids;
    geometry.deleteAttribute(NODE_ID);
  }
  const ridge = geometry.attributes[RIDGE];
  if (ridge) {
    geometry.userData.ridge = ridge;
    geometry.deleteAttribute(RIDGE);
  }
  return geometry;
}

/**
 * Resolves once the browser has painted the next frame (or after 100 ms, as in a
 * hidden tab, where frames stop).
 */
function afterNextPaint() {
  return new Promise((resolve) => {
    requestAnimationFrame(() => setTimeout(resolve, 0));
    setTimeout(resolve, 100);
  });
}

/**
 * Compiles the tree's shader programs once at startup, so loading a snapshot costs
 * fetch + parse + draw, not a shader compile.
 */
export async function precompile(viewer) {
  const { scene, camera, renderer, materials } = viewer;
  // Geometries shaped like a snapshot's (SHORT positions padded to 8 bytes, BYTE
  // normals padded to 4, UBYTE RGBA colours, 16- or 32-bit indices) and made ready
  // the same way: a software rasterizer specializes its code on vertex formats, and
  // three.js picks a program by colour width.
  const make = (colored, index32, n = 3) => {
    const g = new THREE.BufferGeometry();
    const pos = new Int16Array(4 * n), nrm = new Int8Array(4 * n).fill(127);
    g.setAttribute('position', new THREE.InterleavedBufferAttribute(new THREE.InterleavedBuffer(pos, 4), 3, 0));
    g.setAttribute('normal', new THREE.InterleavedBufferAttribute(new THREE.InterleavedBuffer(nrm, 4), 3, 0, true));
    g.setAttribute(NODE_ID, new THREE.Float32BufferAttribute(new Float32Array(n), 1));
    if (colored) g.setAttribute('color', new THREE.Uint8BufferAttribute(new Uint8Array(4 * n).fill(255), 4, true));
    const index = Array.from({ length: 3 * n }, (_, i) => i % n);
    g.setIndex(index32 ? new THREE.Uint32BufferAttribute(index, 1) : new THREE.Uint16BufferAttribute(index, 1));
    return gpuReady(g);
  };
  const dummies = new THREE.Group();
  for (const index32 of [false, true]) {
    for (const k of ['bark', 'leaf']) {
      dummies.add(new THREE.Mesh(make(false, index32), materials[k]));
      dummies.add(new THREE.Mesh(make(true, index32), materials[`${k}Colored`]));
    }
  }
  // One snapshot-sized geometry (all its triangles degenerate, so drawing it costs
  // little): the first real snapshot then finds the GPU side's buffers already grown.
  // Measured in headless Chromium, the first snapshot's draw after opening the page:
  // 143, 174, 147 ms without it, 116, 128, 115 ms with it (the next draws take ~50).
  dummies.add(new THREE.Mesh(make(false, false, 65535), materials.bark));
  for (const k of ['twig', 'twigColored']) {
    const g = make(k === 'twigColored', false);
    g.deleteAttribute('normal');
    dummies.add(new THREE.LineSegments(g, materials[k]));
  }
  const pts = new THREE.BufferGeometry();
  pts.setAttribute('position', new THREE.Float32BufferAttribute([0, 0, 0], 3));
  dummies.add(new THREE.Points(pts, materials.markers));
  // In front of the camera, tiny: drawn once so every program and routine exists.
  camera.updateMatrixWorld();
  dummies.position.copy(camera.position).add(camera.getWorldDirection(new THREE.Vector3()));
  dummies.scale.setScalar(1e-4);
  scene.add(dummies);
  try {
    await MeshoptDecoder.ready;
    await renderer.compileAsync(scene, camera);
    renderer.render(scene, camera);
  } finally {
    scene.remove(dummies);
    dummies.traverse((o) => o.geometry?.dispose());
    viewer.render();
  }
}

/**
 * Starts fetching the snapshot at `url` now (while the page starts up), and parses it
 * as soon as it is here (while the shaders compile); the next load() of the same URL
 * uses it instead of asking again.
 */
export function prefetch(viewer, url) {
  const reply = fetchSnapshot(url, null).then(async (snap) => {
    if (snap.notModified) return snap;
    await MeshoptDecoder.ready;
    return { ...snap, gltf: await viewer.loader.parseAsync(snap.buffer, '') };
  });
  reply.catch(() => {});   // a refusal surfaces in load(), if load() asks for it
  viewer.prefetched = { url, reply, at: performance.now() };
}

/**
 * Loads the snapshot at `url` (If-None-Match with the last ETag) and draws it.
 * Resolves to {changed, ms}; the time covers fetch + parse + first render (for a
 * prefetched snapshot, the part of fetch and parse still outstanding), not the first load's
 * wait for the page's first paint (lastLoad.paintWaitMs). lastLoad.drawnAt is when
 * the frame was done, in ms since navigation. `signal` (an AbortSignal) cancels it: it
 * then rejects with an AbortError and the tree drawn before stays.
 */
export async function load(viewer, url, { signal } = {}) {
  await viewer.ready;
  // The page's first load waits for its first paint (the panels it has just filled
  // in): drawing a tree while the browser rasterizes and composites the page takes a
  // software rasterizer twice as long (10k internodes, headless Chromium: first
  // draws of 106-143 ms, 66-74 ms after the wait) and the tree shows no sooner.
  let paintWaitMs = 0;
  if (!viewer.lastLoad) {
    const w0 = performance.now();
    await afterNextPaint();
    paintWaitMs = performance.now() - w0;
  }
  const t0 = performance.now();
  const sameUrl = url === viewer.url;
  const pre = viewer.prefetched?.url === url ? viewer.prefetched.reply : null;
  viewer.prefetched = null;
  const snap = await (pre || fetchSnapshot(url, sameUrl ? viewer.etag : null, signal));
  if (snap.notModified) return { changed: false, ms: performance.now() - t0 };
  const t1 = performance.now();
  const gltf = snap.gltf || await viewer.loader.parseAsync(snap.buffer, '');
  const t2 = performance.now();
  // Cancelled while parsing: the tree drawn stays (a newer load draws its own).
  if (signal?.aborted) throw signal.reason ?? new DOMException('aborted', 'AbortError');
  install(viewer, gltf);
  viewer.url = url;
  viewer.etag = snap.etag;
  viewer.render();
  // Read one pixel so the measured time includes the GPU finishing the frame.
  const gl = viewer.renderer.getContext();
  gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
  const t3 = performance.now();
  const info = viewer.renderer.info.render;
  viewer.lastLoad = { ms: t3 - t0, fetchMs: t1 - t0, parseMs: t2 - t1, renderMs: t3 - t2,
    bytes: snap.buffer.byteLength, triangles: info.triangles, lines: info.lines,
    prefetched: Boolean(pre), drawnAt: t3, paintWaitMs };
  return { changed: true, ms: viewer.lastLoad.ms };
}

/** A colour on the branch bark ridge (b = 1) keeps this much of itself, as meristemd's
 * COLOR_0 does (lib/mesh/joints.c). */
const RIDGE_DARKEN = 0.55;

/**
 * The bark ridge of implicit junctions, darker (G04 §3.2, Fig. 6): a bark geometry
 * without colours whose `_RIDGE` is above 0 somewhere gets per-vertex colours, the
 * bark's `color` darkened by b. Colours meristemd sent are darkened already.
 */
function ridgeColors(geometry, color) {
  const b = geometry.userData.ridge;
  if (!b || geometry.attributes.color) return;
  let any = false;
  for (let i = 0; i < b.count && !any; i++) any = b.getX(i) > 0;
  if (!any) return;
  const rgba = new Uint8Array(4 * b.count);
  const base = [color.r, color.g, color.b].map((x) => 255 * x);
  for (let i = 0; i < b.count; i++) {
    const k = 1 - (1 - RIDGE_DARKEN) * Math.min(1, Math.max(0, b.getX(i)));
    rgba[4 * i] = base[0] * k; rgba[4 * i + 1] = base[1] * k; rgba[4 * i + 2] = base[2] * k;
    rgba[4 * i + 3] = 255;
  }
  geometry.setAttribute('color', new THREE.Uint8BufferAttribute(rgba, 4, true));
}

/** Replaces the viewer's tree with a parsed snapshot, each part on the viewer's material. */
function install(viewer, gltf) {
  const { materials } = viewer;
  for (const o of viewer.treeRoot.children) o.traverse((m) => { m.geometry?.dispose(); });
  viewer.treeRoot.clear();
  viewer.bark = viewer.leaves = viewer.markers = null;
  viewer.barkMeshes = [];
  viewer.leafMeshes = [];
  viewer.twigLines = [];
  viewer.twigDiameter = 0;
  viewer.nodeInfo = null;
  viewer.ridgeInfo = null;
  viewer.junctionForks = null;
  viewer.extras = gltf.asset?.extras || gltf.parser?.json?.asset?.extras || null;
  const root = gltf.scene;
  root.traverse((o) => {
    // The tree node's extras: the forks implicit junctions patched (mesh.h).
    if (Array.isArray(o.userData?.junction_forks)) viewer.junctionForks = new Set(o.userData.junction_forks);
    if (o.isPoints) {
      o.material = materials.markers;
      viewer.markers = o;
    } else if (o.isLineSegments) {
      gpuReady(o.geometry);
      o.material = o.geometry.attributes.color ? materials.twigColored : materials.twig;
      viewer.twigDiameter = Math.max(viewer.twigDiameter, o.geometry.userData.twig_diameter_max || 0);
      viewer.twigLines.push(o);
    } else if (o.isMesh) {
      gpuReady(o.geometry);
      const name = o.material?.name || '';
      if (name !== 'leaf') ridgeColors(o.geometry, materials.bark.color);
      const colored = Boolean(o.geometry.attributes.color);
      if (name === 'leaf') {
        o.material = colored ? materials.leafColored : materials.leaf;
        viewer.leafMeshes.push(o);
      } else {
        o.material = colored ? materials.barkColored : materials.bark;
        o.userData.twig = Boolean(o.geometry.userData.twig);
        viewer.barkMeshes.push(o);
      }
    }
  });
  viewer.bark = viewer.barkMeshes[0] || null;
  viewer.leaves = viewer.leafMeshes[0] || null;
  viewer.treeRoot.add(root);
  root.updateMatrixWorld(true);
  for (const m of viewer.barkMeshes) m.visible = viewer.showBark;
  for (const m of viewer.leafMeshes) m.visible = viewer.showLeaves;
  viewer.overlay.removeFromParent();
  if (viewer.bark) viewer.bark.parent.add(viewer.overlay);
  viewer.highlighter.apply();
}
