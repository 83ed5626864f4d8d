// #learn/lifting: one level of the lifting scheme (Figure 3, paper section 2) played phase by phase
// around one vertex. The phases are the core's lifting steps of level l (mr.liftingSteps: targets,
// sources, weights in the mesh's vertex indices); the view highlights, for the picked vertex's
// neighbourhood in M^l, the vertices a phase writes (its targets) and reads (their sources), and
// lists the weights. Alongside, a unit coefficient at the picked vertex goes through the phases,
// run by the core (mr.synthesizeSteps / mr.analyzeSteps with steps = k): what it has reached.
// Analysis plays the inverse phases in reverse order; "transposed" plays the transposed phases in
// reverse order (paper Figure 5, section 3.2: each mask applied outwards, mr.transposeSteps), as
// the volume tensors of coarser levels are computed. A quad model (quad-critter, or the editor's
// quad mesh) plays the Catmull-Clark steps of docs/catmull-clark.md: face points, edge points, the
// valence-3 layers, the vertex rule (QuadMultiresMesh.liftingSteps, applied by lib/quad-steps.mjs).
import { sampleModels } from 'virtual:mrvol-models';
import { trianglesOfQuads } from '../../lib/three/edges.mjs';
import { SCHEME_WORDS, phaseText, glossaryKeys, phaseLabel } from './lifting-words.js';
import { Stage, THREE, surface, wire, edgesOf, quadEdgesOf, bounds, fetchSample, openEditorModel, openText, explain, control, select, button, readoutTable, viewParams, setViewParams } from './stage.js';

const WRITTEN = new THREE.Color(0xe36209), READ = new THREE.Color(0x1f6feb), PICKED = new THREE.Color(0x1a7f37);
const IDLE = new THREE.Color(0x6e7781), REACHED = new THREE.Color(0xb392f0);
const POSITIVE_LINE = new THREE.Color(0xe36209), NEGATIVE_LINE = new THREE.Color(0x6f42c1);

const TRIANGLE_SCHEMES = ['loop', 'butterfly', 'linear'];
const QUAD_MODEL = 'quad-critter';
const PLAY_MS = 900;

// The words every scheme shares (the scheme's own come from lifting-words.js).
const SHARED_TEXT = [
  'Analysis runs the inverse phases in reverse order: each subtracts what its phase added (or divides by its factor), so it ' +
    'retraces synthesis exactly.',
  'Pick a vertex of M<sup>l</sup> (click it, or type its index) and <b>step</b> or <b>play</b> the phases. In each phase the ' +
    'vertices of its neighbourhood that the phase <span style="color:#e36209">writes</span> are orange, the ones their masks ' +
    '<span style="color:#1f6feb">read</span> are blue, with a line per weight (orange positive, purple negative) and the ' +
    'weights listed; the picked vertex is green.',
  'The phases are the core’s lifting steps, run by the core: a unit coefficient at the picked vertex (c<sup>l−1</sup> or ' +
    'd<sup>l−1</sup> in synthesis, c<sup>l</sup> in analysis) goes through the first k phases; the vertices it has reached are ' +
    'lilac. After the last phase they are one column of [S<sup>l</sup> C<sup>l</sup>] (synthesis) or [A<sup>l</sup>; B<sup>l</sup>] (analysis).',
  '<b>Transposed</b> (section 3.2, Figure 5): θ<sup>l−1</sup> comes from θ<sup>l</sup> through the transposed synthesis, ' +
    'which the paper runs as the same masks applied <i>outwards</i>, in reverse order: a mask instantiated at a vertex does ' +
    'not read its neighbours, it adds its own value times the same weights to them (x<sub>s</sub> += w x<sub>t</sub>). ' +
    'In this direction the picked vertex and its neighbours push (blue, “reads”) to the vertices their inward masks would ' +
    'read (orange, “writes”); a unit covector at the picked vertex spreads to one row of [S<sup>l</sup> C<sup>l</sup>].',
  'The mesh is the editor\'s model as you left it, when it has a subdivision level; else the spiky ball. The model list offers the quad-critter too.',
];

