// mrvol/three: volume-preserving cage editing as a three.js component for any scene.
//
//   const editor = new VolumeEditControls(mrvol, camera, renderer.domElement, mesh, { level: 0 });
//   scene.add(editor.object);
//   editor.addEventListener('change', () => renderer.render(scene, camera));
//
// The mesh may be a quad mesh ({ positions, quads } or a QuadMultiresMesh): the surface is drawn as
// triangles (each quad split in two), the cage as quads (their sides), the volume kept is the
// bilinear patches' (Catmull-Clark, docs/catmull-clark.md).
//
// It builds an Object3D (the fine surface, the level-e cage's edges and handles), drags handles
// with the pointer (mouse, pen, touch) on the plane facing the camera, restores the volume on every
// move (the mrvol editor), keeps undo/redo, and emits events as three.js controls do. It decides
// nothing else (no keys, no selection, no DOM of its own) and renders nothing: the host renders on
// `change`. dispose() frees the WASM memory it allocated and removes its listeners.
import * as THREE from 'three';
import { EditingSession } from './session.mjs';
import { SurfaceMesh, CageObject, CAGE_COLOR } from './objects.mjs';
import { SurfaceUpload } from './surface-upload.mjs';
import { projectPoints, nearestOnScreen, rayThrough, DragPlane } from './pointer.mjs';

export { EditingSession, FREE_SET_MODES, MAX_PARTS, QUAD_SCHEME } from './session.mjs';
export { SurfaceMesh, CageObject, HIDDEN_HANDLE_OPACITY, AUTO_HANDLE_SIZE, handleSizeForSpacing, medianEdgeSpacing, arrows, bounds, frameSphere, edgesOf, quadEdgesOf, trianglesOfQuads } from './objects.mjs';
export { projectPoints, nearestOnScreen, rayThrough, DragPlane } from './pointer.mjs';

const HOVER_COLOR = new THREE.Color(0x3fb950);
// element -> { count of editors listening on it, its touch-action before the first }
const touchClaims = new WeakMap();
const ACTIVE_COLOR = new THREE.Color(0xf0a020);

