// The three.js view: the fine mesh (flat or smooth shading), the level-e cage over it (edges and
// handle points), orbit/pan/zoom, rendering on demand. It draws what it is given and projects
// handles to the screen; it knows nothing of the core. The cage and the picking are mrvol/three's
// (lib/three): the same objects and pointer geometry as the component.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { CageObject, CAGE_COLOR, frameSphere } from '../lib/three/objects.mjs';
import { FloorShadow } from './floor-shadow.js';
import { projectPoints, nearestOnScreen, rayThrough } from '../lib/three/pointer.mjs';
import { SurfaceUpload } from '../lib/three/surface-upload.mjs';
import { roomLightProbe } from './room-light.js';
import { softwareWebGL } from './software-webgl.js';

const MESH_COLOR = 0xc9b8a0;
const HANDLE_COLOR = new THREE.Color(CAGE_COLOR);
const SELECTED_COLOR = new THREE.Color(0xf0a020);
const HOVER_COLOR = new THREE.Color(0x3fb950);
const APPROX_COLOR = 0x2da44e;
const DETAIL_COLOR = 0xcf222e;
const FOV_DEG = 35;
// The page's background (web/style.css --page-bg) in each theme.
const BACKGROUND = { light: 0xf4f5f7, dark: 0x16191d };
const ROOM_LIGHT_INTENSITY = 0.45;

const FRAME_DIRECTION = new THREE.Vector3(0.45, 0.35, 1).normalize();
const FRAME_MARGIN = 1.1;
const FRAME_SAMPLES = 20_000; // points of a big mesh looked at to frame it
const SHADOW_TRIANGLES = 200_000; // above this, the floor shadow is drawn from a coarser level
const SURFACE_LATER_VERTICES = 100_000; // above this, an opened model's surface buffers wait for the first frame (updateMeshFrom)

/**
 * Puts the camera on FRAME_DIRECTION from the points' projected centre, at the least distance that
 * shows every point (a sample of them for big meshes) with FRAME_MARGIN. sets: arrays of x, y, z.
 */
function frameTight(camera, sets, controls) {
  const z = FRAME_DIRECTION, x = new THREE.Vector3(0, 1, 0).cross(z).normalize(), y = z.clone().cross(x);
  const box = new THREE.Box3();
  const p = new THREE.Vector3();
  const each = (fn) => {
    for (const a of sets) {
      const count = a.length / 3, stride = Math.max(1, Math.floor(count / FRAME_SAMPLES));
      for (let i = 0; i < count; i += stride) fn(p.set(a[3 * i], a[3 * i + 1], a[3 * i + 2]));
    }
  };
  each((q) => box.expandByPoint(q));
  if (box.isEmpty()) return;
  // the centre of the points as seen along the view direction
  const mid = box.getCenter(new THREE.Vector3());
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  each((q) => {
    q.sub(mid);
    x0 = Math.min(x0, q.dot(x)); x1 = Math.max(x1, q.dot(x));
    y0 = Math.min(y0, q.dot(y)); y1 = Math.max(y1, q.dot(y));
  });
  const center = mid.clone().addScaledVector(x, (x0 + x1) / 2).addScaledVector(y, (y0 + y1) / 2);
  const tanV = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)), tanH = tanV * camera.aspect;
  let distance = 0, depth = 0;
  const place = () => {
    distance = 0, depth = 0;
    each((q) => {
      q.sub(center);
      const along = q.dot(z);
      depth = Math.max(depth, along);
      distance = Math.max(distance, along + FRAME_MARGIN * Math.abs(q.dot(x)) / tanH, along + FRAME_MARGIN * Math.abs(q.dot(y)) / tanV);
    });
  };
  place();
  // In perspective the near side of the model spreads wider on the screen than the far side: the
  // centre moves (twice) to the middle of the points' extent on the screen, so the margins match.
  for (let pass = 0; pass < 2; pass++) {
    let u0 = Infinity, u1 = -Infinity, v0 = Infinity, v1 = -Infinity;
    each((q) => {
      q.sub(center);
      const ahead = distance - q.dot(z);
      if (!(ahead > 0)) return;
      const u = q.dot(x) / (ahead * tanH), v = q.dot(y) / (ahead * tanV);
      u0 = Math.min(u0, u), u1 = Math.max(u1, u), v0 = Math.min(v0, v), v1 = Math.max(v1, v);
    });
    if (!(u1 >= u0 && v1 >= v0)) break;
    center.addScaledVector(x, ((u0 + u1) / 2) * tanH * distance).addScaledVector(y, ((v0 + v1) / 2) * tanV * distance);
    place();
  }
  const radius = box.getSize(new THREE.Vector3()).length() / 2 || 1;
  distance = Math.max(distance, depth + radius * 0.05);
  camera.position.copy(center).addScaledVector(z, distance);
  // as frameSphere: room to zoom in and out
  camera.near = distance / 100;
  camera.far = distance * 100;
  camera.up.set(0, 1, 0);
  camera.lookAt(center);
  camera.updateProjectionMatrix();
  if (controls) {
    controls.target.copy(center);
    controls.update();
  }
}

