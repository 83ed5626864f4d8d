// Drawing for the teaching views: one WebGL canvas split into side-by-side panels (scissor), one
// camera shared by all panels (OrbitControls); the meshes, cages, arrows are mrvol/three's
// (lib/three/objects.mjs, as in the editor); and a 2D volume chart. It draws arrays it is given;
// every number comes from the core through the API.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { SurfaceMesh, CageObject, frameSphere, trianglesOfQuads } from '../../lib/three/objects.mjs';
import { storedModel } from '../session.js';
import { fetchSample } from '../models.js';
import { niceTicks } from '../ticks.js';

export { niceTicks }; // the views' charts and tests import it from here

export { THREE };
export { arrows, bounds, edgesOf, quadEdgesOf } from '../../lib/three/objects.mjs';
export { fetchSample };

export class Stage {
  /** @param {HTMLElement} container @param {string[]} labels one panel per label */
  constructor(container, labels) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.setClearColor(0xf4f5f7);
    this.renderer.setScissorTest(true);
    container.append(this.renderer.domElement);
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
    this.camera.position.set(0, 0, 6);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.requestRender());
    this.panels = [];
    this.labelBox = document.createElement('div');
    this.labelBox.className = 'learn-panel-labels';
    container.append(this.labelBox);
    this.setPanels(labels);
    this.frameRequested = false;
    this.loop = null;
    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.resize();
  }

  setPanels(labels) {
    for (const p of this.panels) {
      p.scene.traverse((o) => o.geometry?.dispose());
      p.scene.clear();
    }
    this.labelBox.replaceChildren();
    this.panels = labels.map((label) => {
      const scene = new THREE.Scene();
      scene.add(new THREE.HemisphereLight(0xffffff, 0x606070, 1.4));
      const light = new THREE.DirectionalLight(0xffffff, 1.8);
      light.position.set(2, 3, 4);
      scene.add(light);
      const tag = document.createElement('div');
      tag.className = 'learn-panel-label';
      tag.textContent = label;
      this.labelBox.append(tag);
      return { scene, label, tag, light };
    });
    this.layoutPanels();
    this.requestRender();
  }

  /**
   * Panels in the grid of columns x rows that gives each the largest square (side by side on a
   * wide stage, stacked on a tall one): cells [{ x, y, width, height }] in CSS pixels from the top left.
   */
  layoutPanels() {
    const { clientWidth: w, clientHeight: h } = this.container;
    const n = this.panels.length;
    let best = null;
    for (let columns = 1; columns <= n; columns++) {
      const rows = Math.ceil(n / columns);
      const side = Math.min(w / columns, h / rows);
      if (!best || side > best.side + 0.5) best = { columns, rows, side };
    }
    const { columns, rows } = best;
    this.cells = this.panels.map((panel, i) => {
      const c = i % columns, r = Math.floor(i / columns);
      const x = Math.round(c * w / columns), y = Math.round(r * h / rows);
      const cell = { x, y, width: Math.round((c + 1) * w / columns) - x, height: Math.round((r + 1) * h / rows) - y };
      // The tag covers its cell: the label at its top, a rule between neighbouring panels.
      Object.assign(panel.tag.style, { left: `${x}px`, top: `${y}px`, width: `${cell.width}px`, height: `${cell.height}px`,
        borderLeft: x > 0 ? '1px solid #d6d9de' : 'none', borderTop: y > 0 ? '1px solid #d6d9de' : 'none' });
      return cell;
    });
    this.grid = { columns, rows };
    if (this.cells.length && this.cells[0].height > 0) this.camera.aspect = this.cells[0].width / this.cells[0].height;
    this.camera.updateProjectionMatrix();
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.container;
    if (w === 0 || h === 0) return;
    this.renderer.setSize(w, h);
    this.layoutPanels();
    if (this.framed) { // the model fills the new panel shape, seen from where the camera is
      const [center, radius] = this.framed;
      this.frame(center, radius, this.camera.position.toArray().map((x, k) => x - center[k]), { home: false });
    }
    this.requestRender();
  }

  requestRender() {
    if (this.frameRequested || this.loop) return;
    this.frameRequested = true;
    requestAnimationFrame(() => {
      this.frameRequested = false;
      this.render();
    });
  }

  render() {
    const h = this.container.clientHeight;
    this.camera.updateMatrixWorld();
    this.renderer.setScissor(0, 0, this.container.clientWidth, h);
    this.renderer.clear();
    this.panels.forEach((panel, i) => {
      const { x, y, width, height } = this.cells[i];
      panel.light.position.copy(this.camera.position).add(new THREE.Vector3(1, 2, 0));
      this.renderer.setViewport(x, h - y - height, width, height);
      this.renderer.setScissor(x, h - y - height, width, height);
      this.renderer.render(panel.scene, this.camera);
    });
    this.frames = (this.frames ?? 0) + 1;
  }

  /** Calls step(dtSeconds) before every frame until stop(). */
  animate(step) {
    this.stop();
    let last = performance.now();
    const tick = (now) => {
      if (!this.loop) return;
      const dt = Math.min(0.05, (now - last) / 1000);
      last = now;
      step(dt);
      this.render();
      this.loop = requestAnimationFrame(tick);
    };
    this.loop = requestAnimationFrame(tick);
  }

  stop() {
    if (this.loop) cancelAnimationFrame(this.loop);
    this.loop = null;
  }

  /**
   * Camera on a bounding sphere (center [x,y,z], radius), seen from `direction`; `home`: the view
   * resetView() goes back to (a resize keeps the view the user turned to, and not as home).
   */
  frame(center, radius, direction = [0.45, 0.35, 1], { home = true } = {}) {
    this.framed = [center, radius, direction];
    if (home) this.home = [center, radius, direction];
    frameSphere(this.camera, { center, radius }, { controls: this.controls, direction, margin: 1.08 });
    this.requestRender();
  }

  /** Back to the view the view's code framed (a demo's restart). */
  resetView() {
    if (this.home) this.frame(...this.home);
  }

  dispose() {
    this.stop();
    this.resizeObserver.disconnect();
    this.controls.dispose();
    for (const p of this.panels) p.scene.traverse((o) => o.geometry?.dispose());
    this.renderer.dispose();
    this.renderer.forceContextLoss?.();
    this.renderer.domElement.remove();
    this.labelBox.remove();
  }

  /** The panel under a viewport point (CSS pixels), with the point in its normalized device coordinates, or null. */
  panelAt(clientX, clientY) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const px = clientX - rect.left, py = clientY - rect.top;
    const i = this.cells.findIndex((c) => px >= c.x && px < c.x + c.width && py >= c.y && py < c.y + c.height);
    if (i < 0) return null;
    const c = this.cells[i];
    return { index: i, ndc: new THREE.Vector2((px - c.x) / c.width * 2 - 1, 1 - (py - c.y) / c.height * 2) };
  }

  /** Viewport CSS pixels of a world point seen in panel i. */
  screenOf(point, i = 0) {
    this.camera.updateMatrixWorld();
    const p = new THREE.Vector3(...point).project(this.camera);
    const rect = this.renderer.domElement.getBoundingClientRect();
    const c = this.cells[i];
    return [rect.left + c.x + (p.x + 1) / 2 * c.width, rect.top + c.y + (1 - p.y) / 2 * c.height];
  }
}

