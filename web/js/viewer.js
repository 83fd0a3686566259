// The 3D view: three.js scene, camera and orbit controls, snapshot loading (GLB with
// KHR_mesh_quantization, EXT_meshopt_compression and per-vertex _NODE_ID), picking by
// node id, highlights, the marker cloud and the brush preview. Draws on demand, not in
// a loop.
//
// Speed. A snapshot of a 10,000-internode tree is ~59k triangles; on a software
// rasterizer (headless Chromium draws with SwiftShader) the cost of a frame is mostly
// per triangle and per shaded pixel, and the cost of a load mostly bytes moved. So the
// page asks for compressed snapshots without UVs (it draws no texture), shades bark
// and leaves with diffuse-only Lambert materials (the bark is rough and non-metallic:
// a PBR material adds a specular lobe nobody sees, and ~40% to a frame in SwiftShader),
// paints the ground in its lit colour without lighting it per pixel, and draws the twigs
// of a tree seen whole, thinner than a pixel, as lines (see _chooseTwigDetail).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { fetchSnapshot } from './api.js';

// GLTFLoader names a custom attribute by its glTF name in lower case.
const NODE_ID = '_node_id';
const SKY = new THREE.Color(0xdfe5da);
const GROUND = new THREE.Color(0xd1d5bc);   // the colour the lights give rough 0xc9d1bd ground
const GROUND_Y = 0;
const TWIG_LINE = 0x5a4232;       // what the lights make of bark 0x6e5240 on a thin twig
const TWIG_LINE_TINT = 0xcccccc;  // the same darkening for vertex colours
const TWIG_LINE_OPACITY = 0.4;

/**
 * Whether WebGL runs on a software rasterizer (SwiftShader, llvmpipe): multisampling
 * there costs more than it is worth, so the viewer draws without it.
 */
