// The 3D view: three.js scene, camera and orbit controls, the sky and the ground, and
// drawing on demand (not in a loop). Its other concerns have files of their own beside
// it: loading snapshots (loader.js), picking and reading them back (picking.js),
// highlights (highlight.js), the twigs' level of detail (lod.js).
//
// Speed. A snapshot of a 10,000-internode tree is ~59k triangles; on a software
// rasterizer (headless Chromium draws with SwiftShader) the cost of a frame is mostly
// per triangle and per shaded pixel, and the cost of a load mostly bytes moved. So the
// page asks for compressed snapshots without UVs (it draws no texture), shades bark
// and leaves with diffuse-only Lambert materials (the bark is rough and non-metallic:
// a PBR material adds a specular lobe nobody sees, and ~40% to a frame in SwiftShader),
// paints the ground in its lit colour without lighting it per pixel, and draws the twigs
// of a tree seen whole, thinner than a pixel, as lines (lod.js).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { createLoader, precompile, prefetch, load } from './loader.js';
import { pick, nodeTable, maxNodeId, markerPositions, ridgePoints } from './picking.js';
import { Highlighter } from './highlight.js';
import { chooseTwigDetail } from './lod.js';
import { canvasVariance } from './probe.js';

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

/** The materials of a snapshot's parts (loader.js puts each part on its own). */
function createMaterials() {
  return {
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

    this.materials = createMaterials();
    this.highlighter = new Highlighter(this);
    this.highlights = this.highlighter.highlights;   // name → {ids, color}

    this.loader = createLoader();
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
    this.ridgeInfo = null;  // lazily gathered points on junctions' ridges
    this.junctionForks = null;  // the node ids whose tip is a patched fork (a Set), or null
    this.extras = null;
    this.lastLoad = null;   // {ms, fetchMs, parseMs, renderMs, bytes, triangles, lines, prefetched, drawnAt, paintWaitMs}
    this.prefetched = null; // {url, reply, at}: a snapshot asked for before anyone loads it
    this.framed = false;
    this.raycaster = new THREE.Raycaster();
    this.frames = 0;
    this.showBark = true;
    this.showLeaves = true;

    this._renderQueued = false;
    this.ready = precompile(this);
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
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
    chooseTwigDetail(this);
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

  /** Starts fetching the snapshot at `url` for the next load() of it (loader.js). */
  prefetch(url) { prefetch(this, url); }

  /** Loads the snapshot at `url` and draws it; resolves to {changed, ms} (loader.js). */
  load(url, opts) { return load(this, url, opts); }

  setVisible({ bark, leaves }) {
    if (bark !== undefined) this.showBark = bark;
    if (leaves !== undefined) this.showLeaves = leaves;
    for (const m of this.barkMeshes) m.visible = this.showBark;
    for (const m of this.leafMeshes) m.visible = this.showLeaves;
    this.overlay.visible = this.showBark;
    this.requestRender();
  }

  /**
   * Points the camera at the box {min, max} (summary bounds). `whole`: a wide scene
   * (a forest) seen from higher up, far enough that the box's every corner is in view.
   */
  frame(bounds, { whole = false } = {}) {
    const min = new THREE.Vector3(...bounds.min), max = new THREE.Vector3(...bounds.max);
    const size = max.clone().sub(min);
    const r = whole ? Math.max(Math.hypot(size.x, size.z), size.y, 8) : Math.max(size.x, size.y, size.z, 8);
    const c = min.clone().add(max).multiplyScalar(0.5);
    if (!whole) c.y = Math.max(c.y, r * 0.35);
    const dir = this.camera.position.clone().sub(this.controls.target).normalize();
    if (!this.framed || dir.lengthSq() < 0.5) dir.set(0.45, whole ? 0.6 : 0.28, 0.85).normalize();
    const dist = r / (2 * Math.tan(THREE.MathUtils.degToRad(this.camera.fov / 2))) * 1.35;
    this.controls.target.copy(c);
    this.camera.position.copy(c).addScaledVector(dir, dist);
    this.camera.near = Math.max(0.01, dist / 200);
    this.camera.far = dist * 20;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    // OrbitControls turns the camera after reading its world matrix: bring the matrix
    // up to date now, so picking and screenOf see this view before the next frame does.
    this.camera.updateMatrixWorld();
    this.setGrid(Math.max(size.x, size.z) * 1.6 + 10);
    this.framed = true;
    this.requestRender();
  }

  /**
   * Looks at a small region (a fork's close-up): the ball of radius `r` about `center`
   * fills the view, seen from `dir` (a direction from the centre towards the camera;
   * by default the current one).
   */
  closeUp(center, r, dir = null) {
    const c = new THREE.Vector3(...center);
    const d = dir ? new THREE.Vector3(...dir).normalize()
      : this.camera.position.clone().sub(this.controls.target).normalize();
    if (d.lengthSq() < 0.5) d.set(0.45, 0.28, 0.85).normalize();
    const half = THREE.MathUtils.degToRad(this.camera.fov / 2);
    const halfWide = Math.atan(Math.tan(half) * this.camera.aspect);
    const dist = r / Math.tan(Math.min(half, halfWide));
    this.controls.target.copy(c);
    this.camera.position.copy(c).addScaledVector(d, dist);
    this.camera.near = Math.max(0.001, dist / 200);
    this.camera.far = dist * 400;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.camera.updateMatrixWorld();
    this.requestRender();
  }

  /**
   * The bark's points on implicit junctions' bounding field (`_RIDGE` > 0: the
   * patches' crotches), world space, as a flat xyz array; empty without junctions.
   * Computed once per snapshot, on demand.
   */
  ridgePoints() { return (this.ridgeInfo ??= ridgePoints(this.barkMeshes)); }

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

  /** The tree under a client position: {node, point} or null (picking.js). */
  pick(clientX, clientY, slop = 8) { return pick(this, clientX, clientY, slop); }

  /**
   * Per-node centroid and principal axis (world space) from the bark vertices, by node
   * id; computed once per snapshot, on demand.
   */
  nodes() { return (this.nodeInfo ??= nodeTable(this.barkMeshes)); }

  /** Node ids in the current snapshot's bark, ascending. */
  nodeIds() { return [...this.nodes().keys()].sort((a, b) => a - b); }

  /**
   * Highlights node ids (a Set, or a predicate on ids) in `color` under `name`, or
   * clears `name` (ids null). Drawn over the bark triangles of those nodes.
   */
  setHighlight(name, ids, color) {
    this.highlighter.set(name, ids, color);
    this.requestRender();
  }

  /** Largest node id in the snapshot (-1 without bark). */
  maxNodeId() { return maxNodeId(this.barkMeshes); }

  /** World positions of the marker cloud in the snapshot (needs markers=1). */
  markerPositions() { return markerPositions(this.markers); }

  /** Luminance variance of a freshly drawn frame: near zero for a blank one. */
  pixelVariance() {
    this.render();
    return canvasVariance(this.renderer.domElement);
  }
}