export class Viewer {
  /** @param {HTMLElement} container the element the canvas fills */
  constructor(container) {
    this.container = container;
    // no multisampling on software WebGL: it multiplies a big mesh's frame there (software-webgl.js)
    this.renderer = new THREE.WebGLRenderer({ antialias: !softwareWebGL() });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    container.appendChild(this.renderer.domElement);
    this.canvas = this.renderer.domElement;
    const dark = window.matchMedia?.('(prefers-color-scheme: dark)');
    const applyTheme = () => {
      this.renderer.setClearColor(dark?.matches ? BACKGROUND.dark : BACKGROUND.light);
      this.requestRender();
    };
    this.frameRequested = false;
    applyTheme();
    dark?.addEventListener?.('change', applyTheme);

    this.scene = new THREE.Scene();
    // Physically based shading lit by a room (a light probe of three's RoomEnvironment: web/room-light.js)
    // plus a key light.
    this.roomLight = roomLightProbe(ROOM_LIGHT_INTENSITY);
    this.scene.add(this.roomLight);
    this.camera = new THREE.PerspectiveCamera(FOV_DEG, 1, 0.01, 1000);
    this.camera.position.set(0, 0, 6);
    this.scene.add(this.camera);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x606070, 0.6));
    const key = new THREE.DirectionalLight(0xffffff, 1.4);
    key.position.set(2, 3, 4);
    this.camera.add(key); // the light follows the view

    // a soft shadow on a floor under the model (web/floor-shadow.js)
    this.shadow = new FloorShadow(this.renderer, this.scene);
    this.shadow.onLate = () => this.requestRender();

    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.addEventListener('change', () => this.requestRender());

    this.meshMaterial = new THREE.MeshStandardMaterial({
      color: MESH_COLOR, roughness: 0.6, metalness: 0.0, flatShading: true,
      side: THREE.DoubleSide, // open meshes show their inside
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    this.mesh = null;
    // draws nothing in the view: it only casts the floor's shadow (setMesh)
    this.casterMaterial = new THREE.MeshBasicMaterial({ colorWrite: false, depthWrite: false, depthTest: false, side: THREE.DoubleSide });
    this.shadowCaster = null;
    // One set of cage materials for every cage shown (their shaders compile once, in precompile()).
    this.cageMaterials = CageObject.materials({ color: CAGE_COLOR });
    this.cage = null;
    // handle dots sized to the cage's spacing on the screen (6..13 CSS px), or a fixed size in CSS px
    this.handleSize = 'auto';
    // Optional layers: a second, semi-transparent mesh (an approximation of the fine one, same
    // faces) and line segments (one per vertex, from the approximation to the fine position).
    this.approxMaterial = new THREE.MeshStandardMaterial({
      color: APPROX_COLOR, roughness: 0.7, metalness: 0.0, flatShading: true, side: THREE.DoubleSide,
      transparent: true, opacity: 0.4, depthWrite: false,
    });
    this.detailMaterial = new THREE.LineBasicMaterial({ color: DETAIL_COLOR });
    this.approx = null;
    this.details = null;
    this.overlay = { approx: false, details: false };
    this.layerData = { approx: false, details: false };
    this.marks = new Map(); // handle index -> THREE.Color (painted handles, parts)
    this.cageGroup = new THREE.Group();
    this.scene.add(this.cageGroup);

    this.selection = new Set();
    this.hover = -1;
    this.flat = true;
    this.onFrame = null; // (renderMs) => void, called after each rendered frame

    this.frameRequested = false;
    this.beforeFrame = new Set();
    this.sized = false;
    this.sizeHeld = false; // holdSize
    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.resize();
  }

  /**
   * Compiles the shader programs of the mesh, cage and handles ahead of the first model (software
   * WebGL takes a few hundred ms for them), while the core and the model are still loading.
   */
  precompile() {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(9), 3));
    geometry.setIndex([0, 1, 2]);
    const behind = new THREE.BufferGeometry();  // the faint handles' colours have an alpha
    behind.setAttribute('position', geometry.getAttribute('position'));
    behind.setAttribute('color', new THREE.BufferAttribute(new Float32Array(12), 4));
    const placeholders = [
      new THREE.Mesh(geometry, this.meshMaterial),
      new THREE.LineSegments(geometry, this.cageMaterials.lines),
      new THREE.LineSegments(geometry, this.cageMaterials.hidden),
      new THREE.Points(geometry, this.cageMaterials.handles),
      new THREE.Points(behind, this.cageMaterials.hiddenHandles),
    ];
    this.scene.add(...placeholders);
    try {
      this.renderer.compile(this.scene, this.camera);
    } finally {
      this.scene.remove(...placeholders);
      geometry.dispose();
      behind.dispose();
    }
  }

  /**
   * Held (the status strip shown above the view while a file opens or an editor is made): the
   * canvas keeps its size in pixels when the view shrinks, pushed down and cut at the view's
   * bottom, instead of a frame drawn again at the new size at once. On software WebGL such a frame
   * held the page's thread while the GPU process drew and read it back: 0.3-0.5 s at the drop of a
   * file with a small model shown, seconds with a big one (docs/big-file-frames.md). A view grown
   * meanwhile is fitted as before. Released, the size follows the view again (a frame only when it changed).
   */
  holdSize(held) {
    if (held === this.sizeHeld) return;
    this.sizeHeld = held;
    // the canvas's size in pixels is its style (renderer.setSize): held, it stays, cut by the view
    this.container.classList.toggle('size-held', held);
    if (!held) this.resize();
  }

  /** ResizeObserver: the drawing buffer follows the view's size, and is drawn again at once. */
  resize() {
    // setSize cleared the canvas: draw now (ResizeObserver runs before paint), not a blank frame.
    if (this.#fitSize()) {
      this.shadow?.beforeRender();
      this.renderer.render(this.scene, this.camera);
    }
  }

  /**
   * Sets the drawing buffer's and camera's size to the view's; false when they were already (a
   * frame already drawn at this size is not drawn again: a frame of a big mesh takes seconds on
   * software WebGL).
   */
  #fitSize() {
    const { clientWidth: w, clientHeight: h } = this.container;
    if (w === 0 || h === 0) return false;
    const size = this.renderer.getSize(new THREE.Vector2());
    if (size.x === w && size.y === h && this.sized) return false;
    if (this.sizeHeld && w <= size.x && h <= size.y && this.sized) return false; // cut, not drawn again (holdSize)
    this.sized = true;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    // FOV_DEG spans the narrower side: a framed model stays in view when a tall view (a phone, its
    // sheet folded or not) changes height.
    this.camera.fov = w >= h ? FOV_DEG : THREE.MathUtils.radToDeg(2 * Math.atan(Math.tan(THREE.MathUtils.degToRad(FOV_DEG / 2)) * h / w));
    this.camera.updateProjectionMatrix();
    return true;
  }

  /**
   * Draws the scene in the next animation frame; `before` (optional) runs in that frame first
   * (once), e.g. to move a marker: it is drawn with this frame, not in one more.
   */
  requestRender(before = null) {
    if (before) this.beforeFrame.add(before);
    if (this.frameRequested) return;
    this.frameRequested = true;
    requestAnimationFrame(() => {
      this.frameRequested = false;
      const started = performance.now();
      // a layout change in this frame (the panel, the status strip): its size now, so that the
      // ResizeObserver after this callback finds nothing to draw again
      this.#fitSize();
      for (const fn of this.beforeFrame) fn();
      this.beforeFrame.clear();
      this.shadow.beforeRender(started);
      this.renderer.render(this.scene, this.camera);
      this.onFrame?.(performance.now() - started);
    });
  }

  /**
   * Replaces the fine mesh. positions: Float64Array (3 per vertex), faces: Uint32Array. With
   * `editorNormals` the normals come from the editor (updateMeshFrom), not computed here.
   * `shadowFaces(maxTriangles)`: for a mesh over SHADOW_TRIANGLES, coarser faces on the same vertices
   * to cast the floor shadow (web/shadow-caster.js), or null.
   */
  setMesh(positions, faces, { editorNormals = false, shadowFaces = null } = {}) {
    for (const object of [this.mesh, this.approx, this.details, this.shadowCaster]) {
      if (!object) continue;
      this.scene.remove(object);
      object.geometry.dispose();
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
    geometry.setIndex(new THREE.BufferAttribute(faces.length > 0 ? new Uint32Array(faces) : new Uint32Array(0), 1));
    this.mesh = new THREE.Mesh(geometry, this.meshMaterial);
    this.mesh.frustumCulled = false;
    this.mesh.castShadow = true;
    this.scene.add(this.mesh);
    // a big mesh's shadow from a coarser level of its hierarchy, on the same vertices (shadow-caster.js)
    this.shadowCaster = null;
    const coarse = faces.length / 3 > SHADOW_TRIANGLES ? shadowFaces?.(SHADOW_TRIANGLES) : null;
    if (coarse) {
      const caster = new THREE.BufferGeometry();
      caster.setAttribute('position', geometry.getAttribute('position')); // shared: uploaded once, follows edits
      caster.setIndex(new THREE.BufferAttribute(coarse, 1));
      this.shadowCaster = new THREE.Mesh(caster, this.casterMaterial);
      this.shadowCaster.frustumCulled = false;
      this.shadowCaster.castShadow = true;
      this.shadowCaster.visible = this.mesh.visible;
      this.mesh.castShadow = false;
      this.scene.add(this.shadowCaster);
    }
    this.shadow.fit(positions);
    // The layers (same faces) are made when first filled (updateApprox / updateDetails): a big
    // mesh opens without two more copies of its positions.
    this.approx = null;
    this.details = null;
    this.layerData = { approx: false, details: false }; // filled since the last setMesh
    if (!this.flat && !editorNormals) geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    this.requestRender();
  }

  /**
   * Points the camera at the mesh and the cage, as close as keeps every point in view (a margin of
   * FRAME_MARGIN): the model fills the view where its shape allows, not its bounding sphere.
   */
  frameAll() {
    const sets = [];
    if (this.mesh) sets.push(this.mesh.geometry.getAttribute('position').array);
    if (this.cage) sets.push(this.cage.positions);
    if (sets.length === 0) return;
    // The view's size now: a layout change of this task (a model's readouts) is not yet seen by the
    // ResizeObserver, and a frame made for the old aspect cut the model's sides on a phone.
    this.#fitSize();
    frameTight(this.camera, sets, this.controls);
    this.requestRender();
  }

  /** Points the camera at a bounding sphere (room left for the panels). */
  frame(sphere) {
    frameSphere(this.camera, { center: sphere.center.toArray(), radius: sphere.radius }, { controls: this.controls, margin: 1.3 });
  }

  /** New fine positions, same connectivity. */
  updateMesh(positions) {
    // in place: the buffer is uploaded again, not reallocated; no bounding sphere per step (the mesh
    // is not frustum culled; framing reads the positions): a pass less over a big mesh per frame
    const attribute = this.mesh.geometry.getAttribute('position');
    attribute.array.set(positions);
    attribute.needsUpdate = true;
    if (!this.flat) this.mesh.geometry.computeVertexNormals();
    this.shadow.changed();
    this.requestRender();
  }

  /**
   * The editor's current surface (its float32 positions and, unless flat, normals, computed in
   * WASM): only the vertices the last edit changed are copied and uploaded (lib/three/surface-upload.mjs).
   * `opened`: a new editor of the shape drawn (a model just opened: setMesh drew its positions; a
   * level, scheme or surface change: the shape as it was drawn); `unmoved`: nothing moved since the
   * last call (a free set chosen): see #surfaceWhenIdle.
   */
  updateMeshFrom(editor, { opened = false, unmoved = false } = {}) {
    if (!this.mesh || !editor) return;
    // a quad editor has no float32 views over WASM memory yet: its fine positions, copied
    if (typeof editor.positionsView !== 'function') return this.updateMesh(editor.positions());
    this.surfaceUpload ??= new SurfaceUpload();
    if (unmoved && this.surfaceLater === editor) return; // still what setMesh drew (#surfaceWhenIdle)
    if (opened && this.flat && editor.surface?.() !== 'limit' && this.mesh.geometry.getAttribute('position').count > SURFACE_LATER_VERTICES) {
      this.#surfaceWhenIdle(editor);
      return;
    }
    this.surfaceLater = null;
    if (this.surfaceUpload.draw(this.mesh.geometry, editor, { normals: !this.flat })) {
      this.shadow.changed();
      this.requestRender();
    }
  }

  // A model just opened (`opened`): the editor's surface is the positions setMesh drew (its own
  // mesh, flat shading: no normals needed). A big one's float32 buffers, which the core builds on
  // their first use (0.3 s at 655k vertices: most of the page's set-up), wait until the page is idle
  // after the first frame; the attribute is then taken as in step with them (nothing copied,
  // uploaded or drawn again). An update before that (an edit, smooth shading) draws as usual.
  #surfaceWhenIdle(editor) {
    this.surfaceLater = editor;
    const geometry = this.mesh.geometry;
    (window.requestIdleCallback ?? ((f) => setTimeout(f, 200)))(() => {
      if (this.surfaceLater !== editor || this.mesh?.geometry !== geometry || editor.deleted) return;
      this.surfaceLater = null;
      this.surfaceUpload.takeInStep(geometry, editor);
    }, { timeout: 2000 });
  }

  /**
   * Flat or smooth shading. Smooth: the normals from `editor` (computed in WASM: normalsView) where
   * it has them, else three.js's computeVertexNormals (167 ms at 655k vertices on the page).
   */
  setFlat(flat, editor = null) {
    this.flat = flat;
    this.meshMaterial.flatShading = flat;
    this.meshMaterial.needsUpdate = true;
    if (!flat && this.mesh) {
      if (typeof editor?.normalsView === 'function') {
        this.surfaceLater = null; // (a new editor's buffers made now: the normals need them)
        this.updateMeshFrom(editor);
      } else {
        this.mesh.geometry.computeVertexNormals();
      }
    }
    this.requestRender();
  }

  setLayers({ mesh, cage, approx = this.overlay.approx, details = this.overlay.details }) {
    if (this.mesh) this.mesh.visible = mesh;
    if (this.shadowCaster) this.shadowCaster.visible = mesh;
    if (this.shadow.floor.visible !== mesh) this.shadow.setVisible(mesh);
    this.cageGroup.visible = cage;
    this.overlay = { approx, details };
    this.#showOverlay();
    this.requestRender();
  }

  #showOverlay() {
    if (this.approx) this.approx.visible = this.overlay.approx && this.layerData.approx;
    if (this.details) this.details.visible = this.overlay.details && this.layerData.details;
  }

  /** The layer `kind` ('approx' or 'details'), made for the current mesh when first asked for. */
  #layer(kind) {
    if (this[kind]) return this[kind];
    const count = this.mesh.geometry.getAttribute('position').count;
    const geometry = new THREE.BufferGeometry();
    let object;
    if (kind === 'approx') {
      geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * count), 3));
      geometry.setIndex(this.mesh.geometry.getIndex());
      object = new THREE.Mesh(geometry, this.approxMaterial);
      object.renderOrder = 1;
    } else {
      geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6 * count), 3));
      object = new THREE.LineSegments(geometry, this.detailMaterial);
    }
    object.frustumCulled = false;
    object.visible = false;
    this.scene.add(object);
    this[kind] = object;
    return object;
  }

  /** The approximation layer's positions (same vertices and faces as the fine mesh). */
  updateApprox(positions) {
    const attribute = this.#layer('approx').geometry.getAttribute('position');
    attribute.array.set(positions);
    attribute.needsUpdate = true;
    this.layerData.approx = true;
    this.#showOverlay();
    this.requestRender();
  }

  /** One segment per vertex, from `from` to `to` (3 per vertex each). */
  updateDetails(from, to) {
    const attribute = this.#layer('details').geometry.getAttribute('position');
    const out = attribute.array;
    for (let i = 0, n = from.length / 3; i < n; i++) {
      out[6 * i] = from[3 * i];
      out[6 * i + 1] = from[3 * i + 1];
      out[6 * i + 2] = from[3 * i + 2];
      out[6 * i + 3] = to[3 * i];
      out[6 * i + 4] = to[3 * i + 1];
      out[6 * i + 5] = to[3 * i + 2];
    }
    attribute.needsUpdate = true;
    this.layerData.details = true;
    this.#showOverlay();
    this.requestRender();
  }

  /** What the layers draw now (read-only counts for tests). */
  overlayInfo() {
    const drawn = (object) => Boolean(object?.visible && object.parent === this.scene);
    return {
      approx: { drawn: drawn(this.approx), vertices: this.approx ? this.approx.geometry.getAttribute('position').count : 0,
        triangles: this.approx ? this.approx.geometry.getIndex().count / 3 : 0 },
      details: { drawn: drawn(this.details), segments: drawn(this.details) ? this.details.geometry.getAttribute('position').count / 2 : 0 },
    };
  }

  /** Replaces the cage: positions (3 per handle) and edges (pairs of handle indices). */
  setCage(positions, edges) {
    if (this.cage) {
      this.cageGroup.remove(this.cage);
      this.cage.dispose();
    }
    this.cage = new CageObject(positions, edges, { materials: this.cageMaterials, handleSize: this.handleSize });
    this.cageGroup.add(this.cage);
    this.selection = new Set();
    this.marks = new Map();
    this.hover = -1;
    this.updateColors();
  }

  get cageCount() { return this.cage?.count ?? 0; }
  /** The handle dot size (CSS px) for the camera and the view now (handleSize 'auto': from the cage's spacing on the screen). */
  get handlePixelSize() {
    if (!this.cage) return null;
    return this.cage.updateHandleSize(this.camera, this.canvas.clientWidth, this.canvas.clientHeight);
  }
  /** Handle positions (Float64Array, 3 per handle) as drawn. */
  get cagePositions() { return this.cage?.positions ?? null; }

  updateCage(positions) {
    this.cage.setPositions(positions);
    this.requestRender();
  }

  setSelection(selection) {
    this.selection = new Set(selection);
    this.updateColors();
  }

  /** Colours of marked handles (painted, parts): Map of handle index to a colour (hex or CSS). */
  setMarks(marks) {
    this.marks = new Map([...marks].map(([i, c]) => [i, new THREE.Color(c)]));
    this.updateColors();
  }

  setHover(index) {
    if (index === this.hover) return;
    this.hover = index;
    this.updateColors();
  }

  updateColors() {
    if (!this.cage) return;
    // selected and hovered handles at full strength through the surface too, the others faint there
    this.cage.setHandleColors((i) => (this.selection.has(i) ? SELECTED_COLOR : i === this.hover ? HOVER_COLOR
      : this.marks.get(i) ?? HANDLE_COLOR), (i) => this.selection.has(i) || i === this.hover);
    this.requestRender();
  }

  /**
   * Handle positions on the screen: [x0, y0, x1, y1, ...] in CSS pixels relative to the canvas,
   * and the depth of each (NDC z) in `depths` when given.
   */
  projectHandles(out = new Float64Array(2 * this.cageCount), depths = null) {
    return projectPoints(this.cagePositions ?? [], this.camera, this.canvas.clientWidth, this.canvas.clientHeight, out, depths);
  }

  /** The handle nearest to a canvas point (CSS pixels) within `radius` pixels, or -1. */
  pickHandle(x, y, radius = 8) {
    if (!this.cageGroup.visible || this.cageCount === 0) return -1;
    if (this.pickDepths?.length !== this.cageCount) this.pickDepths = new Float64Array(this.cageCount);
    const screen = this.projectHandles(undefined, this.pickDepths);
    return nearestOnScreen(screen, this.pickDepths, x, y, radius);
  }

  /** Ray through a canvas point (CSS pixels). */
  rayAt(x, y, ray = new THREE.Ray()) {
    return rayThrough(this.camera, x, y, this.canvas.clientWidth, this.canvas.clientHeight, ray);
  }

  /** Camera's view direction (unit, world). */
  viewDirection(out = new THREE.Vector3()) {
    return this.camera.getWorldDirection(out);
  }
}

export { THREE };