export async function mount({ mrvol, layout, el, stale }) {
  // The editor's model as it was left (edits included) when it has a level to play, else a sample.
  const fits = (m) => m.levels >= 1 && m.vertexCount <= 200_000 && !(m.lowestLevel > 0);
  let opened = await openEditorModel(mrvol, fits, { quads: true });
  if (stale()) {
    opened?.mr.delete();
    return null;
  }
  const samples = [sampleModels.includes('spiky-ball') ? 'spiky-ball' : sampleModels[0], ...(sampleModels.includes(QUAD_MODEL) ? [QUAD_MODEL] : [])];
  const modelOptions = [...(opened ? [[EDITOR, `editor: ${opened.name}`]] : []), ...samples.map((m) => [m, m])];
  const editorOpened = opened;
  // The model on screen; `mesh`: { positions, faces (triangles), quads (a quad model) }.
  let name, mesh, mr, quad, depths, N, n;
  async function load(choice) {
    if (choice === EDITOR) opened = editorOpened;
    else {
      const text = await fetchSample(choice);
      if (stale()) return false;
      opened = { name: choice, ...openText(mrvol, text, { quads: true }) };
    }
    if (mr && mr !== opened.mr && mr !== editorOpened?.mr) mr.delete();
    ({ name, mesh, mr, quad } = opened);
    depths = mr.depths();
    N = mr.vertexCount;
    n = mr.levels;
    if (n < 1) throw new Error(`${name} has no subdivision level`);
    return true;
  }
  // Settings from the address (a reload or a shared link), checked against what there is.
  const asked = viewParams();
  const firstModel = modelOptions.some(([value]) => value === asked.get('model')) ? asked.get('model') : modelOptions[0][0];
  if (!(await load(firstModel))) return null;
  const s = { level: 1, scheme: quad ? 'catmull-clark' : 'loop', mode: 'synthesis', vertex: 0, phase: 0 };
  if (/^\d+$/.test(asked.get('l') ?? '')) s.level = Math.max(1, Number(asked.get('l')));
  if (['loop', 'butterfly', 'linear', 'catmull-clark'].includes(asked.get('scheme'))) s.scheme = asked.get('scheme');
  if (['synthesis', 'analysis', 'transposed'].includes(asked.get('mode'))) s.mode = asked.get('mode');
  const askedVertex = /^\d+$/.test(asked.get('vertex') ?? '') ? Number(asked.get('vertex')) : 0;
  const askedPhase = /^\d+$/.test(asked.get('phase') ?? '') ? Number(asked.get('phase')) : 0;
  const modelSelect = control(layout.controls, 'model', select(modelOptions, firstModel, 'lifting-model'));
  const levelSelect = control(layout.controls, 'level l', select([], '1', 'lifting-level'));
  const schemeSelect = control(layout.controls, 'scheme', select([], s.scheme, 'lifting-scheme'));
  /** The level and scheme selects for the model on screen (a quad model: Catmull-Clark alone). */
  function fillSelects() {
    levelSelect.replaceChildren(...[...Array(n).keys()].map((k) => new Option(`${k + 1}: M${sup(k)} → M${sup(k + 1)}`, String(k + 1))));
    s.level = Math.min(s.level, n);
    levelSelect.value = String(s.level);
    const schemes = quad ? ['catmull-clark'] : TRIANGLE_SCHEMES;
    if (!schemes.includes(s.scheme)) s.scheme = schemes[0];
    schemeSelect.replaceChildren(...schemes.map((k) => new Option(k, k)));
    schemeSelect.value = s.scheme;
  }
  fillSelects();
  const modeSelect = control(layout.controls, 'direction', select([['synthesis', 'synthesis'], ['analysis', 'analysis (inverse, reversed)'], ['transposed', 'transposed (Figure 5)']], s.mode, 'lifting-mode'));
  const vertexInput = document.createElement('input');
  vertexInput.type = 'number';
  vertexInput.min = 0;
  vertexInput.value = 0;
  vertexInput.dataset.testid = 'lifting-vertex';
  control(layout.controls, 'vertex', vertexInput);
  const pickRow = el('div', { class: 'learn-row' });
  const phaseRow = el('div', { class: 'learn-row' });
  // What the point colours mean.
  const legend = el('div', { class: 'learn-legend learn-points-legend', testid: 'lifting-legend' });
  for (const [color, text] of [[PICKED, 'picked'], [WRITTEN, 'written'], [READ, 'read'], [REACHED, 'reached'], [IDLE, 'other']])
    legend.append(el('span', {}, el('i', { style: `background:#${color.getHexString()};border-radius:50%` }), text));
  layout.controls.append(pickRow, phaseRow, legend);
  const set = readoutTable(layout.readouts, [
    ['picked', 'lifting-picked'], ['phase', 'lifting-phase'], ['writes', 'lifting-written'], ['reads', 'lifting-read'],
    ['reached', 'lifting-touched'],
  ]);
  const weightsBox = el('div', { testid: 'lifting-weights' });
  layout.readouts.append(weightsBox);

  const stage = new Stage(layout.stage, ['']);
  let b = bounds(mesh.positions);
  stage.frame(b.center, b.radius);
  // The level on screen: { vertices (indices of M^l), index Map, positions, points, lines, ring, steps }.
  let current = null;
  let result = null;
  let timer = null;

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
    // M^l: triangles, or quads (drawn as two triangles each, wired along their sides)
    const levelFaces = quad ? mr.levelQuads(l) : mr.levelFaces(l);
    const corners = quad ? 4 : 3;
    const faces = Uint32Array.from(levelFaces, (u) => index.get(u));
    const body = surface(positions, quad ? trianglesOfQuads(faces) : faces, { color: 0xe8e2d8 });
    scene.add(body);
    scene.add(wire(positions, quad ? quadEdgesOf(faces) : edgesOf(faces), { color: 0x8c959f, points: false }));
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3 * vertices.length), 3));
    // 14 px dots on a coarse M^l; smaller as it fills (M^3 of a quad model: 3458 would tile the surface).
    const dot = Math.max(5, Math.min(14, Math.round(14 * Math.sqrt(400 / vertices.length))));
    const points = new THREE.Points(geometry, new THREE.PointsMaterial({ size: dot, sizeAttenuation: false, vertexColors: true, depthTest: true }));
    scene.add(points);
    const lines = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ vertexColors: true, depthTest: false, transparent: true, opacity: 0.9 }));
    lines.renderOrder = 2;
    scene.add(lines);
    // Neighbours in M^l (connectivity only, for choosing which rows of a phase to show): along the
    // triangles' edges; for quads every corner of the quads around (a face point and its quad's corners).
    const ring = new Map(vertices.map((u) => [u, new Set()]));
    for (let f = 0; f < levelFaces.length; f += corners)
      for (let e = 0; e < corners; e++)
        for (let g = 1; g < (quad ? corners : 2); g++) {
          const a = levelFaces[f + e], c = levelFaces[f + (e + g) % corners];
          ring.get(a).add(c);
          ring.get(c).add(a);
        }
    // The core's steps of level l, with each step's row of a target vertex.
    const steps = mr.liftingSteps({ level: l, scheme: s.scheme }).map((step) => ({ ...step, rowOf: new Map([...step.targets].map((t, r) => [t, r])) }));
    current = { vertices, index, positions, points, lines, ring, steps, body };
    vertexInput.max = N - 1;
    stage.panels[0].tag.textContent = `M${sup(l)}: ${vertices.length} vertices (${vertices.filter((u) => depths[u] === l).length} odd)`;
    showWords();
  }

  /** The text, the phase glossary and the "next" buttons in the words of the scheme played. */
  function showWords() {
    const words = SCHEME_WORDS[s.scheme];
    layout.text.replaceChildren();
    explain(layout.text, words.title, [words.intro, ...SHARED_TEXT.slice(0, 1)]);
    const glossary = el('dl', { class: 'learn-glossary', testid: 'lifting-glossary' });
    for (const key of glossaryKeys(current.steps.map((step) => step.name))) {
      const term = el('dt');
      term.innerHTML = phaseLabel(key);
      glossary.append(term, el('dd', { text: phaseText(s.scheme, key) }));
    }
    layout.text.append(glossary);
    for (const text of SHARED_TEXT.slice(1)) {
      const paragraph = el('p');
      paragraph.innerHTML = text;
      layout.text.append(paragraph);
    }
    nextEven.textContent = `next ${words.even}`;
    nextOdd.textContent = `next ${words.odd}`;
  }

  const phaseCount = () => current.steps.length;
  // A vertex of M^l: even or odd; on a quad mesh a face point (P_f writes it), an edge point (P_e) or an old vertex.
  const written = (name, u) => current.steps.find((step) => step.name === name)?.rowOf.has(u);
  const kindOf = (u) => (!quad ? (depths[u] === s.level ? 'odd' : 'even')
    : depths[u] < s.level ? 'old vertex, even' : written('P_f', u) ? 'face point, odd' : written('P_e', u) ? 'edge point, odd' : 'odd');
  // The step run by phase k (1-based) in the current direction, and whether it runs inverted.
  const stepOfPhase = (k) => (s.mode === 'synthesis' ? current.steps[k - 1] : current.steps[phaseCount() - k]);
  const phaseName = (k) => (k === 0 ? 'start' : s.mode === 'synthesis' ? stepOfPhase(k).name
    : `${stepOfPhase(k).name}${s.mode === 'analysis' ? '⁻¹' : 'ᵀ'}`);

  /** Rows of phase k whose target is the picked vertex or one of its neighbours in M^l. */
  function maskAround(k) {
    if (k === 0) return { written: [], read: [], weights: [] };
    const step = stepOfPhase(k);
    const inverse = s.mode === 'analysis', outwards = s.mode === 'transposed';
    const written = new Set(), read = new Set(), weights = [];
    for (const t of [s.vertex, ...current.ring.get(s.vertex)]) {
      const r = step.rowOf.get(t);
      if (r === undefined) continue;
      if (step.scaling) {
        written.add(t);
        weights.push({ target: t, source: null, weight: inverse ? 1 / step.weights[r] : step.weights[r], scaling: true });
        continue;
      }
      // Inwards, row t reads its sources into t; outwards (transposed), t adds itself to them.
      (outwards ? read : written).add(t);
      for (let q = step.offsets[r]; q < step.offsets[r + 1]; q++) {
        const u = step.sources[q];
        (outwards ? written : read).add(u);
        weights.push(outwards ? { target: u, source: t, weight: step.weights[q], scaling: false }
          : { target: t, source: u, weight: inverse ? -step.weights[q] : step.weights[q], scaling: false });
      }
    }
    return { written: [...written], read: [...read], weights };
  }

  /** The unit coefficient at the picked vertex after k phases, run by the core. */
  function unitAfter(k) {
    const unit = new Float64Array(3 * N);
    unit[3 * s.vertex] = 1;
    const options = { level: s.level, scheme: s.scheme, steps: k };
    const x = s.mode === 'synthesis' ? mr.synthesizeSteps(unit, options)
      : s.mode === 'analysis' ? mr.analyzeSteps(unit, options) : mr.transposeSteps(unit, options);
    const reached = [];
    for (let u = 0; u < N; u++) if (x[3 * u] !== 0) reached.push({ vertex: u, value: x[3 * u] });
    reached.sort((p, q) => Math.abs(q.value) - Math.abs(p.value));
    return reached;
  }

  function show() {
    if (depths[s.vertex] > s.level) s.vertex = 0;
    vertexInput.value = s.vertex;
    setViewParams('learn/lifting', { model: modelSelect.value, l: s.level, scheme: s.scheme, mode: s.mode, vertex: s.vertex, phase: s.phase });
    const k = s.phase;
    const mask = maskAround(k);
    const reached = unitAfter(k);
    // Points: reached (lilac) under read (blue) under written (orange) under picked (green).
    const colors = current.points.geometry.getAttribute('color');
    const paint = (u, c) => colors.setXYZ(current.index.get(u), c.r, c.g, c.b);
    current.vertices.forEach((u) => paint(u, IDLE));
    for (const r of reached) paint(r.vertex, REACHED);
    for (const u of mask.read) paint(u, READ);
    for (const u of mask.written) paint(u, WRITTEN);
    paint(s.vertex, PICKED);
    colors.needsUpdate = true;
    // One line per weight, from the source read to the target written.
    const segment = [], segmentColors = [];
    for (const w of mask.weights) {
      if (w.scaling) continue;
      for (const u of [w.source, w.target]) segment.push(...current.positions.subarray(3 * current.index.get(u), 3 * current.index.get(u) + 3));
      const c = w.weight >= 0 ? POSITIVE_LINE : NEGATIVE_LINE;
      segmentColors.push(c.r, c.g, c.b, c.r, c.g, c.b);
    }
    current.lines.geometry.dispose();
    current.lines.geometry = new THREE.BufferGeometry();
    current.lines.geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(segment), 3));
    current.lines.geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(segmentColors), 3));

    const odd = depths[s.vertex] === s.level;
    const what = s.mode === 'synthesis'
      ? `${odd ? 'd' : 'c'}${sup(s.level - 1)}${sub(s.vertex)} → c${sup(s.level)}`
      : s.mode === 'analysis' ? `c${sup(s.level)}${sub(s.vertex)} → c${sup(s.level - 1)}, d${sup(s.level - 1)}`
        : `covector at c${sup(s.level)}${sub(s.vertex)} → (c${sup(s.level - 1)}, d${sup(s.level - 1)}), outwards`;
    set('lifting-picked', `vertex ${s.vertex} (${kindOf(s.vertex)}, depth ${depths[s.vertex]}): ${what}`, s.vertex);
    const phase = phaseName(k);
    const about = k === 0 ? 'before the first phase'
      : (s.mode === 'analysis' ? 'undoes ' : s.mode === 'transposed' ? 'applied outwards: ' : '') + phaseText(s.scheme, stepOfPhase(k).name);
    set('lifting-phase', `${k} / ${phaseCount()}: ${phase} — ${about}`, k);
    set('lifting-written', `${mask.written.length} vertices near the picked one`, mask.written.length);
    set('lifting-read', `${mask.read.length} vertices`, mask.read.length);
    set('lifting-touched', `${reached.length} ${reached.length === 1 ? 'vertex carries' : 'vertices carry'} the unit coefficient`, reached.length);
    const table = el('table', { class: 'learn-block-table' });
    table.append(el('tr', {}, el('th', { text: 'writes' }), el('th', { text: 'reads' }), el('th', { text: k > 0 && stepOfPhase(k).scaling ? 'factor' : 'weight' })));
    for (const w of mask.weights.slice(0, 40))
      table.append(el('tr', {}, el('td', { text: `${w.target}${w.target === s.vertex ? ' (picked)' : ''}` }),
        el('td', { text: w.scaling ? '× itself' : `${w.source}${w.source === s.vertex ? ' (picked)' : ''}` }), el('td', { text: w.weight.toFixed(6) })));
    weightsBox.replaceChildren(table);
    if (mask.weights.length > 40) weightsBox.append(el('div', { class: 'muted', text: `… and ${mask.weights.length - 40} more` }));
    if (k > 0 && mask.written.length === 0) weightsBox.append(el('div', { class: 'muted', text: `${phase} writes no vertex next to this one` }));
    result = {
      model: name, quad, kind: kindOf(s.vertex), level: s.level, scheme: s.scheme, mode: s.mode, vertex: s.vertex, odd, phase: k, phaseCount: phaseCount(), phaseName: phase,
      phases: Array.from({ length: phaseCount() }, (_, i) => phaseName(i + 1)),
      written: mask.written.length, read: mask.read.length, writtenVertices: mask.written, readVertices: mask.read,
      weights: mask.weights.slice(0, 60), touched: reached.length, reached: reached.slice(0, 60),
    };
    stage.requestRender();
  }

  function stop() {
    clearInterval(timer);
    timer = null;
    playButton.textContent = '▶ play';
  }
  /** Shows phase k (0 = before the first), clamped. */
  function setPhase(k) {
    s.phase = Math.max(0, Math.min(phaseCount(), k));
    show();
  }
  function step() {
    if (s.phase >= phaseCount()) return false;
    setPhase(s.phase + 1);
    return true;
  }
  function reset() {
    stop();
    setPhase(0);
  }
  function play() {
    if (timer !== null) return stop();
    if (s.phase >= phaseCount()) setPhase(0);
    timer = setInterval(() => {
      if (!step() || s.phase >= phaseCount()) stop();
    }, PLAY_MS);
    playButton.textContent = '❚❚ pause';
    show();
  }
  const playButton = button('▶ play', 'lifting-play', () => play());
  phaseRow.append(button('step ▸', 'lifting-step', () => { stop(); step(); }), playButton, button('⟲ reset', 'lifting-reset', reset));

  /** Picks a vertex of M^l; focus: turn the camera to face it. Back to phase 0. */
  function pick(vertex, focus = true) {
    if (!Number.isInteger(vertex) || vertex < 0 || vertex >= N || depths[vertex] > s.level) return false;
    s.vertex = vertex;
    if (focus) {
      const k = current.index.get(vertex);
      const direction = [0, 1, 2].map((i) => current.positions[3 * k + i] - b.center[i]);
      if (Math.hypot(...direction) > 1e-9) stage.frame(b.center, b.radius, direction.map((d, i) => d + [0.2, 0.3, 0][i] * Math.hypot(...direction)));
    }
    reset();
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
  const nextEven = button('', 'lifting-next-even', () => nextOf(false)), nextOdd = button('', 'lifting-next-odd', () => nextOf(true));
  pickRow.append(nextEven, nextOdd);

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
    // The vertex nearest the ray among those not behind the surface (a vertex lies on it: a little
    // slack); a click off the model takes the silhouette's.
    const front = raycaster.intersectObject(current.body)[0]?.distance ?? Infinity;
    const seen = raycaster.intersectObject(current.points).filter((h) => h.distance <= front + 0.02 * b.radius);
    seen.sort((p, q) => p.distanceToRay - q.distanceToRay);
    if (seen.length) pick(current.vertices[seen[0].index], false);
  });

  modelSelect.addEventListener('change', async () => {
    stop();
    if (!(await load(modelSelect.value))) return;
    fillSelects();
    b = bounds(mesh.positions);
    raycaster.params.Points.threshold = 0.05 * b.radius;
    s.vertex = 0;
    buildLevel();
    pick(0);
  });
  levelSelect.addEventListener('change', () => { s.level = Number(levelSelect.value); buildLevel(); reset(); });
  schemeSelect.addEventListener('change', () => { s.scheme = schemeSelect.value; buildLevel(); reset(); });
  modeSelect.addEventListener('change', () => { s.mode = modeSelect.value; reset(); });
  vertexInput.addEventListener('change', () => { if (!pick(Number(vertexInput.value))) vertexInput.value = s.vertex; });
  buildLevel();
  if (!pick(askedVertex)) pick(0); // the camera faces it
  if (askedPhase) setPhase(askedPhase);
  return {
    dispose() {
      stop();
      stage.dispose();
      if (mr !== editorOpened?.mr) mr.delete();
      editorOpened?.mr.delete();
    },
    actions: {
      pick,
      step,
      reset,
      setPhase,
      /** Screen position (viewport CSS pixels) of a vertex of M^l, for click tests. */
      screenOf(vertex) {
        const k = current.index.get(vertex);
        stage.camera.updateMatrixWorld(); // frame() moved it; the next render has not run yet
        const p = new THREE.Vector3().fromArray(current.positions, 3 * k).project(stage.camera);
        const rect = canvas.getBoundingClientRect();
        return [rect.left + (p.x + 1) / 2 * rect.width, rect.top + (1 - p.y) / 2 * rect.height];
      },
      /** Every vertex of M^l on the screen: [vertex, x, y, depth (NDC z)] (tests: a vertex behind the surface). */
      screenOfAll() {
        stage.camera.updateMatrixWorld();
        const rect = canvas.getBoundingClientRect(), p = new THREE.Vector3();
        return current.vertices.map((u, k) => {
          p.fromArray(current.positions, 3 * k).project(stage.camera);
          return [u, rect.left + (p.x + 1) / 2 * rect.width, rect.top + (1 - p.y) / 2 * rect.height, p.z];
        });
      },
    },
    debug: () => result && { ...result, playing: timer !== null },
  };
}

const EDITOR = '(editor)';
const SUP = '⁰¹²³⁴⁵⁶⁷⁸⁹', SUB = '₀₁₂₃₄₅₆₇₈₉';
function sup(n) {
  return String(n).replace(/\d/g, (d) => SUP[d]);
}
function sub(n) {
  return String(n).replace(/\d/g, (d) => SUB[d]);
}