/** A colour-map legend on the stage: the ramp, its end values and what it shows. update({ title, lo, hi }). */
export function colorbar(container, { title, lo, hi, colors = ramp, testid = 'colorbar' }) {
  const box = document.createElement('div');
  box.className = 'learn-colorbar';
  box.dataset.testid = testid;
  const name = document.createElement('div');
  const bar = document.createElement('div');
  bar.className = 'bar';
  const stops = Array.from({ length: 11 }, (_, i) => `rgb(${colors(i / 10).map((c) => Math.round(255 * c)).join(',')})`);
  bar.style.background = `linear-gradient(to right, ${stops.join(',')})`;
  const ends = document.createElement('div');
  ends.className = 'ends';
  const low = document.createElement('span'), high = document.createElement('span');
  ends.append(low, high);
  box.append(name, bar, ends);
  container.append(box);
  box.update = ({ title: t, lo: a, hi: b }) => {
    name.textContent = t;
    low.textContent = a;
    high.textContent = b;
  };
  box.update({ title, lo, hi });
  return box;
}

/** Blue - white - red, t in -1..1 -> [r, g, b] (signed values: basis functions). */
export function diverging(t) {
  const x = Math.min(1, Math.max(-1, t));
  const end = x < 0 ? [0.129, 0.4, 0.674] : [0.698, 0.094, 0.168];
  const a = Math.abs(x);
  return [0.97 + (end[0] - 0.97) * a, 0.97 + (end[1] - 0.97) * a, 0.97 + (end[2] - 0.97) * a];
}