export class VolumeEditControls extends THREE.EventDispatcher {
  /**
   * @param {object} mrvol the API object (createMrvol)
   * @param {THREE.Camera} camera the camera the scene is rendered with
   * @param {HTMLElement | { domElement: HTMLElement }} element the element the pointer acts on (or a renderer)
   * @param {{ positions: Float64Array, faces: Uint32Array } | { positions: Float64Array, quads: Uint32Array } | object} mesh
   *   a triangle or quad mesh, or a MultiresMesh / QuadMultiresMesh (stays the caller's)
   * @param {object} [options] { level = 0, scheme = 'loop', preserve = true, tolerance = 1e-6,
   *   theta: unset (default: the cage polynomial where the cage is coarse against the mesh, as
   *   createEditor's 'auto' picks it, else matrix-free) | 'matrix-free' | 'auto' (compute theta^e now
   *   when it fits) | a Theta,
   *   pickRadius = 10 (CSS px), surfaceColor, cageColor, flat = true,
   *   handleSize = 'auto' (sized to the cage's spacing on the screen, 6..13 CSS px) | CSS px }
   */
  constructor(mrvol, camera, element, mesh, options = {}) {
    super();
    const { level = 0, scheme, preserve = true, tolerance = 1e-6, theta = null, pickRadius = 10,
      surfaceColor, cageColor = CAGE_COLOR, handleSize = 'auto', flat = true } = options;
    this.#MrvolError = mrvol.MrvolError;
    this.camera = camera;
    this.domElement = element?.domElement ?? element;
    if (!this.domElement?.addEventListener) throw new TypeError('VolumeEditControls needs a DOM element or a renderer');
    this.enabled = true;
    this.pickRadius = pickRadius;
    // (unset: the session's 'auto' path, O(cage) per step where it takes the polynomial, where
    // matrix-free is a pass over the fine mesh: 16 ms against 0.02 at 163k vertices)
    this.session = new EditingSession(mrvol, { level, scheme, preserve, tolerance, path: theta === null ? 'auto' : 'matrix-free' });
    this.session.open(mesh, { name: 'mesh' });
    this.object = new THREE.Group();
    this.object.name = 'mrvol';
    this.surface = new SurfaceMesh(this.session.positions(), this.session.model.faces, { color: surfaceColor, flat });
    this.surface.frustumCulled = false; // (its bounding sphere is not kept up to date: #sync)
    // drawn from the editor's own positions: the first move copies only what it moved
    if (typeof this.session.editor.positionsView === 'function') this.#upload.takeInStep(this.surface.geometry, this.session.editor);
    this.object.add(this.surface);
    this.#cageStyle = { color: cageColor, handleSize };
    this.cage = null;
    this.#buildCage();
    if (theta === 'auto') {
      if (this.session.gradientChoice().path === 'tensor') this.session.computeTheta();
    } else if (theta !== null && theta !== 'matrix-free') {
      const used = this.session.useTheta(theta, 'given');
      if (!used.ok) {
        this.surface.dispose();
        this.cage.dispose();
        this.session.dispose();
        throw new mrvol.MrvolError(`this theta does not fit the mesh: ${used.reason}`);
      }
    }
    this.session.addEventListener('error', this.#onError);
    this.#listen(true);
  }

  #cageStyle;
  #MrvolError;
  #disposed = false;
  // The session after dispose() is gone: a call then says so (it was a TypeError from inside, a
  // null volume, or an answer about the freed cage).
  #live() {
    if (this.#disposed) throw new this.#MrvolError('this VolumeEditControls was disposed');
    return this.session;
  }
  #drag = null;    // { pointerId, handle, plane, origin (world), started }
  #hover = -1;
  #screen = null;
  #depths = null;
  #ray = new THREE.Ray();
  #world = new THREE.Vector3();
  #local = new THREE.Vector3();
  #originLocal = new THREE.Vector3();

  get preserve() { return this.#live().preserve; }
  set preserve(value) { this.#live().preserve = Boolean(value); }
  get level() { return this.#live().level; }
  get dragging() { return this.#drag?.started ?? false; }
  /** Handle (cage vertex) count. */
  get handleCount() { return this.#live().cageSize; }
  /** 'auto' or the fixed handle size (CSS px) given. */
  get handleSize() { return this.cage.handleSize; }
  /**
   * The handle dot size (CSS px) for the camera and the element now: the fixed size, or 'auto''s
   * (measured again only when the camera, the element's size or the cage changed).
   */
  get handlePixelSize() {
    const rect = this.domElement.getBoundingClientRect();
    return this.cage.updateHandleSize(this.camera, rect.width, rect.height);
  }

  volume() { return this.#live().volume(); }
  referenceVolume() { return this.#live().referenceVolume(); }
  /** Fine positions (caller's vertex order) and cage positions (cage order), copies. */
  positions() { return this.#live().positions(); }
  cagePositions() { return this.#live().cagePositions(); }
  /** The core's report of the last drag step, or null. */
  get lastReport() { return this.session.lastReport; }

  /** Another cage level (the shape and the reference volume stay). */
  setLevel(level) {
    this.#live().setLevel(level);
    this.#buildCage();
    this.#changed(null, 'level');
  }

  /**
   * Moves handles (cage vertices, cage order) by `delta` from code, as one drag: the volume
   * restored, one undo step, the picture redrawn and `change` (reason 'move') sent. Returns the
   * core's report, or null when refused (an `error` event says why). Not during a pointer drag.
   */
  moveHandles(handles, delta) {
    const session = this.#live();
    if (this.#drag) throw new this.#MrvolError('moveHandles: a pointer drag is going on');
    const report = session.moveHandles(handles, delta);
    this.#sync();
    this.#changed(report, 'move');
    return report;
  }

  undo() {
    if (!this.#live().undo()) return false;
    this.#sync();
    this.#changed(null, 'undo');
    return true;
  }

  redo() {
    if (!this.#live().redo()) return false;
    this.#sync();
    this.#changed(null, 'redo');
    return true;
  }

  /** Abandons a drag going on (the cage goes back); true if there was one. */
  cancel() {
    const drag = this.#drag;
    if (!drag) return false;
    this.#drag = null;
    this.domElement.releasePointerCapture?.(drag.pointerId);
    if (!drag.started) return false;
    this.session.cancelDrag();
    this.#sync();
    this.#colorHandles();
    this.dispatchEvent({ type: 'dragend', cancelled: true });
    this.#changed(null, 'cancel');
    return true;
  }

  /** Screen positions of the handles ([x0, y0, ...], CSS pixels of the element). */
  handleScreenPositions() {
    this.#live();
    const rect = this.domElement.getBoundingClientRect();
    return Array.from(this.#project(rect));
  }

  /** Frees what the editor holds (WASM memory, GPU buffers, listeners); later calls throw MrvolError. A second call does nothing. */
  dispose() {
    if (this.#disposed) return;
    this.cancel();
    this.#listen(false);
    this.session.removeEventListener('error', this.#onError);
    this.object.removeFromParent();
    this.surface.dispose();
    this.cage?.dispose();
    this.session.dispose();
    this.#disposed = true;
  }

  // ---- drawing ----------------------------------------------------------------------------------------

  #buildCage() {
    if (this.cage) {
      this.object.remove(this.cage);
      this.cage.dispose();
    }
    this.cage = new CageObject(this.session.cagePositions(), this.session.cageEdges(), this.#cageStyle);
    this.object.add(this.cage);
    this.#hover = -1;
    this.#screen = new Float64Array(2 * this.session.cageSize);
    this.#depths = new Float64Array(this.session.cageSize);
  }

  // The surface from the editor's float32 buffers in WASM memory where it has them (positions and
  // normals written by the core, only the vertices an edit rewrote copied and uploaded), else from
  // its positions. No bounding sphere per move (a pass over the mesh): the surface is not culled,
  // and a raycast computes the sphere when it needs it.
  #upload = new SurfaceUpload();
  #sync() {
    const editor = this.session.editor;
    if (typeof editor.positionsView === 'function') {
      this.#upload.draw(this.surface.geometry, editor, { normals: !this.surface.material.flatShading });
      this.surface.geometry.boundingSphere = null;
    } else {
      this.surface.setPositions(this.session.positions());
    }
    this.cage.setPositions(this.session.cagePositions());
  }

  #colorHandles() {
    const active = this.#drag?.started ? this.#drag.handle : -1;
    this.cage.setHandleColors((i) => (i === active ? ACTIVE_COLOR : i === this.#hover ? HOVER_COLOR : this.cage.baseColor));
  }

  #changed(report, reason) {
    this.dispatchEvent({ type: 'change', report, reason });
  }

  #onError = (e) => {
    this.dispatchEvent({ type: 'error', message: e.detail.message, error: e.detail.error });
  };

  // ---- pointer ----------------------------------------------------------------------------------------

  #project(rect) {
    // Handles in world coordinates (the object may be moved, turned, scaled), into a kept buffer:
    // pointer moves do not allocate.
    this.object.updateWorldMatrix(true, false);
    const local = this.cage.positions;
    if (this.#worldPositions?.length !== local.length) this.#worldPositions = new Float64Array(local.length);
    const world = this.#worldPositions;
    const matrix = this.object.matrixWorld;
    for (let i = 0; i < world.length; i += 3) this.#world.fromArray(local, i).applyMatrix4(matrix).toArray(world, i);
    return projectPoints(world, this.camera, rect.width, rect.height, this.#screen, this.#depths);
  }
  #worldPositions = null;

  #pick(e) {
    const rect = this.domElement.getBoundingClientRect();
    const x = e.clientX - rect.left, y = e.clientY - rect.top;
    if (!this.object.visible || !this.cage.visible) return { index: -1, x, y, rect };
    this.#project(rect);
    return { index: nearestOnScreen(this.#screen, this.#depths, x, y, this.pickRadius), x, y, rect };
  }

  #listen(on) {
    const method = on ? 'addEventListener' : 'removeEventListener';
    // Capture: runs before OrbitControls' listeners on the same element, which a press on a handle stops.
    this.domElement[method]('pointerdown', this.#onPointerDown, { capture: true });
    this.domElement[method]('pointermove', this.#onPointerMove, { capture: true });
    this.domElement[method]('pointerup', this.#onPointerUp, { capture: true });
    this.domElement[method]('pointercancel', this.#onPointerCancel, { capture: true });
    // Touch drags are ours, not the page's scroll, while any editor listens on the element: the
    // element's own touch-action comes back when the last one is disposed, in whatever order.
    const style = this.domElement.style;
    const claim = touchClaims.get(this.domElement) ?? { count: 0, original: style.touchAction };
    claim.count += on ? 1 : -1;
    if (claim.count > 0) {
      touchClaims.set(this.domElement, claim);
      style.touchAction = 'none';
    } else {
      touchClaims.delete(this.domElement);
      style.touchAction = claim.original;
    }
  }

  #onPointerDown = (e) => {
    if (!this.enabled || this.#drag || (e.pointerType === 'mouse' && e.button !== 0)) return;
    const { index, x, y, rect } = this.#pick(e);
    if (index < 0) return;
    e.stopImmediatePropagation();
    e.preventDefault();
    this.object.updateWorldMatrix(true, false);
    const point = new THREE.Vector3().fromArray(this.cage.positions, 3 * index).applyMatrix4(this.object.matrixWorld);
    const plane = new DragPlane();
    if (!plane.start(this.camera, rayThrough(this.camera, x, y, rect.width, rect.height, this.#ray), point)) return;
    this.#drag = { pointerId: e.pointerId, handle: index, plane, origin: point, started: false };
    this.domElement.setPointerCapture?.(e.pointerId);
  };

  #onPointerMove = (e) => {
    const drag = this.#drag;
    if (!drag) {
      if (!this.enabled || e.buttons !== 0) return;
      const { index } = this.#pick(e);
      if (index !== this.#hover) {
        this.#hover = index;
        this.#colorHandles();
        this.#changed(null, 'hover');
      }
      return;
    }
    if (e.pointerId !== drag.pointerId) return;
    e.stopImmediatePropagation();
    const rect = this.domElement.getBoundingClientRect();
    const ray = rayThrough(this.camera, e.clientX - rect.left, e.clientY - rect.top, rect.width, rect.height, this.#ray);
    const delta = drag.plane.delta(ray);
    if (!delta) return;
    if (!drag.started) {
      drag.started = true;
      this.session.beginDrag([drag.handle]);
      this.#colorHandles();
      this.dispatchEvent({ type: 'dragstart', handle: drag.handle });
    }
    // The world displacement in the object's own coordinates (it may be moved, turned, scaled).
    this.#originLocal.copy(drag.origin);
    this.object.worldToLocal(this.#originLocal);
    this.#local.copy(drag.origin).add(this.#world.fromArray(delta));
    this.object.worldToLocal(this.#local).sub(this.#originLocal);
    const report = this.session.dragBy(this.#local.toArray());
    if (!report) {
      // Refused (an `error` event said why): the session put the cage back.
      this.#drag = null;
      this.domElement.releasePointerCapture?.(e.pointerId);
      this.#sync();
      this.#colorHandles();
      this.dispatchEvent({ type: 'dragend', cancelled: true });
      this.#changed(null, 'cancel');
      return;
    }
    this.#sync();
    this.dispatchEvent({ type: 'drag', handle: drag.handle, report });
    this.#changed(report, 'drag');
  };

  #onPointerUp = (e) => {
    const drag = this.#drag;
    if (!drag || e.pointerId !== drag.pointerId) return;
    e.stopImmediatePropagation();
    this.#drag = null;
    this.domElement.releasePointerCapture?.(e.pointerId);
    if (!drag.started) return;
    this.session.endDrag();
    this.#colorHandles();
    this.dispatchEvent({ type: 'dragend', handle: drag.handle, cancelled: false });
    this.#changed(this.session.lastReport, 'dragend');
  };

  #onPointerCancel = (e) => {
    if (this.#drag && e.pointerId === this.#drag.pointerId) this.cancel();
  };
}
