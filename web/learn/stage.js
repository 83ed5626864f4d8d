// Drawing for the teaching views: one WebGL canvas split into side-by-side panels (scissor), one
// camera shared by all panels (OrbitControls), meshes, wire cages, arrows; and a 2D volume chart.
// It draws arrays it is given; every number comes from the core through the API.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { loadSession, decodeFloat64 } from '../session.js';

export { THREE };

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
    const vertical = THREE.MathUtils.degToRad(this.camera.fov / 2);
    const horizontal = Math.atan(Math.tan(vertical) * this.camera.aspect);
    const distance = radius / Math.sin(Math.min(vertical, horizontal)) * 1.15;
    const d = new THREE.Vector3(...direction).normalize();
    this.controls.target.set(...center);
    this.camera.position.set(...center).addScaledVector(d, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
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

/** Bounding sphere of flat positions: { center, radius }. */
export function bounds(positions) {
  const box = new THREE.Box3();
  const p = new THREE.Vector3();
  for (let i = 0; i < positions.length; i += 3) box.expandByPoint(p.fromArray(positions, i));
  const center = box.getCenter(new THREE.Vector3());
  let r2 = 0;
  for (let i = 0; i < positions.length; i += 3) r2 = Math.max(r2, center.distanceToSquared(p.fromArray(positions, i)));
  return { center: center.toArray(), radius: Math.max(Math.sqrt(r2), 1e-6) };
}

/** A shaded surface; colors (3 per vertex, 0..1) optional. update() takes new positions. */
export function surface(positions, faces, { color = 0xc9b8a0, colors = null, flat = true, opacity = 1 } = {}) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
  geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(faces), 1));
  if (colors) geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(colors), 3));
  const material = new THREE.MeshStandardMaterial({
    color: colors ? 0xffffff : color, vertexColors: !!colors, roughness: 0.65, flatShading: flat, side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1, transparent: opacity < 1, opacity,
  });
  const mesh = new THREE.Mesh(geometry, material);
  mesh.update = (p) => {
    geometry.getAttribute('position').array.set(p);
    geometry.getAttribute('position').needsUpdate = true;
    if (!flat) geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
  };
  mesh.setColors = (c) => {
    if (!geometry.getAttribute('color')) {
      geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(c), 3));
      material.vertexColors = true;
      material.color.set(0xffffff);
      material.needsUpdate = true;
    } else {
      geometry.getAttribute('color').array.set(c);
      geometry.getAttribute('color').needsUpdate = true;
    }
  };
  mesh.clearColors = () => {
    if (!geometry.getAttribute('color')) return;
    geometry.deleteAttribute('color');
    material.vertexColors = false;
    material.color.set(color);
    material.needsUpdate = true;
  };
  if (!flat) geometry.computeVertexNormals();
  return mesh;
}

/** The unique edges of triangles (pairs of indices into the positions given to wire()). */
export function edgesOf(faces, index = null) {
  const seen = new Set();
  const out = [];
  for (let f = 0; f < faces.length; f += 3)
    for (let k = 0; k < 3; k++) {
      let a = faces[f + k], b = faces[f + (k + 1) % 3];
      if (index) { a = index.get(a); b = index.get(b); }
      const key = a < b ? `${a},${b}` : `${b},${a}`;
      if (seen.has(key)) continue;
      seen.add(key);
      out.push(a, b);
    }
  return out;
}

/** Line segments between points (positions) along index pairs, with handle dots. */
export function wire(positions, edges, { color = 0x1f6feb, points = true, opacity = 1 } = {}) {
  const group = new THREE.Group();
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
  geometry.setIndex(edges);
  const lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color, transparent: opacity < 1, opacity }));
  const hidden = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color, transparent: true, opacity: 0.2 * opacity, depthTest: false }));
  group.add(lines, hidden);
  if (points) group.add(new THREE.Points(geometry, new THREE.PointsMaterial({ color, size: 7, sizeAttenuation: false, depthTest: false })));
  for (const o of group.children) o.frustumCulled = false;
  group.update = (p) => {
    geometry.getAttribute('position').array.set(p);
    geometry.getAttribute('position').needsUpdate = true;
  };
  return group;
}

/** Arrows as line segments from points `from` along vectors `vectors` (same length, flat) scaled by `scale`. */
export function arrows(from, vectors, { color = 0xd1242f, scale = 1 } = {}) {
  const count = from.length / 3;
  const p = new Float32Array(count * 6 * 3);
  const a = new THREE.Vector3(), v = new THREE.Vector3(), side = new THREE.Vector3(), up = new THREE.Vector3();
  let n = 0;
  for (let i = 0; i < count; i++) {
    a.fromArray(from, 3 * i);
    v.fromArray(vectors, 3 * i).multiplyScalar(scale);
    const length = v.length();
    if (length < 1e-12) continue;
    const tip = a.clone().add(v);
    side.crossVectors(v, Math.abs(v.y) < 0.9 * length ? up.set(0, 1, 0) : up.set(1, 0, 0)).setLength(0.12 * length);
    const back = tip.clone().addScaledVector(v, -0.25);
    for (const [s, t] of [[a, tip], [tip, back.clone().add(side)], [tip, back.clone().sub(side)]]) {
      s.toArray(p, 3 * n++);
      t.toArray(p, 3 * n++);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(p.slice(0, 3 * n), 3));
  const lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color }));
  lines.frustumCulled = false;
  return lines;
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

/** Fetches a sample model's OBJ text; null if there is none of that name. */
export async function fetchModel(name) {
  const response = await fetch(`${import.meta.env.BASE_URL}models/${encodeURIComponent(name)}.obj`);
  if (!response.ok) return null;
  return response.text();
}

/**
 * The editor's model as its stored session left it (web/session.js): { name, text, positions },
 * positions being the edited fine positions when they were kept (else null); null without a
 * session or when an opened file was too big to keep.
 */
export async function editorModel() {
  const session = loadSession();
  if (!session) return null;
  const { kind, name, text } = session.model;
  const source = kind === 'file' ? text ?? null : await fetchModel(name);
  if (typeof source !== 'string') return null;
  let positions = null;
  try {
    positions = session.positions ? decodeFloat64(session.positions) : null;
  } catch { /* a damaged session: the file's own positions */ }
  return { name, text: source, positions };
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