/** A shaded surface (SurfaceMesh); update(positions) takes new positions. */
export function surface(positions, faces, options = {}) {
  const mesh = new SurfaceMesh(positions, faces, options);
  mesh.update = (p) => mesh.setPositions(p);
  return mesh;
}

/** A wire cage (CageObject) between points along index pairs, with dots; update(positions). */
export function wire(positions, edges, { color = 0x1f6feb, points = true, opacity = 1 } = {}) {
  const cage = new CageObject(positions, edges, { color, handles: points, handleSize: 7, opacity });
  cage.update = (p) => cage.setPositions(p);
  return cage;
}

/** Viridis-like ramp, t in 0..1 -> [r, g, b]. */
export function ramp(t) {
  const stops = [[0.267, 0.005, 0.329], [0.229, 0.322, 0.546], [0.128, 0.567, 0.551], [0.369, 0.789, 0.383], [0.993, 0.906, 0.144]];
  const x = Math.min(1, Math.max(0, t)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x)), f = x - i;
  return stops[i].map((c, k) => c + (stops[i + 1][k] - c) * f);
}


/**
 * A line chart of series over time on a 2D canvas: series [{ name, color, values: number[] }],
 * x = sample index. draw() redraws.
 */
export class Chart {
  /** grow: x spans the samples so far (at least 20), not maxPoints: a short record (a drag) fills the width. */
  constructor(container, { title = '', height = 150, maxPoints = 600, testid = 'volume-chart', grow = false, empty = '' } = {}) {
    this.grow = grow;
    this.empty = empty; // said while there is nothing to plot
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'learn-chart';
    this.canvas.dataset.testid = testid;
    this.canvas.height = height;
    container.append(this.canvas);
    this.title = title;
    this.series = [];
    this.maxPoints = maxPoints;
    // Drawn again at its new width when the page turns or is resized (a paused demo draws nothing else).
    let width = 0;
    new ResizeObserver(() => {
      if (this.canvas.clientWidth > 0 && this.canvas.clientWidth !== width) (width = this.canvas.clientWidth), this.draw();
    }).observe(this.canvas);
  }
  /** Forgets every sample (a demo's restart). */
  clear() {
    for (const s of this.series) s.values.length = 0;
  }
  add(name, color) {
    const s = { name, color, values: [] };
    this.series.push(s);
    return s;
  }
  push(values) {
    values.forEach((v, i) => {
      const s = this.series[i];
      s.values.push(v);
      if (s.values.length > this.maxPoints) s.values.shift();
    });
  }
  draw() {
    const c = this.canvas;
    const w = c.clientWidth || 600;
    if (c.width !== w) c.width = w;
    const h = c.height;
    const g = c.getContext('2d');
    g.clearRect(0, 0, w, h);
    g.fillStyle = '#ffffff';
    g.fillRect(0, 0, w, h);
    let lo = Infinity, hi = -Infinity;
    for (const s of this.series) for (const v of s.values) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    if (!Number.isFinite(lo)) {
      g.fillStyle = '#57606a';
      g.font = '11px system-ui, sans-serif';
      g.fillText(this.title, 12, 14);
      g.fillText(this.empty, 12, h / 2);
      return;
    }
    const pad = Math.max((hi - lo) * 0.05, Math.abs(hi) * 1e-6, 1e-12);
    const axis = niceTicks(lo - pad, hi + pad, Math.max(3, Math.floor((h - 30) / 28)));
    this.ticks = axis.ticks;
    c.dataset.ticks = JSON.stringify(axis.ticks);
    c.dataset.tickStep = String(axis.step);
    lo = axis.ticks[0];
    hi = axis.ticks[axis.ticks.length - 1];
    const labels = axis.ticks.map((v) => axis.format(v));
    c.dataset.tickLabels = JSON.stringify(labels);
    g.font = '11px system-ui, sans-serif';
    const left = 12 + Math.max(...labels.map((t) => g.measureText(t).width)), right = 10, bottom = 8;
    // The legend beside the title, or on a line of its own when the chart is narrow (phones).
    const titleWidth = g.measureText(this.title).width;
    const legendWidth = this.series.reduce((sum, s) => sum + g.measureText(s.name).width + 40, 0);
    const ownLine = left + titleWidth + 16 + legendWidth > w;
    const top = ownLine ? 36 : 22;
    const span = this.grow ? Math.max(20, ...this.series.map((s) => s.values.length)) : this.maxPoints;
    const X = (i) => left + (w - left - right) * i / Math.max(1, span - 1);
    const Y = (v) => top + (h - top - bottom) * (1 - (v - lo) / (hi - lo));
    g.strokeStyle = '#d6d9de';
    g.fillStyle = '#57606a';
    g.textAlign = 'right';
    axis.ticks.forEach((v, t) => {
      g.beginPath(); g.moveTo(left, Math.round(Y(v)) + 0.5); g.lineTo(w - right, Math.round(Y(v)) + 0.5); g.stroke();
      g.fillText(labels[t], left - 6, Y(v) + 4);
    });
    g.textAlign = 'left';
    g.fillText(this.title, left, 14);
    let x = ownLine ? left : left + titleWidth + 16;
    const legendY = ownLine ? 28 : 14;
    for (const s of this.series) {
      g.strokeStyle = s.color;
      g.lineWidth = 2;
      g.beginPath();
      s.values.forEach((v, i) => (i ? g.lineTo(X(i), Y(v)) : g.moveTo(X(i), Y(v))));
      g.stroke();
      g.fillStyle = s.color;
      g.fillRect(x, legendY - 8, 14, 4);
      g.fillStyle = '#1d2128';
      g.fillText(s.name, x + 18, legendY);
      x += g.measureText(s.name).width + 40;
    }
    g.lineWidth = 1;
  }
}

