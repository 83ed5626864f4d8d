// #learn/lifting: one level of the lifting scheme (Figure 3, paper section 2) seen from one vertex.
// Synthesis: which level-l vertices one coefficient c^{l-1}_v (even v) or d^{l-1}_v (odd v) writes,
// with the weights, i.e. one column of [S^l C^l]. Analysis: which coefficients of level l-1 read one
// vertex c^l_w, one column of [A^l; B^l]. Both are measured through the API, exactly: a unit
// coefficient is synthesized from level l-1 and analysed back to level l (or the reverse). The API
// has no access to the single phases U, P_o, N, P_e yet, so the view shows their composite.
import { sampleModels } from 'virtual:mrvol-models';
import { Stage, THREE, surface, wire, edgesOf, bounds, fetchModel, explain, control, select, button, readoutTable } from './stage.js';

const POSITIVE = new THREE.Color(0xe36209), NEGATIVE = new THREE.Color(0x6f42c1), IDLE = new THREE.Color(0x6e7781);

export async function mount({ mrvol, layout, el, stale }) {
  explain(layout.text, 'Lifting: one level, one vertex (Figure 3, section 2)', [
    'One synthesis step (c<sup>l−1</sup>, d<sup>l−1</sup>) → c<sup>l</sup> of the Loop-based scheme runs four phases in place ' +
      '(section 2, Figure 3): <b>U</b> updates the even (old) vertices from the details of the odd (new) ones ' +
      '(weights α/v, β/v), <b>P<sub>o</sub></b> predicts the odd vertices from the even ones (3/8, 3/8, 1/8, 1/8), ' +
      '<b>N</b> scales the even vertices by 8/5 (3/8 + cos(2π/v)/4)², <b>P<sub>e</sub></b> moves the even vertices by μ times ' +
      'their odd neighbours. Analysis runs the inverse phases in reverse order.',
    'Pick a vertex of M<sup>l</sup> (click it, or type its index). <b>Synthesis</b>: the coloured vertices are those the ' +
      'coefficient of the picked vertex writes at level l (even: c<sup>l−1</sup>, odd: d<sup>l−1</sup>), orange positive, ' +
      'purple negative, with the weights listed: one column of [S<sup>l</sup> C<sup>l</sup>]. <b>Analysis</b>: the ' +
      'coefficients of level l−1 that read the picked vertex: one column of [A<sup>l</sup>; B<sup>l</sup>].',
    'These are the four phases composed, measured through the API (a unit coefficient synthesized and analysed back). ' +
      'Playing the phases one by one needs an API that exposes the lifting steps, which the core does not offer yet.',
  ]);
  const name = sampleModels.includes('spiky-ball') ? 'spiky-ball' : sampleModels[0];
  const text = await fetchModel(name);
  if (stale()) return null;
  const mesh = mrvol.readObj(text);
  const mr = mrvol.openMesh(mesh);
  const depths = mr.depths();
  const N = mr.vertexCount, n = mr.levels;
  if (n < 1) throw new Error(`${name} has no subdivision level`);
  const s = { level: 1, scheme: 'loop', mode: 'synthesis', vertex: 0 };
  const levelSelect = control(layout.controls, 'level l', select([...Array(n).keys()].map((k) => [String(k + 1), `${k + 1}: M${k} → M${k + 1}`]), '1', 'lifting-level'));
  const schemeSelect = control(layout.controls, 'scheme', select(['loop', 'butterfly', 'linear'].map((k) => [k, k]), s.scheme, 'lifting-scheme'));
  const modeSelect = control(layout.controls, 'direction', select([['synthesis', 'synthesis: what it writes'], ['analysis', 'analysis: what reads it']], s.mode, 'lifting-mode'));
  const vertexInput = document.createElement('input');
  vertexInput.type = 'number';
  vertexInput.min = 0;
  vertexInput.value = 0;
  vertexInput.dataset.testid = 'lifting-vertex';
  control(layout.controls, 'vertex', vertexInput);
  const row = el('div', { class: 'learn-row' });
  layout.controls.append(row);
  const set = readoutTable(layout.readouts, [['picked', 'lifting-picked'], ['touched', 'lifting-touched']]);
  const weightsBox = el('div', { testid: 'lifting-weights' });
  layout.readouts.append(weightsBox);

  const stage = new Stage(layout.stage, ['']);
  const b = bounds(mesh.positions);
  stage.frame(b.center, b.radius);
  let current = null; // { vertices (caller indices of M^l), index Map, points, colors }
  let result = null;

  function unit(vertex) {
    const a = new Float64Array(3 * N);
    a[3 * vertex] = 1;
    return a;
  }

  function compute() {
    const l = s.level, v = s.vertex;
    const options = (level) => ({ level, scheme: s.scheme });
    let out;
    if (s.mode === 'synthesis') out = mr.analyze(mr.synthesize(unit(v), options(l - 1)), options(l));
    else out = mr.analyze(mr.synthesize(unit(v), options(l)), options(l - 1));
    const touched = [];
    for (let u = 0; u < N; u++) if (depths[u] <= l && Math.abs(out[3 * u]) > 1e-12) touched.push({ vertex: u, weight: out[3 * u], odd: depths[u] === l });
    touched.sort((x, y) => Math.abs(y.weight) - Math.abs(x.weight));
    return touched;
  }

  function buildLevel() {
    const l = s.level;
    const scene = stage.panels[0].scene;
    scene.traverse((o) => o.geometry?.dispose());
    scene.children.filter((o) => !o.isLight).forEach((o) => scene.remove(o));
    const coarse = mr.analyze(mesh.positions, { level: l, scheme: s.scheme });
    const vertices = [];
    for (let u = 0; u < N; u++) if (depths[u] <= l) vertices.push(u);
    const index = new Map(vertices.map((u, k) => [u, k]));
    const positions = new Float64Array(3 * vertices.length);
    vertices.forEach((u, k) => positions.set(coarse.subarray(3 * u, 3 * u + 3), 3 * k));
    const faces = Uint32Array.from(mr.levelFaces(l), (u) => index.get(u));
    scene.add(surface(positions, faces, { color: 0xe8e2d8 }));
    scene.add(wire(positions, edgesOf(faces), { color: 0x8c959f, points: false }));
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3 * vertices.length), 3));
    geometry.setAttribute('size', new THREE.BufferAttribute(new Float32Array(vertices.length), 1));
    const points = new THREE.Points(geometry, new THREE.PointsMaterial({ size: 14, sizeAttenuation: false, vertexColors: true, depthTest: true }));
    scene.add(points);
    current = { vertices, index, points, positions };
    vertexInput.max = N - 1;
    stage.panels[0].tag.textContent = `M${sup(l)}: ${vertices.length} vertices (${vertices.filter((u) => depths[u] === l).length} odd)`;
  }

  function show() {
    if (depths[s.vertex] > s.level) s.vertex = 0;
    vertexInput.value = s.vertex;
    const touched = compute();
    const colors = current.points.geometry.getAttribute('color');
    current.vertices.forEach((u, k) => colors.setXYZ(k, IDLE.r, IDLE.g, IDLE.b));
    const max = Math.max(...touched.map((t) => Math.abs(t.weight)), 1e-300);
    for (const t of touched) {
      const c = (t.weight > 0 ? POSITIVE : NEGATIVE).clone().lerp(new THREE.Color(0xffffff), 0.55 * (1 - Math.sqrt(Math.abs(t.weight) / max)));
      const k = current.index.get(t.vertex);
      colors.setXYZ(k, c.r, c.g, c.b);
    }
    const picked = current.index.get(s.vertex);
    colors.setXYZ(picked, 0, 0.6, 0.2);
    colors.needsUpdate = true;
    const odd = depths[s.vertex] === s.level;
    const what = s.mode === 'synthesis'
      ? `${odd ? 'd' : 'c'}${sup(s.level - 1)}${sub(s.vertex)} → c${sup(s.level)}`
      : `c${sup(s.level)}${sub(s.vertex)} → c${sup(s.level - 1)}, d${sup(s.level - 1)}`;
    set('lifting-picked', `vertex ${s.vertex} (${odd ? 'odd' : 'even'}, depth ${depths[s.vertex]}): ${what}`, s.vertex);
    set('lifting-touched', `${touched.length} coefficients`, touched.length);
    const table = el('table', { class: 'learn-block-table' });
    table.append(el('tr', {}, el('th', { text: 'vertex' }), el('th', { text: 'kind' }), el('th', { text: 'weight' })));
    for (const t of touched.slice(0, 30)) {
      const kind = s.mode === 'synthesis' ? `c${sup(s.level)}` : t.odd ? `d${sup(s.level - 1)}` : `c${sup(s.level - 1)}`;
      table.append(el('tr', {}, el('td', { text: String(t.vertex) }), el('td', { text: `${kind} (${t.odd ? 'odd' : 'even'})` }), el('td', { text: t.weight.toFixed(6) })));
    }
    weightsBox.replaceChildren(table);
    if (touched.length > 30) weightsBox.append(el('div', { class: 'muted', text: `… and ${touched.length - 30} smaller` }));
    result = { level: s.level, scheme: s.scheme, mode: s.mode, vertex: s.vertex, odd, touched: touched.length, weights: touched.slice(0, 60) };
    stage.requestRender();
  }

  /** Picks a vertex of M^l; focus: turn the camera to face it. */
  function pick(vertex, focus = true) {
    if (!Number.isInteger(vertex) || vertex < 0 || vertex >= N || depths[vertex] > s.level) return false;
    s.vertex = vertex;
    if (focus) {
      const k = current.index.get(vertex);
      const direction = [0, 1, 2].map((i) => current.positions[3 * k + i] - b.center[i]);
      if (Math.hypot(...direction) > 1e-9) stage.frame(b.center, b.radius, direction.map((d, i) => d + [0.2, 0.3, 0][i] * Math.hypot(...direction)));
    }
    show();
    return true;
  }

  function nextOf(odd) {
    const wanted = (u) => (odd ? depths[u] === s.level : depths[u] < s.level);
    for (let k = 1; k <= N; k++) {
      const u = (s.vertex + k) % N;
      if (wanted(u)) return pick(u);
    }
    return false;
  }
  row.append(button('next even', 'lifting-next-even', () => nextOf(false)), button('next odd', 'lifting-next-odd', () => nextOf(true)));

  // Click on a vertex of M^l.
  const raycaster = new THREE.Raycaster();
  raycaster.params.Points.threshold = 0.05 * b.radius;
  const canvas = stage.renderer.domElement;
  let down = null;
  canvas.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
  canvas.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    const rect = canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1, 1 - (e.clientY - rect.top) / rect.height * 2);
    stage.camera.updateMatrixWorld();
    raycaster.setFromCamera(ndc, stage.camera);
    const hits = raycaster.intersectObject(current.points);
    if (hits.length) pick(current.vertices[hits[0].index], false);
  });

  levelSelect.addEventListener('change', () => { s.level = Number(levelSelect.value); buildLevel(); show(); });
  schemeSelect.addEventListener('change', () => { s.scheme = schemeSelect.value; buildLevel(); show(); });
  modeSelect.addEventListener('change', () => { s.mode = modeSelect.value; show(); });
  vertexInput.addEventListener('change', () => { if (!pick(Number(vertexInput.value))) vertexInput.value = s.vertex; });
  buildLevel();
  show();
  return {
    dispose() {
      stage.dispose();
      mr.delete();
    },
    actions: {
      pick,
      /** Screen position (viewport CSS pixels) of a vertex of M^l, for click tests. */
      screenOf(vertex) {
        const k = current.index.get(vertex);
        stage.camera.updateMatrixWorld(); // frame() moved it; the next render has not run yet
        const p = new THREE.Vector3().fromArray(current.positions, 3 * k).project(stage.camera);
        const rect = canvas.getBoundingClientRect();
        return [rect.left + (p.x + 1) / 2 * rect.width, rect.top + (1 - p.y) / 2 * rect.height];
      },
    },
    debug: () => result,
  };
}

const SUP = '⁰¹²³⁴⁵⁶⁷⁸⁹', SUB = '₀₁₂₃₄₅₆₇₈₉';
function sup(n) {
  return String(n).replace(/\d/g, (d) => SUP[d]);
}
function sub(n) {
  return String(n).replace(/\d/g, (d) => SUB[d]);
}
