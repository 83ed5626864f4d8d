// Pointer handling for the cage handles: picks in screen space (the nearest projected handle
// within a few pixels), drags on the plane through the grabbed handle facing the camera, and emits.
// It decides nothing else: the app says which handles a pick moves and what a drag does. The drag
// geometry is mrvol/three's (lib/three/pointer.mjs), as in the component.
import { THREE } from './viewer.js';
import { DragPlane } from '../lib/three/pointer.mjs';

const PICK_RADIUS_PX = 8;
const CLICK_SLOP_PX = 4;

// Scratch objects: pointer handlers do not allocate.
const ray = new THREE.Ray();
const point = new THREE.Vector3();

/**
 * handlers: {
 *   pick(index, shiftKey) -> handle indices to drag, or null (no drag),
 *   dragStart(handles), drag(delta: [dx, dy, dz], eventTime), dragEnd(), dragCancel(),
 *   clickEmpty(),
 *   boxSelect(indices) for a shift-drag on empty space: the handles inside the box,
 *   painting() -> true while presses paint handles instead of dragging them,
 *   paint(index, first) for each handle a stroke passes over (first: the one pressed), paintEnd(),
 * }
 */
export class CageDragger {
  constructor(viewer, container, handlers) {
    this.viewer = viewer;
    this.container = container;
    this.handlers = handlers;
    this.drag = null;
    this.down = null;
    this.stroke = null; // a paint stroke: { pointerId, last }
    this.box = null;    // a selection box: { pointerId, x0, y0, x1, y1, el }
    this.enabled = true;
    // Capture phase on the container: runs before OrbitControls' listeners on the canvas, so a
    // press on a handle never starts an orbit.
    container.addEventListener('pointerdown', (e) => this.#pointerDown(e), { capture: true });
    container.addEventListener('pointermove', (e) => this.#pointerMove(e), { capture: true });
    container.addEventListener('pointerup', (e) => this.#pointerUp(e), { capture: true });
    container.addEventListener('pointercancel', (e) => this.#pointerUp(e, true), { capture: true });
  }

  get dragging() { return this.drag !== null && this.drag.started && !this.drag.cancelled; }

  #local(e) {
    const rect = this.viewer.canvas.getBoundingClientRect();
    return [e.clientX - rect.left, e.clientY - rect.top];
  }

  #pointerDown(e) {
    if (!this.enabled || e.button !== 0 || this.drag || this.stroke || this.box) return;
    const [x, y] = this.#local(e);
    const index = this.viewer.pickHandle(x, y, PICK_RADIUS_PX);
    if (index < 0 && e.shiftKey && this.handlers.boxSelect && !this.handlers.painting?.()) {
      // Shift-drag on empty space: a selection box (instead of OrbitControls' pan).
      e.stopPropagation();
      e.preventDefault();
      const el = document.createElement('div');
      el.className = 'selection-box';
      el.dataset.testid = 'selection-box';
      Object.assign(el.style, { position: 'fixed', pointerEvents: 'none', border: '1px dashed #1f6feb',
                                background: 'rgba(31, 111, 235, 0.08)', left: `${e.clientX}px`, top: `${e.clientY}px`,
                                width: '0px', height: '0px' });
      document.body.append(el);
      this.box = { pointerId: e.pointerId, x0: e.clientX, y0: e.clientY, x1: e.clientX, y1: e.clientY, el };
      this.viewer.canvas.setPointerCapture?.(e.pointerId);
      return;
    }
    if (index < 0) {
      this.down = { x: e.clientX, y: e.clientY };
      return;
    }
    e.stopPropagation();
    e.preventDefault();
    if (this.handlers.painting?.()) {
      // A stroke: every handle it passes over is painted (no orbit meanwhile).
      this.stroke = { pointerId: e.pointerId, last: index };
      this.viewer.canvas.setPointerCapture?.(e.pointerId);
      this.handlers.paint(index, true);
      return;
    }
    const handles = this.handlers.pick(index, e.shiftKey);
    if (!handles || handles.length === 0) return;
    point.fromArray(this.viewer.cagePositions, 3 * index);
    const plane = new DragPlane();
    if (!plane.start(this.viewer.camera, this.viewer.rayAt(x, y, ray), point)) return;
    this.drag = { pointerId: e.pointerId, handles, started: false, cancelled: false, plane };
    this.viewer.canvas.setPointerCapture?.(e.pointerId);
    this.container.classList.add('dragging');
  }

  #pointerMove(e) {
    const box = this.box;
    if (box) {
      if (e.pointerId !== box.pointerId) return;
      e.stopPropagation();
      box.x1 = e.clientX, box.y1 = e.clientY;
      Object.assign(box.el.style, { left: `${Math.min(box.x0, box.x1)}px`, top: `${Math.min(box.y0, box.y1)}px`,
                                    width: `${Math.abs(box.x1 - box.x0)}px`, height: `${Math.abs(box.y1 - box.y0)}px` });
      return;
    }
    const stroke = this.stroke;
    if (stroke) {
      if (e.pointerId !== stroke.pointerId) return;
      e.stopPropagation();
      const [x, y] = this.#local(e);
      const index = this.viewer.pickHandle(x, y, PICK_RADIUS_PX);
      this.viewer.setHover(index);
      if (index >= 0 && index !== stroke.last) {
        stroke.last = index;
        this.handlers.paint(index, false);
      }
      return;
    }
    const drag = this.drag;
    if (!drag) {
      if (e.buttons !== 0 || !this.enabled) return;
      const [x, y] = this.#local(e);
      const index = this.viewer.pickHandle(x, y, PICK_RADIUS_PX);
      this.viewer.setHover(index);
      this.container.classList.toggle('over-handle', index >= 0);
      return;
    }
    if (e.pointerId !== drag.pointerId) return;
    e.stopPropagation();
    if (drag.cancelled) return;
    const [x, y] = this.#local(e);
    const delta = drag.plane.delta(this.viewer.rayAt(x, y, ray));
    if (!delta) return;
    if (!drag.started) {
      drag.started = true;
      this.handlers.dragStart(drag.handles);
    }
    this.handlers.drag(delta, e.timeStamp);
  }

  #pointerUp(e, cancelled = false) {
    const box = this.box;
    if (box && e.pointerId === box.pointerId) {
      e.stopPropagation();
      this.box = null;
      box.el.remove();
      this.viewer.canvas.releasePointerCapture?.(e.pointerId);
      if (cancelled || Math.hypot(box.x1 - box.x0, box.y1 - box.y0) < CLICK_SLOP_PX) return;
      // Handles whose projection lies in the box (and in front of the camera).
      const rect = this.viewer.canvas.getBoundingClientRect();
      const depths = new Float64Array(this.viewer.cageCount);
      const screen = this.viewer.projectHandles(undefined, depths);
      const [xa, xb] = [Math.min(box.x0, box.x1) - rect.left, Math.max(box.x0, box.x1) - rect.left];
      const [ya, yb] = [Math.min(box.y0, box.y1) - rect.top, Math.max(box.y0, box.y1) - rect.top];
      const inside = [];
      for (let i = 0; i < this.viewer.cageCount; i++) {
        const sx = screen[2 * i], sy = screen[2 * i + 1];
        if (depths[i] >= -1 && depths[i] <= 1 && sx >= xa && sx <= xb && sy >= ya && sy <= yb) inside.push(i);
      }
      this.handlers.boxSelect(inside);
      return;
    }
    const stroke = this.stroke;
    if (stroke && e.pointerId === stroke.pointerId) {
      e.stopPropagation();
      this.stroke = null;
      this.viewer.canvas.releasePointerCapture?.(e.pointerId);
      this.handlers.paintEnd?.();
      return;
    }
    const drag = this.drag;
    if (drag && e.pointerId === drag.pointerId) {
      e.stopPropagation();
      this.drag = null;
      this.viewer.canvas.releasePointerCapture?.(e.pointerId);
      this.container.classList.remove('dragging');
      if (drag.started && !drag.cancelled) {
        if (cancelled) this.handlers.dragCancel();
        else this.handlers.dragEnd();
      }
      return;
    }
    if (this.down && !cancelled) {
      const moved = Math.hypot(e.clientX - this.down.x, e.clientY - this.down.y);
      if (moved < CLICK_SLOP_PX && !e.shiftKey) this.handlers.clickEmpty();
    }
    this.down = null;
  }

  /** Escape: abandons the running drag (the app restores the cage). True if there was one. */
  cancel() {
    const drag = this.drag;
    if (!drag || !drag.started || drag.cancelled) return false;
    drag.cancelled = true;
    this.container.classList.remove('dragging');
    this.handlers.dragCancel();
    return true;
  }
}