/**
 * The editor's model as its stored session left it: { name, text, positions }, positions being
 * the edited fine positions when they were kept (else null); null without a stored session or when
 * an opened file was too big to keep.
 */
export async function editorModel() {
  const stored = storedModel();
  if (!stored) return null;
  const text = stored.kind === 'file' ? stored.text : await fetchSample(stored.name).catch(() => null);
  if (typeof text !== 'string') return null;
  return { name: stored.name, text, positions: stored.positions };
}

/**
 * An OBJ text opened for a view: { mesh: { positions, faces (triangles), quads (or null) }, mr, quad }.
 * With `quads`, a semi-regular quad OBJ opens as a QuadMultiresMesh (Catmull-Clark levels; faces:
 * its quads split in two for drawing); else, and for any other file, as a triangle MultiresMesh.
 * `positions` (edited ones of the same vertices) replace the file's.
 */
export function openText(mrvol, text, { positions = null, quads = false } = {}) {
  const mesh = mrvol.readObj(text);
  if (positions?.length === mesh.positions.length) mesh.positions = positions;
  if (quads && mesh.polygons > 0) {
    let mr = null;
    try {
      const read = mrvol.readObjQuads(text);
      if (read.positions.length === mesh.positions.length) {
        mr = mrvol.openQuadMesh({ positions: mesh.positions, quads: read.quads });
        if (mr.levels > 0) return { mesh: { positions: mesh.positions, faces: trianglesOfQuads(read.quads), quads: read.quads }, mr, quad: true };
      }
    } catch { /* not a semi-regular quad mesh: triangles */ }
    mr?.delete();
  }
  return { mesh: { ...mesh, quads: null }, mr: mrvol.openMesh(mesh), quad: false };
}