export function softwareRendering() {
  try {
    const gl = document.createElement('canvas').getContext('webgl2');
    if (!gl) return true;
    const ext = gl.getExtension('WEBGL_debug_renderer_info');
    const name = String(gl.getParameter(ext ? ext.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
    gl.getExtension('WEBGL_lose_context')?.loseContext();
    return /swiftshader|llvmpipe|software/i.test(name);
  } catch {
    return false;
  }
}

/**
 * Makes a snapshot's geometry cheap to upload and draw, in place, and returns it:
 * - SHORT positions and BYTE normals come padded to 4 components (glTF aligns vertex
 *   attributes to 4 bytes); handing the padding to WebGL as a 4th component gives
 *   formats the GPU reads as they are, where 3-component ones are converted on every
 *   upload (the shaders read xyz either way; ~10 ms less per 10k-internode load);
 * - the `_NODE_ID` attribute moves to `userData.nodeIds`: only picking and highlights
 *   read it, on the CPU, so it is never uploaded.
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
  return geometry;
}

/** The per-vertex node ids of a snapshot geometry (a BufferAttribute), or undefined. */
const nodeIdsOf = (geometry) => geometry.userData.nodeIds;

/**
 * The internode a triangle covers: the smallest id among its vertices (mesh.h,
 * Picking; the rule holds whatever order the decoder gave the corners in).
 */
const triangleNode = (ids, a, b, c) => Math.round(Math.min(ids.getX(a), ids.getX(b), ids.getX(c)));

// Twigs at most this many pixels wide are drawn as lines (see _chooseTwigDetail).
const TWIG_LINE_PX = 1.5;

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

export class Viewer {
  constructor(container, { antialias = true } = {}) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.outputColorSpace = THREE.SRGBColorSpace;
    container.append(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.renderer.autoClear = false;   // render() clears sky and ground itself
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.05, 2000);
    this.camera.position.set(18, 14, 30);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.set(0, 6, 0);
    this.controls.enableDamping = false;
    this.controls.addEventListener('change', () => this.requestRender());

    this.scene.add(new THREE.HemisphereLight(0xf4f8ff, 0x5a6248, 1.5));
    const sun = new THREE.DirectionalLight(0xfff4e0, 2.4);
    sun.position.set(30, 60, 25);
    this.scene.add(sun);
    const fill = new THREE.DirectionalLight(0xdde8ff, 0.6);
    fill.position.set(-25, 10, -30);
    this.scene.add(fill);

    this.ground = new THREE.Group();
    this.scene.add(this.ground);
    this.setGrid(40);

    this.treeRoot = new THREE.Group();            // the snapshot's scene
    this.scene.add(this.treeRoot);
    this.overlay = new THREE.Group();             // highlights (children of the tree node)
    this.preview = new THREE.Group();             // brush dabs and bend handles, world space
    this.scene.add(this.preview);

    this.materials = {
      bark: new THREE.MeshLambertMaterial({ color: 0x6e5240 }),
      barkColored: new THREE.MeshLambertMaterial({ color: 0xffffff, vertexColors: true }),
      leaf: new THREE.MeshLambertMaterial({ color: 0x5f9442, side: THREE.DoubleSide }),
      leafColored: new THREE.MeshLambertMaterial({ color: 0xffffff, side: THREE.DoubleSide,
        vertexColors: true }),
      // Twig lines, unlit, in the colour lit bark shows. A line covers its pixel whole
      // where a twig a fraction of a pixel wide covers a fraction of it: at full
      // opacity the crown turns brown. TWIG_LINE_OPACITY matches the prisms' look.
      twig: new THREE.LineBasicMaterial({ color: TWIG_LINE, transparent: true,
        opacity: TWIG_LINE_OPACITY, depthWrite: false }),
      twigColored: new THREE.LineBasicMaterial({ color: TWIG_LINE_TINT, vertexColors: true,
        transparent: true, opacity: TWIG_LINE_OPACITY, depthWrite: false }),
      markers: new THREE.PointsMaterial({ color: 0x5b6066, size: 3, sizeAttenuation: false,
        transparent: true, opacity: 0.75, depthWrite: false }),
    };
    this.highlightMaterials = new Map();

    this.loader = new GLTFLoader().setMeshoptDecoder(MeshoptDecoder);
    this.etag = null;
    this.url = null;
    // A snapshot's bark (and leaves) may be several primitives: the GLB splits them
    // into chunks of at most 65,535 vertices, about 14,000 internodes each.
    this.barkMeshes = [];   // THREE.Mesh per bark primitive (userData.twig: twigs' prisms)
    this.leafMeshes = [];
    this.twigLines = [];    // THREE.LineSegments: the twigs' lines, if the snapshot has them
    this.twigDiameter = 0;  // the thickest twig's diameter, world units
    this.twigLinesShown = false;
    this.bark = null;       // the first bark mesh (its material and attributes stand for all)
    this.leaves = null;
    this.markers = null;    // THREE.Points
    this.nodeInfo = null;   // lazily computed per-node centroids and axes
    this.extras = null;
    this.lastLoad = null;   // {ms, fetchMs, parseMs, renderMs, bytes, triangles, lines, prefetched, drawnAt, paintWaitMs}
    this.prefetched = null; // {url, reply, at}: a snapshot asked for before anyone loads it
    this.framed = false;
    this.raycaster = new THREE.Raycaster();
    this.frames = 0;
    this.showBark = true;
    this.showLeaves = true;

    this._renderQueued = false;
    this.ready = this._precompile();
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  /**
   * Compiles the tree's shader programs once at startup, so loading a snapshot costs
   * fetch + parse + draw, not a shader compile.
   */
  async _precompile() {
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
        dummies.add(new THREE.Mesh(make(false, index32), this.materials[k]));
        dummies.add(new THREE.Mesh(make(true, index32), this.materials[`${k}Colored`]));
      }
    }
    // One snapshot-sized geometry (all its triangles degenerate, so drawing it costs
    // little): the first real snapshot then finds the GPU side's buffers already grown.
    // Measured in headless Chromium, the first snapshot's draw after opening the page:
    // 143, 174, 147 ms without it, 116, 128, 115 ms with it (the next draws take ~50).
    dummies.add(new THREE.Mesh(make(false, false, 65535), this.materials.bark));
    for (const k of ['twig', 'twigColored']) {
      const g = make(k === 'twigColored', false);
      g.deleteAttribute('normal');
      dummies.add(new THREE.LineSegments(g, this.materials[k]));
    }
    const pts = new THREE.BufferGeometry();
    pts.setAttribute('position', new THREE.Float32BufferAttribute([0, 0, 0], 3));
    dummies.add(new THREE.Points(pts, this.materials.markers));
    // In front of the camera, tiny: drawn once so every program and routine exists.
    this.camera.updateMatrixWorld();
    dummies.position.copy(this.camera.position).add(this.camera.getWorldDirection(new THREE.Vector3()));
    dummies.scale.setScalar(1e-4);
    this.scene.add(dummies);
    try {
      await MeshoptDecoder.ready;
      await this.renderer.compileAsync(this.scene, this.camera);
      this.renderer.render(this.scene, this.camera);
    } finally {
      this.scene.remove(dummies);
      dummies.traverse((o) => o.geometry?.dispose());
      this.render();
    }
  }

  resize() {
    const w = Math.max(1, this.container.clientWidth), h = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(w, h, true);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  requestRender() {
    if (this._renderQueued) return;
    this._renderQueued = true;
    requestAnimationFrame(() => { this._renderQueued = false; this.render(); });
  }

  render() {
    this._chooseTwigDetail();
    this._clearSkyAndGround();
    this.renderer.render(this.scene, this.camera);
    this.frames++;
  }

  /**
   * Clears to the sky's colour above the horizon and the ground's below it. Flat ground
   * under this light rig is one colour, reaching to the horizon, and with no camera roll
   * (orbit controls keep "up") the horizon is a row of pixels: two clears paint it for
   * nothing, where a ground mesh cost a software rasterizer ~5 ms a frame.
   */
  _clearSkyAndGround() {
    const r = this.renderer;
    r.setClearColor(SKY);
    r.clear(true, true, true);
    if (!this.ground.visible) return;
    const h = r.domElement.clientHeight || r.domElement.height;
    const row = Math.min(h, Math.max(0, Math.round((this._horizonNdcY() + 1) / 2 * h)));
    if (row === 0) return;
    r.setClearColor(GROUND);
    r.setScissor(0, 0, r.domElement.clientWidth || r.domElement.width, row);
    r.setScissorTest(true);
    r.clear(true, false, false);
    r.setScissorTest(false);
  }

  /**
   * Where the ground plane's horizon is, in normalized device y (-1 bottom, 1 top): +∞
   * when the camera looks straight down, -∞ from below the ground (none of it faces it).
   */
  _horizonNdcY() {
    const cam = this.camera;
    cam.updateMatrixWorld();
    if (cam.position.y <= GROUND_Y) return -Infinity;
    const f = cam.getWorldDirection(new THREE.Vector3()).setY(0);
    if (f.lengthSq() < 1e-12) return Infinity;
    f.normalize();
    const p = new THREE.Vector4(f.x, 0, f.z, 0).applyMatrix4(cam.matrixWorldInverse).applyMatrix4(cam.projectionMatrix);
    return p.w > 0 ? p.y / p.w : Infinity;
  }

  /**
   * Level of detail for twigs (mesh.h, Twig lines): where the thickest twig is under
   * TWIG_LINE_PX pixels wide at the distance of the orbit target, draw the twigs'
   * lines instead of their prisms. A 1-px line is then what the prism rasterizes to
   * anyway, for a third of the work (a 10k-internode tree: 8.5k segments against 37k
   * triangles). The prisms stay pickable (pick() asks them whatever is drawn).
   */
  _chooseTwigDetail() {
    const lines = this.twigLines.length > 0 && this.showBark && this._twigPixels() < TWIG_LINE_PX;
    this.twigLinesShown = lines;
    for (const l of this.twigLines) l.visible = lines;
    for (const m of this.barkMeshes) m.visible = this.showBark && !(lines && m.userData.twig);
  }

  /** How many pixels wide the thickest twig is at the orbit target's distance. */
  _twigPixels() {
    const dist = this.camera.position.distanceTo(this.controls.target);
    const h = this.renderer.domElement.height;
    return this.twigDiameter * h / (2 * Math.tan(THREE.MathUtils.degToRad(this.camera.fov / 2)) * Math.max(dist, 1e-6));
  }

  /** A ground grid about `size` wide, centred at the origin. */
  setGrid(size) {
    const s = Math.max(10, Math.ceil(size / 10) * 10);
    if (this.gridSize === s) return;
    this.gridSize = s;
    this.ground.clear();
    // The ground itself is no mesh: see _clearSkyAndGround.
    const grid = new THREE.GridHelper(s, s / 2, 0x8d9a80, 0xb2bca6);
    grid.material.transparent = true;
    grid.material.opacity = 0.8;
    this.ground.add(grid);
  }

  setGridVisible(on) { this.ground.visible = on; this.requestRender(); }

  /**
   * Starts fetching the snapshot at `url` now (while the page starts up), and parses it
   * as soon as it is here (while the shaders compile); the next load() of the same URL
   * uses it instead of asking again.
   */
  prefetch(url) {
    const reply = fetchSnapshot(url, null).then(async (snap) => {
      if (snap.notModified) return snap;
      await MeshoptDecoder.ready;
      return { ...snap, gltf: await this.loader.parseAsync(snap.buffer, '') };
    });
    reply.catch(() => {});   // a refusal surfaces in load(), if load() asks for it
    this.prefetched = { url, reply, at: performance.now() };
  }

  /**
   * Loads the snapshot at `url` (If-None-Match with the last ETag) and draws it.
   * Resolves to {changed, ms}; the time covers fetch + parse + first render (for a
   * prefetched snapshot, the part of fetch and parse still outstanding), not the first load's
   * wait for the page's first paint (lastLoad.paintWaitMs). lastLoad.drawnAt is when
   * the frame was done, in ms since navigation.
   */
  async load(url) {
    await this.ready;
    // The page's first load waits for its first paint (the panels it has just filled
    // in): drawing a tree while the browser rasterizes and composites the page takes a
    // software rasterizer twice as long (10k internodes, headless Chromium: first
    // draws of 106-143 ms, 66-74 ms after the wait) and the tree shows no sooner.
    let paintWaitMs = 0;
    if (!this.lastLoad) {
      const w0 = performance.now();
      await afterNextPaint();
      paintWaitMs = performance.now() - w0;
    }
    const t0 = performance.now();
    const sameUrl = url === this.url;
    const pre = this.prefetched?.url === url ? this.prefetched.reply : null;
    this.prefetched = null;
    const snap = await (pre || fetchSnapshot(url, sameUrl ? this.etag : null));
    if (snap.notModified) return { changed: false, ms: performance.now() - t0 };
    const t1 = performance.now();
    const gltf = snap.gltf || await this.loader.parseAsync(snap.buffer, '');
    const t2 = performance.now();
    this._install(gltf);
    this.url = url;
    this.etag = snap.etag;
    this.render();
    // Read one pixel so the measured time includes the GPU finishing the frame.
    const gl = this.renderer.getContext();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    const t3 = performance.now();
    this.lastLoad = { ms: t3 - t0, fetchMs: t1 - t0, parseMs: t2 - t1, renderMs: t3 - t2,
      bytes: snap.buffer.byteLength, triangles: this.renderer.info.render.triangles,
      lines: this.renderer.info.render.lines,
      prefetched: Boolean(pre), drawnAt: t3, paintWaitMs };
    return { changed: true, ms: this.lastLoad.ms };
  }

  _install(gltf) {
    for (const o of this.treeRoot.children) o.traverse((m) => { m.geometry?.dispose(); });
    this.treeRoot.clear();
    this.bark = this.leaves = this.markers = null;
    this.barkMeshes = [];
    this.leafMeshes = [];
    this.twigLines = [];
    this.twigDiameter = 0;
    this.nodeInfo = null;
    this.extras = gltf.asset?.extras || gltf.parser?.json?.asset?.extras || null;
    const root = gltf.scene;
    root.traverse((o) => {
      if (o.isPoints) {
        o.material = this.materials.markers;
        this.markers = o;
      } else if (o.isLineSegments) {
        gpuReady(o.geometry);
        o.material = o.geometry.attributes.color ? this.materials.twigColored : this.materials.twig;
        this.twigDiameter = Math.max(this.twigDiameter, o.geometry.userData.twig_diameter_max || 0);
        this.twigLines.push(o);
      } else if (o.isMesh) {
        gpuReady(o.geometry);
        const colored = Boolean(o.geometry.attributes.color);
        const name = o.material?.name || '';
        if (name === 'leaf') {
          o.material = colored ? this.materials.leafColored : this.materials.leaf;
          this.leafMeshes.push(o);
        } else {
          o.material = colored ? this.materials.barkColored : this.materials.bark;
          o.userData.twig = Boolean(o.geometry.userData.twig);
          this.barkMeshes.push(o);
        }
      }
    });
    this.bark = this.barkMeshes[0] || null;
    this.leaves = this.leafMeshes[0] || null;
    this.treeRoot.add(root);
    root.updateMatrixWorld(true);
    for (const m of this.barkMeshes) m.visible = this.showBark;
    for (const m of this.leafMeshes) m.visible = this.showLeaves;
    this.overlay.removeFromParent();
    if (this.bark) this.bark.parent.add(this.overlay);
    this._applyHighlights();
  }

  setVisible({ bark, leaves }) {
    if (bark !== undefined) this.showBark = bark;
    if (leaves !== undefined) this.showLeaves = leaves;
    for (const m of this.barkMeshes) m.visible = this.showBark;
    for (const m of this.leafMeshes) m.visible = this.showLeaves;
    this.overlay.visible = this.showBark;
    this.requestRender();
  }

  /** Points the camera at the box {min, max} (summary bounds). */
  frame(bounds) {
    const min = new THREE.Vector3(...bounds.min), max = new THREE.Vector3(...bounds.max);
    const size = max.clone().sub(min);
    const r = Math.max(size.x, size.y, size.z, 8);
    const c = min.clone().add(max).multiplyScalar(0.5);
    c.y = Math.max(c.y, r * 0.35);
    const dir = this.camera.position.clone().sub(this.controls.target).normalize();
    if (!this.framed || dir.lengthSq() < 0.5) dir.set(0.45, 0.28, 0.85).normalize();
    const dist = r / (2 * Math.tan(THREE.MathUtils.degToRad(this.camera.fov / 2))) * 1.35;
    this.controls.target.copy(c);
    this.camera.position.copy(c).addScaledVector(dir, dist);
    this.camera.near = Math.max(0.01, dist / 200);
    this.camera.far = dist * 20;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.setGrid(Math.max(size.x, size.z) * 1.6 + 10);
    this.framed = true;
    this.requestRender();
  }

  /** Normalized device coordinates of a client (CSS px) position. */
  ndc(clientX, clientY) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    return new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1,
      -((clientY - rect.top) / rect.height) * 2 + 1);
  }

  /** Client coordinates of a world point. */
  screenOf(p) {
    const v = new THREE.Vector3(p[0] ?? p.x, p[1] ?? p.y, p[2] ?? p.z).project(this.camera);
    const rect = this.renderer.domElement.getBoundingClientRect();
    return { x: rect.left + (v.x + 1) / 2 * rect.width, y: rect.top + (1 - v.y) / 2 * rect.height };
  }

  /** The world-space ray through a client position. */
  ray(clientX, clientY) {
    this.raycaster.setFromCamera(this.ndc(clientX, clientY), this.camera);
    return this.raycaster.ray.clone();
  }

  /**
   * The tree under a client position: {node, point} (the hit triangle's node, from
   * _NODE_ID), else the nearest bark vertex within `slop` px, else null.
   */
  pick(clientX, clientY, slop = 8) {
    // Twigs drawn as lines are picked on their prisms, hidden or not.
    const targets = [...(this.showBark ? this.barkMeshes : []),
      ...(this.showLeaves ? this.leafMeshes : [])];
    if (!targets.length) return null;
    this.raycaster.setFromCamera(this.ndc(clientX, clientY), this.camera);
    const hits = this.raycaster.intersectObjects(targets, false);
    for (const h of hits) {
      const ids = nodeIdsOf(h.object.geometry);
      if (ids && h.face) return { node: triangleNode(ids, h.face.a, h.face.b, h.face.c), point: h.point.clone() };
    }
    if (!this.bark || !this.showBark) return null;
    // Thin twigs are hard to hit: take the nearest bark vertex on screen.
    const rect = this.renderer.domElement.getBoundingClientRect();
    const v = new THREE.Vector3();
    let best = null, bestD = slop * slop, bestZ = Infinity;
    for (const mesh of this.barkMeshes) {
      const pos = mesh.geometry.attributes.position;
      const m = new THREE.Matrix4().multiplyMatrices(this.camera.projectionMatrix,
        this.camera.matrixWorldInverse).multiply(mesh.matrixWorld);
      for (let i = 0; i < pos.count; i++) {
        v.fromBufferAttribute(pos, i).applyMatrix4(m);
        if (v.z < -1 || v.z > 1) continue;
        const dx = rect.left + (v.x + 1) / 2 * rect.width - clientX;
        const dy = rect.top + (1 - v.y) / 2 * rect.height - clientY;
        const d = dx * dx + dy * dy;
        if (d < bestD || (d === bestD && v.z < bestZ)) { best = { mesh, i }; bestD = d; bestZ = v.z; }
      }
    }
    if (!best) return null;
    const point = new THREE.Vector3().fromBufferAttribute(best.mesh.geometry.attributes.position, best.i)
      .applyMatrix4(best.mesh.matrixWorld);
    return { node: Math.round(nodeIdsOf(best.mesh.geometry).getX(best.i)), point };
  }

  /**
   * Per-node centroid and principal axis (world space) from the bark vertices, by node
   * id; computed once per snapshot, on demand.
   */
  nodes() {
    if (this.nodeInfo) return this.nodeInfo;
    const info = new Map();
    const v = new THREE.Vector3(), n = new THREE.Vector3();
    const acc = new Map();
    for (const mesh of this.barkMeshes) {
      const g = mesh.geometry, pos = g.attributes.position, nrm = g.attributes.normal;
      const ids = nodeIdsOf(g), mw = mesh.matrixWorld;
      for (let i = 0; i < pos.count; i++) {
        const id = Math.round(ids.getX(i));
        v.fromBufferAttribute(pos, i).applyMatrix4(mw);
        n.fromBufferAttribute(nrm, i).normalize();   // the node transform is translate + uniform scale
        let a = acc.get(id);
        if (!a) acc.set(id, (a = { k: 0, s: [0, 0, 0], nn: [0, 0, 0, 0, 0, 0], ymin: Infinity, ymax: -Infinity }));
        a.k++;
        a.s[0] += v.x; a.s[1] += v.y; a.s[2] += v.z;
        a.nn[0] += n.x * n.x; a.nn[1] += n.y * n.y; a.nn[2] += n.z * n.z;
        a.nn[3] += n.x * n.y; a.nn[4] += n.x * n.z; a.nn[5] += n.y * n.z;
        a.ymin = Math.min(a.ymin, v.y); a.ymax = Math.max(a.ymax, v.y);
      }
    }
    const b = new THREE.Matrix3(), d = new THREE.Vector3();
    for (const [id, a] of acc) {
      const c = a.s.map((x) => x / a.k);
      // Bark normals are perpendicular to the internode's axis: the axis is the
      // direction the normals vary least along, whatever the internode's thickness.
      const m = a.nn.map((x) => x / a.k);
      const tr = m[0] + m[1] + m[2];
      b.set(tr - m[0], -m[3], -m[4], -m[3], tr - m[1], -m[5], -m[4], -m[5], tr - m[2]);
      d.set(0.05, 1, 0.03);
      for (let k = 0; k < 40; k++) {
        d.applyMatrix3(b);
        if (d.lengthSq() < 1e-20) { d.set(0, 1, 0); break; }
        d.normalize();
      }
      if (d.y < 0) d.negate();
      info.set(id, { center: c, axis: [d.x, d.y, d.z], count: a.k, ymin: a.ymin, ymax: a.ymax });
    }
    return (this.nodeInfo = info);
  }

  /** Node ids in the current snapshot's bark, ascending. */
  nodeIds() { return [...this.nodes().keys()].sort((a, b) => a - b); }

  /**
   * Highlights: name → {ids: Set|function(id), color}. Drawn over the bark triangles
   * of those nodes.
   */
  setHighlight(name, ids, color) {
    this.highlights ??= new Map();
    if (!ids) this.highlights.delete(name); else this.highlights.set(name, { ids, color });
    this._applyHighlights();
    this.requestRender();
  }

  _applyHighlights() {
    // An overlay borrows its bark's attributes (which twig lines share too): free only
    // its own index, or three.js would drop the bark's buffers and upload them again.
    for (const o of this.overlay.children) {
      o.geometry.deleteAttribute('position');
      o.geometry.deleteAttribute('normal');
      o.geometry.dispose();
    }
    this.overlay.clear();
    if (!this.bark || !this.highlights?.size) return;
    // The chunks share their parent node (the quantization grid) and have no transform
    // of their own, so the overlay sits beside them with the first one's.
    this.overlay.position.copy(this.bark.position);
    this.overlay.quaternion.copy(this.bark.quaternion);
    this.overlay.scale.copy(this.bark.scale);
    let order = 0;
    for (const { ids: want, color } of this.highlights.values()) {
      const has = typeof want === 'function' ? want : (id) => want.has(id);
      let mat = this.highlightMaterials.get(color);
      if (!mat) {
        mat = new THREE.MeshLambertMaterial({ color, emissive: color, emissiveIntensity: 0.35,
          polygonOffset: true, polygonOffsetFactor: -1 - order, polygonOffsetUnits: -4 });
        this.highlightMaterials.set(color, mat);
      }
      for (const mesh of this.barkMeshes) {
        const g = mesh.geometry, ids = nodeIdsOf(g), index = g.index;
        const out = [];
        const n = index ? index.count : g.attributes.position.count;
        for (let t = 0; t < n; t += 3) {
          const a = index ? index.getX(t) : t, b = index ? index.getX(t + 1) : t + 1,
            c = index ? index.getX(t + 2) : t + 2;
          if (has(triangleNode(ids, a, b, c))) out.push(a, b, c);
        }
        if (!out.length) continue;
        const hg = new THREE.BufferGeometry();
        hg.setAttribute('position', g.attributes.position);
        hg.setAttribute('normal', g.attributes.normal);
        hg.setIndex(out);
        const m = new THREE.Mesh(hg, mat);
        m.renderOrder = 2 + order;
        this.overlay.add(m);
      }
      order++;
    }
  }

  /** Largest node id in the snapshot (-1 without bark). */
  maxNodeId() {
    let m = -1;
    for (const mesh of this.barkMeshes) {
      const ids = nodeIdsOf(mesh.geometry);
      for (let i = 0; i < ids.count; i++) m = Math.max(m, ids.getX(i));
    }
    return Math.round(m);
  }

  /** World positions of the marker cloud in the snapshot (needs markers=1). */
  markerPositions() {
    if (!this.markers) return [];
    const pos = this.markers.geometry.attributes.position, mw = this.markers.matrixWorld;
    const v = new THREE.Vector3(), out = [];
    for (let i = 0; i < pos.count; i++) {
      v.fromBufferAttribute(pos, i).applyMatrix4(mw);
      out.push([v.x, v.y, v.z]);
    }
    return out;
  }

  /** Luminance variance of the canvas: near zero for a blank frame. */
  pixelVariance() {
    this.render();
    const src = this.renderer.domElement;
    const c = document.createElement('canvas');
    c.width = src.width; c.height = src.height;
    const g = c.getContext('2d');
    g.drawImage(src, 0, 0);
    const px = g.getImageData(0, 0, c.width, c.height).data;
    let sum = 0, sum2 = 0, n = 0;
    for (let i = 0; i < px.length; i += 4 * 7) {
      const y = 0.299 * px[i] + 0.587 * px[i + 1] + 0.114 * px[i + 2];
      sum += y; sum2 += y * y; n++;
    }
    return sum2 / n - (sum / n) ** 2;
  }
}
