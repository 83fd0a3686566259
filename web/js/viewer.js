// The 3D view: three.js scene, camera and orbit controls, snapshot loading (GLB with
// KHR_mesh_quantization and per-vertex _NODE_ID), picking by node id, highlights,
// the marker cloud and the brush preview. Draws on demand, not in a loop.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { fetchSnapshot } from './api.js';

// GLTFLoader names a custom attribute by its glTF name in lower case.
const NODE_ID = '_node_id';
const BACKGROUND = 0xdfe5da;

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

export class Viewer {
  constructor(container, { antialias = true } = {}) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.outputColorSpace = THREE.SRGBColorSpace;
    container.append(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(BACKGROUND);
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
      bark: new THREE.MeshStandardMaterial({ color: 0x6e5240, roughness: 0.92, metalness: 0 }),
      barkColored: new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.9, metalness: 0,
        vertexColors: true }),
      leaf: new THREE.MeshStandardMaterial({ color: 0x5f9442, roughness: 0.7, metalness: 0,
        side: THREE.DoubleSide }),
      leafColored: new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.7, metalness: 0,
        side: THREE.DoubleSide, vertexColors: true }),
      markers: new THREE.PointsMaterial({ color: 0x5b6066, size: 3, sizeAttenuation: false,
        transparent: true, opacity: 0.75, depthWrite: false }),
    };
    this.highlightMaterials = new Map();

    this.loader = new GLTFLoader();
    this.etag = null;
    this.url = null;
    this.bark = null;       // THREE.Mesh of the bark primitive
    this.leaves = null;
    this.markers = null;    // THREE.Points
    this.nodeInfo = null;   // lazily computed per-node centroids and axes
    this.extras = null;
    this.lastLoad = null;   // {ms, fetchMs, parseMs, renderMs, bytes, triangles}
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
    // The same vertex formats as a snapshot (SHORT positions, normalized BYTE normals,
    // FLOAT uv, FLOAT RGBA colours, FLOAT _NODE_ID): a software rasterizer specializes
    // its code on them, and three.js picks a program by colour width.
    const make = (colored, index32) => {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Int16BufferAttribute([0, 0, 0, 1, 0, 0, 0, 1, 0], 3));
      g.setAttribute('normal', new THREE.Int8BufferAttribute([0, 0, 127, 0, 0, 127, 0, 0, 127], 3, true));
      g.setAttribute('uv', new THREE.Float32BufferAttribute([0, 0, 1, 0, 0, 1], 2));
      g.setAttribute(NODE_ID, new THREE.Float32BufferAttribute([0, 0, 0], 1));
      if (colored) g.setAttribute('color', new THREE.Float32BufferAttribute(new Array(12).fill(1), 4));
      g.setIndex(index32 ? new THREE.Uint32BufferAttribute([0, 1, 2], 1) : new THREE.Uint16BufferAttribute([0, 1, 2], 1));
      return g;
    };
    const dummies = new THREE.Group();
    for (const index32 of [false, true]) {
      for (const k of ['bark', 'leaf']) {
        dummies.add(new THREE.Mesh(make(false, index32), this.materials[k]));
        dummies.add(new THREE.Mesh(make(true, index32), this.materials[`${k}Colored`]));
      }
    }
    const pts = new THREE.BufferGeometry();
    pts.setAttribute('position', new THREE.Int16BufferAttribute([0, 0, 0], 3));
    dummies.add(new THREE.Points(pts, this.materials.markers));
    // In front of the camera, tiny: drawn once so every program and routine exists.
    this.camera.updateMatrixWorld();
    dummies.position.copy(this.camera.position).add(this.camera.getWorldDirection(new THREE.Vector3()));
    dummies.scale.setScalar(1e-4);
    this.scene.add(dummies);
    try {
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
    this.renderer.render(this.scene, this.camera);
    this.frames++;
  }

  /** A ground grid about `size` wide, centred at the origin. */
  setGrid(size) {
    const s = Math.max(10, Math.ceil(size / 10) * 10);
    if (this.gridSize === s) return;
    this.gridSize = s;
    this.ground.clear();
    const disc = new THREE.Mesh(new THREE.CircleGeometry(s * 0.75, 64),
      new THREE.MeshStandardMaterial({ color: 0xc9d1bd, roughness: 1 }));
    disc.rotation.x = -Math.PI / 2;
    disc.position.y = -0.02;
    this.ground.add(disc);
    const grid = new THREE.GridHelper(s, s / 2, 0x8d9a80, 0xb2bca6);
    grid.material.transparent = true;
    grid.material.opacity = 0.8;
    this.ground.add(grid);
  }

  setGridVisible(on) { this.ground.visible = on; this.requestRender(); }

  /**
   * Loads the snapshot at `url` (If-None-Match with the last ETag) and draws it.
   * Resolves to {changed, ms}; the time covers fetch + parse + first render.
   */
  async load(url) {
    await this.ready;
    const t0 = performance.now();
    const sameUrl = url === this.url;
    const snap = await fetchSnapshot(url, sameUrl ? this.etag : null);
    if (snap.notModified) return { changed: false, ms: performance.now() - t0 };
    const t1 = performance.now();
    const gltf = await this.loader.parseAsync(snap.buffer, '');
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
      bytes: snap.buffer.byteLength, triangles: this.renderer.info.render.triangles };
    return { changed: true, ms: this.lastLoad.ms };
  }

  _install(gltf) {
    for (const o of this.treeRoot.children) o.traverse((m) => { m.geometry?.dispose(); });
    this.treeRoot.clear();
    this.bark = this.leaves = this.markers = null;
    this.nodeInfo = null;
    this.extras = gltf.asset?.extras || gltf.parser?.json?.asset?.extras || null;
    const root = gltf.scene;
    root.traverse((o) => {
      if (o.isPoints) {
        o.material = this.materials.markers;
        this.markers = o;
      } else if (o.isMesh) {
        const colored = Boolean(o.geometry.attributes.color);
        const name = o.material?.name || '';
        if (name === 'leaf') {
          o.material = colored ? this.materials.leafColored : this.materials.leaf;
          this.leaves = o;
        } else {
          o.material = colored ? this.materials.barkColored : this.materials.bark;
          this.bark = o;
        }
      }
    });
    this.treeRoot.add(root);
    root.updateMatrixWorld(true);
    if (this.bark) this.bark.visible = this.showBark;
    if (this.leaves) this.leaves.visible = this.showLeaves;
    this.overlay.removeFromParent();
    if (this.bark) this.bark.parent.add(this.overlay);
    this._applyHighlights();
  }

  setVisible({ bark, leaves }) {
    if (bark !== undefined) this.showBark = bark;
    if (leaves !== undefined) this.showLeaves = leaves;
    if (this.bark) this.bark.visible = this.showBark;
    if (this.leaves) this.leaves.visible = this.showLeaves;
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
   * The tree under a client position: {node, point} (node id from _NODE_ID of the hit
   * triangle's first vertex), else the nearest bark vertex within `slop` px, else null.
   */
  pick(clientX, clientY, slop = 8) {
    const targets = [this.bark, this.showLeaves ? this.leaves : null].filter((m) => m && m.visible);
    if (!targets.length) return null;
    this.raycaster.setFromCamera(this.ndc(clientX, clientY), this.camera);
    const hits = this.raycaster.intersectObjects(targets, false);
    for (const h of hits) {
      const ids = h.object.geometry.attributes[NODE_ID];
      if (ids && h.face) return { node: Math.round(ids.getX(h.face.a)), point: h.point.clone() };
    }
    if (!this.bark || !this.bark.visible) return null;
    // Thin twigs are hard to hit: take the nearest bark vertex on screen.
    const g = this.bark.geometry, pos = g.attributes.position, ids = g.attributes[NODE_ID];
    const rect = this.renderer.domElement.getBoundingClientRect();
    const m = new THREE.Matrix4().multiplyMatrices(this.camera.projectionMatrix,
      this.camera.matrixWorldInverse).multiply(this.bark.matrixWorld);
    const v = new THREE.Vector3();
    let best = -1, bestD = slop * slop, bestZ = Infinity;
    for (let i = 0; i < pos.count; i++) {
      v.fromBufferAttribute(pos, i).applyMatrix4(m);
      if (v.z < -1 || v.z > 1) continue;
      const dx = rect.left + (v.x + 1) / 2 * rect.width - clientX;
      const dy = rect.top + (1 - v.y) / 2 * rect.height - clientY;
      const d = dx * dx + dy * dy;
      if (d < bestD || (d === bestD && v.z < bestZ)) { best = i; bestD = d; bestZ = v.z; }
    }
    if (best < 0) return null;
    const point = new THREE.Vector3().fromBufferAttribute(pos, best).applyMatrix4(this.bark.matrixWorld);
    return { node: Math.round(ids.getX(best)), point };
  }

  /**
   * Per-node centroid and principal axis (world space) from the bark vertices, by node
   * id; computed once per snapshot, on demand.
   */
  nodes() {
    if (this.nodeInfo) return this.nodeInfo;
    const info = new Map();
    if (!this.bark) return (this.nodeInfo = info);
    const g = this.bark.geometry, pos = g.attributes.position, nrm = g.attributes.normal;
    const ids = g.attributes[NODE_ID];
    const mw = this.bark.matrixWorld, v = new THREE.Vector3(), n = new THREE.Vector3();
    const acc = new Map();
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
   * whose first vertex names one of the ids.
   */
  setHighlight(name, ids, color) {
    this.highlights ??= new Map();
    if (!ids) this.highlights.delete(name); else this.highlights.set(name, { ids, color });
    this._applyHighlights();
    this.requestRender();
  }

  _applyHighlights() {
    for (const o of this.overlay.children) o.geometry.dispose();
    this.overlay.clear();
    if (!this.bark || !this.highlights?.size) return;
    this.overlay.position.copy(this.bark.position);
    this.overlay.quaternion.copy(this.bark.quaternion);
    this.overlay.scale.copy(this.bark.scale);
    const g = this.bark.geometry, ids = g.attributes[NODE_ID], index = g.index;
    let order = 0;
    for (const { ids: want, color } of this.highlights.values()) {
      const has = typeof want === 'function' ? want : (id) => want.has(id);
      const out = [];
      const n = index ? index.count : g.attributes.position.count;
      for (let t = 0; t < n; t += 3) {
        const a = index ? index.getX(t) : t;
        if (has(Math.round(ids.getX(a)))) {
          out.push(a, index ? index.getX(t + 1) : t + 1, index ? index.getX(t + 2) : t + 2);
        }
      }
      if (!out.length) continue;
      const hg = new THREE.BufferGeometry();
      hg.setAttribute('position', g.attributes.position);
      hg.setAttribute('normal', g.attributes.normal);
      hg.setIndex(out);
      let mat = this.highlightMaterials.get(color);
      if (!mat) {
        mat = new THREE.MeshStandardMaterial({ color, emissive: color, emissiveIntensity: 0.35,
          roughness: 0.6, polygonOffset: true, polygonOffsetFactor: -1 - order, polygonOffsetUnits: -4 });
        this.highlightMaterials.set(color, mat);
      }
      const m = new THREE.Mesh(hg, mat);
      m.renderOrder = 2 + order++;
      this.overlay.add(m);
    }
  }

  /** Largest node id in the snapshot (-1 without bark). */
  maxNodeId() {
    if (!this.bark) return -1;
    const ids = this.bark.geometry.attributes[NODE_ID];
    let m = -1;
    for (let i = 0; i < ids.count; i++) m = Math.max(m, ids.getX(i));
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
