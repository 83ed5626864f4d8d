// Drawing for the teaching views: one WebGL canvas split into side-by-side panels (scissor), one
// camera shared by all panels (OrbitControls); the meshes, cages, arrows are mrvol/three's
// (lib/three/objects.mjs, as in the editor); and a 2D volume chart. It draws arrays it is given;
// every number comes from the core through the API.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { SurfaceMesh, CageObject, frameSphere } from '../../lib/three/objects.mjs';
import { storedModel } from '../session.js';
import { fetchSample } from '../models.js';

export { THREE };
export { arrows, bounds, edgesOf } from '../../lib/three/objects.mjs';
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
    this.labelBox.style.gridTemplateColumns = `repeat(${labels.length}, 1fr)`;
    this.requestRender();
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.container;
    if (w === 0 || h === 0) return;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / this.panels.length / h;
    this.camera.updateProjectionMatrix();
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
    const w = this.container.clientWidth, h = this.container.clientHeight;
    const n = this.panels.length;
    this.camera.updateMatrixWorld();
    this.panels.forEach((panel, i) => {
      const x = Math.round(i * w / n), width = Math.round((i + 1) * w / n) - x;
      panel.light.position.copy(this.camera.position).add(new THREE.Vector3(1, 2, 0));
      this.renderer.setViewport(x, 0, width, h);
      this.renderer.setScissor(x, 0, width, h);
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

  /** Camera on a bounding sphere (center [x,y,z], radius), seen from `direction`. */
  frame(center, radius, direction = [0.45, 0.35, 1]) {
    frameSphere(this.camera, { center, radius }, { controls: this.controls, direction, margin: 1.15 });
    this.requestRender();
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
  constructor(container, { title = '', height = 150, maxPoints = 600 } = {}) {
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'learn-chart';
    this.canvas.dataset.testid = 'volume-chart';
    this.canvas.height = height;
    container.append(this.canvas);
    this.title = title;
    this.series = [];
    this.maxPoints = maxPoints;
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
    if (!Number.isFinite(lo)) return;
    const pad = Math.max((hi - lo) * 0.1, Math.abs(hi) * 1e-3, 1e-9);
    lo -= pad; hi += pad;
    const left = 70, right = 10, top = 22, bottom = 8;
    const X = (i) => left + (w - left - right) * i / Math.max(1, this.maxPoints - 1);
    const Y = (v) => top + (h - top - bottom) * (1 - (v - lo) / (hi - lo));
    g.strokeStyle = '#d6d9de';
    g.fillStyle = '#57606a';
    g.font = '11px system-ui, sans-serif';
    for (let t = 0; t <= 4; t++) {
      const v = lo + (hi - lo) * t / 4;
      g.beginPath(); g.moveTo(left, Y(v)); g.lineTo(w - right, Y(v)); g.stroke();
      g.fillText(v.toPrecision(5), 4, Y(v) + 4);
    }
    g.fillText(this.title, left, 14);
    let x = left + g.measureText(this.title).width + 16;
    for (const s of this.series) {
      g.strokeStyle = s.color;
      g.lineWidth = 2;
      g.beginPath();
      s.values.forEach((v, i) => (i ? g.lineTo(X(i), Y(v)) : g.moveTo(X(i), Y(v))));
      g.stroke();
      g.fillStyle = s.color;
      g.fillRect(x, 6, 14, 4);
      g.fillStyle = '#1d2128';
      g.fillText(s.name, x + 18, 14);
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
 * The editor's model opened as a MultiresMesh ({ name, mesh, mr }) when it `fits` (mr => bool),
 * else null (no session, unreadable, or not fitting; nothing is left open).
 */
export async function openEditorModel(mrvol, fits = () => true) {
  const editor = await editorModel();
  if (!editor) return null;
  let mr = null;
  try {
    const mesh = mrvol.readObj(editor.text);
    if (editor.positions?.length === mesh.positions.length) mesh.positions = editor.positions;
    mr = mrvol.openMesh(mesh);
    if (fits(mr)) return { name: editor.name, mesh, mr };
  } catch { /* shown as a sample instead */ }
  mr?.delete();
  return null;
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