/**
 * The editor's model opened as a MultiresMesh ({ name, mesh, mr, quad }) when it `fits` (mr => bool),
 * else null (no session, unreadable, or not fitting; nothing is left open). With `quads`, a quad
 * model opens as quads (openText).
 */
export async function openEditorModel(mrvol, fits = () => true, { quads = false } = {}) {
  const editor = await editorModel();
  if (!editor) return null;
  let opened = null;
  try {
    opened = openText(mrvol, editor.text, { positions: editor.positions, quads });
    if (fits(opened.mr)) return { name: editor.name, ...opened };
  } catch { /* shown as a sample instead */ }
  opened?.mr.delete();
  return null;
}

/** The view's settings in the address (#learn/levels?l=2&details=colour): a reload or a shared link keeps them. */
export function viewParams() {
  return new URLSearchParams(location.hash.split('?')[1] ?? '');
}

/**
 * Writes the settings of the view at `route` into the address (no history entry, no hashchange);
 * nothing when the address is another view's by now.
 */
export function setViewParams(route, values) {
  const [current] = location.hash.replace(/^#/, '').split('?');
  if (current !== route) return;
  const query = new URLSearchParams(Object.entries(values).filter(([, v]) => v !== null && v !== undefined && v !== false)
    .map(([k, v]) => [k, String(v === true ? 1 : v)])).toString();
  history.replaceState(history.state, '', `#${route}${query ? `?${query}` : ''}`);
}

/** A paragraph list from strings (HTML allowed: they are ours). */
export function explain(box, title, paragraphs) {
  const h = document.createElement('h2');
  h.textContent = title;
  box.append(h);
  for (const text of paragraphs) {
    const p = document.createElement('p');
    p.innerHTML = text;
    box.append(p);
  }
}

/** A labelled control row. */
export function control(box, label, input) {
  const row = document.createElement('label');
  row.className = 'learn-row';
  const span = document.createElement('span');
  span.textContent = label;
  row.append(span, input);
  box.append(row);
  return input;
}

export function select(options, value, testid) {
  const s = document.createElement('select');
  for (const [v, text] of options) {
    const o = document.createElement('option');
    o.value = v;
    o.textContent = text;
    s.append(o);
  }
  s.value = value;
  s.dataset.testid = testid;
  return s;
}

export function button(text, testid, onClick) {
  const b = document.createElement('button');
  b.type = 'button';
  b.textContent = text;
  b.dataset.testid = testid;
  b.addEventListener('click', onClick);
  return b;
}

/** A readout table: rows [label, testid]; returns set(testid, text, value). */
export function readoutTable(box, rows) {
  const table = document.createElement('table');
  const cells = new Map();
  for (const [label, id] of rows) {
    const tr = document.createElement('tr');
    const th = document.createElement('th');
    th.textContent = label;
    const td = document.createElement('td');
    td.dataset.testid = id;
    td.textContent = '–';
    tr.append(th, td);
    table.append(tr);
    cells.set(id, td);
  }
  box.append(table);
  return (id, text, value) => {
    const td = cells.get(id);
    td.textContent = text;
    if (value !== undefined) td.dataset.value = String(value);
  };
}
