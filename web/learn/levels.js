// #learn/levels: the filterbank of Figure 1 (paper section 2). Level by level, the coarse
// approximation (synthesis with every detail of level >= l set to zero), the level-l mesh M^l
// (coarse coefficients c^l on levelFaces(l)), and the details d^l as arrows or as a colour map of
// their size; the three schemes side by side. Analysis and synthesis come from the core. A quad
// model (quad-critter, or the editor's quad mesh) shows its Catmull-Clark levels: quad cages, the
// bilinear-patch volume.
import { sampleModels } from 'virtual:mrvol-models';
import { Stage, THREE, surface, wire, arrows, edgesOf, quadEdgesOf, bounds, ramp, diverging, colorbar, fetchSample, editorModel, openText, explain, control, select, button, readoutTable, viewParams, setViewParams } from './stage.js';

const TRIANGLE_SCHEMES = ['loop', 'butterfly', 'linear'];
const QUAD_SCHEMES = ['catmull-clark'];
const MODELS = ['spiky-ball', 'blob', 'torus', 'quad-critter'];

export async function mount({ mrvol, layout, el, stale }) {
  explain(layout.text, 'Levels: analysis and synthesis (Figure 1, section 2)', [
    'A semi-regular mesh M<sup>n</sup> comes from n 1-to-4 splits of a coarse mesh. One <b>analysis</b> step splits ' +
      'the geometry c<sup>l</sup> into a coarser c<sup>l−1</sup> = A<sup>l</sup>c<sup>l</sup> and details ' +
      'd<sup>l−1</sup> = B<sup>l</sup>c<sup>l</sup>; one <b>synthesis</b> step puts them back: ' +
      'c<sup>l</sup> = S<sup>l</sup>c<sup>l−1</sup> + C<sup>l</sup>d<sup>l−1</sup> (paper, section 2, Figure 1).',
    'Here the slider picks a level l: the surface is the synthesis with every detail of level ≥ l set to zero ' +
      '(the approximation at scale l), the blue wire is M<sup>l</sup> with its coarse coefficients c<sup>l</sup>. ' +
      'Arrows show the details d<sup>l</sup> that the next synthesis step adds (at the vertices born at level l+1); ' +
      'the colour map shows the size of every detail that was zeroed.',
    'Editing at level e moves c<sup>e</sup> and keeps the details: the scale of the edit is the scale of the level. ' +
      'The Loop-based scheme (the paper\'s, with the update step U) smooths; Butterfly interpolates; linear is the baseline.',
    '<b>Single wavelet</b>: every coefficient 0 but one detail of d<sup>l</sup> (at the finest level, of d<sup>n−1</sup>), set to 1; the synthesis of that vector is the ' +
      'wavelet (basis function) of the vertex, drawn as a bump over the smooth level-0 surface and coloured by its value. ' +
      'Compare its support and shape across schemes. The faint wires behind the blue one are the coarser meshes M<sup>0</sup> … M<sup>l−1</sup>.',
    'The model list starts with the editor\'s model as you left it (your edits included), then the samples. ' +
      'A quad model (quad-critter) shows its <b>Catmull-Clark</b> levels: each split puts a face point in every quad and an ' +
      'edge point on every edge, M<sup>l</sup> is a mesh of quads, and the volume is that of the bilinear patches through ' +
      'the quads\' corners (docs/catmull-clark.md).',
  ]);
  const models = [...MODELS.filter((m) => sampleModels.includes(m)), ...sampleModels.filter((m) => !MODELS.includes(m) && m !== 'icosahedron')];
  // The model on the editor's screen (its stored session, with the edits) comes first.
  const editor = await editorModel();
  if (stale()) return null;
  const options = [...(editor ? [[EDITOR, `editor: ${editor.name}`]] : []), ...models.map((m) => [m, m])];
  const s = { model: options[0][0], scheme: 'loop', compare: false, level: 0, details: 'arrows' };
  // Settings from the address (a reload or a shared link): checked against what there is.
  const asked = viewParams();
  if (options.some(([value]) => value === asked.get('model'))) s.model = asked.get('model');
  if ([...TRIANGLE_SCHEMES, ...QUAD_SCHEMES].includes(asked.get('scheme'))) s.scheme = asked.get('scheme');
  if (['arrows', 'colour', 'none'].includes(asked.get('details'))) s.details = asked.get('details');
  if (/^\d$/.test(asked.get('l') ?? '')) s.level = Number(asked.get('l'));
  s.compare = asked.get('compare') === '1';
  const modelSelect = control(layout.controls, 'model', select(options, s.model, 'levels-model'));
  const schemeSelect = control(layout.controls, 'scheme', select(TRIANGLE_SCHEMES.map((m) => [m, m]), s.scheme, 'levels-scheme'));
  let modelSchemes = TRIANGLE_SCHEMES; // the model's schemes (a quad model: Catmull-Clark alone)
  const compare = document.createElement('input');
  compare.type = 'checkbox';
  compare.dataset.testid = 'levels-compare';
  compare.checked = s.compare;
  control(layout.controls, 'compare schemes', compare);
  const slider = document.createElement('input');
  slider.type = 'range';
  slider.min = 0;
  slider.step = 1;
  slider.dataset.testid = 'levels-level';
  control(layout.controls, 'level l', slider);
  const detailSelect = control(layout.controls, 'details', select([['arrows', 'arrows'], ['colour', 'colour map of |d|'], ['none', 'none']], s.details, 'levels-details'));
  const ghosts = document.createElement('input');
  ghosts.type = 'checkbox';
  ghosts.checked = true;
  ghosts.dataset.testid = 'levels-ghosts';
  control(layout.controls, 'coarser levels', ghosts);
  s.ghosts = true;
  s.wavelet = null; // the vertex whose detail is the single non-zero coefficient, or null
  const bank = el('div', { class: 'filterbank', testid: 'filterbank' });
  layout.controls.append(bank);
  const play = el('div', { class: 'learn-row' });
  layout.controls.append(play);
  const set = readoutTable(layout.readouts, [
    ['model', 'levels-model-info'], ['level l', 'levels-current'], ['vertices of Mˡ', 'levels-cage-size'],
    ['details zeroed', 'levels-zeroed'], ['max |dˡ|', 'levels-dmax'], ['volume (approx.)', 'levels-volume'],
    ['volume (fine)', 'levels-volume-fine'], ['wavelet', 'levels-wavelet-info'],
  ]);
  let legend = null;

  const stage = new Stage(layout.stage, [s.scheme]);
  let model = null; // { name, mr, faces, quads, positions, depths, n, perScheme: Map(scheme -> { coefficients, approx: [], cage: [] }) }
  let timer = null;

  function loadScheme(scheme) {
    if (model.perScheme.has(scheme)) return model.perScheme.get(scheme);
    const { mr, positions, depths, n, faces, quads } = model;
    const coefficients = mr.analyze(positions, { level: 0, scheme }); // c^0 and every detail d^0..d^{n-1}
    const levels = [];
    for (let l = 0; l <= n; l++) {
      // The details of the vertices born after level l set to zero (the core's approximation).
      const approx = mr.approximation(positions, { level: l, scheme });
      const coarse = mr.analyze(positions, { level: l, scheme }); // c^l on the vertices of depth <= l
      // a quad model's volume: the bilinear patches through its quads' corners
      levels.push({ approx, coarse, volume: quads ? mrvol.quadVolume({ positions: approx, quads }) : mrvol.volume({ positions: approx, faces }) });
    }
    let dmax = 0;
    for (let i = 0; i < depths.length; i++)
      if (depths[i] > 0) dmax = Math.max(dmax, Math.hypot(coefficients[3 * i], coefficients[3 * i + 1], coefficients[3 * i + 2]));
    const entry = { coefficients, levels, dmax };
    model.perScheme.set(scheme, entry);
    return entry;
  }

  async function openModel(choice) {
    const name = choice === EDITOR ? editor.name : choice;
    const text = choice === EDITOR ? editor.text : await fetchSample(name);
    if (stale()) return;
    const { mesh, mr, quad } = openText(mrvol, text, { positions: choice === EDITOR ? editor.positions : null, quads: true });
    const n = mr.levels;
    if (n === 0 || mr.lowestLevel > 0) {
      mr.delete();
      throw new Error(n === 0 ? `${name} has no subdivision level to step through` : `${name}'s analysis stops at level ${mr.lowestLevel} (a cube's first split)`);
    }
    model?.mr.delete();
    model = { name, mr, faces: mesh.faces, quads: mesh.quads, positions: mesh.positions, depths: mr.depths(), n, perScheme: new Map(), fineVolume: mr.info().volume };
    // the schemes this model takes; the scheme select follows
    modelSchemes = quad ? QUAD_SCHEMES : TRIANGLE_SCHEMES;
    if (!modelSchemes.includes(s.scheme)) s.scheme = modelSchemes[0];
    schemeSelect.replaceChildren(...modelSchemes.map((m) => new Option(m, m)));
    schemeSelect.value = s.scheme;
    compare.disabled = quad;
    if (quad) s.compare = compare.checked = false;
    // M^l's faces (triangles or quads) and the cage's edges (a quad cage: the quads' sides)
    model.levelFaces = Array.from({ length: n + 1 }, (_, l) => (quad ? mr.levelQuads(l) : mr.levelFaces(l)));
    model.cages = model.levelFaces.map((levelFaces, l) => {
      const vertices = [];
      for (let i = 0; i < model.depths.length; i++) if (model.depths[i] <= l) vertices.push(i);
      const index = new Map(vertices.map((v, k) => [v, k]));
      return { vertices, edges: quad ? quadEdgesOf(levelFaces, index) : edgesOf(levelFaces, index) };
    });
    s.wavelet = null;
    s.level = Math.min(s.level, n);
    slider.max = n;
    const b = bounds(mesh.positions);
    model.radius = b.radius;
    model.bounds = b;
    stage.frame(b.center, b.radius);
    set('levels-model-info', `${name}: ${mr.vertexCount} vertices, ${quad ? `${mr.faceCount} quads (Catmull-Clark)` : `${mr.faceCount ?? mesh.faces.length / 3} triangles`}, n = ${n}`);
    buildBank();
    draw();
  }

  function buildBank() {
    bank.replaceChildren();
    for (let l = model.n; l >= 0; l--) {
      const b = el('button', { type: 'button', testid: `bank-${l}`, text: `c${sup(l)}` });
      b.addEventListener('click', () => {
        stopPlaying();
        setLevel(l);
      });
      bank.append(b);
      if (l > 0) bank.append(el('span', { text: '→' }), el('span', { class: 'd', text: `d${sup(l - 1)}` }), el('span', { text: '+' }));
    }
  }

  function draw() {
    if (!model) return;
    const schemes = s.compare ? modelSchemes : [s.scheme];
    const reframe = stage.panels.length !== schemes.length;
    stage.setPanels(schemes.map((x) => `${x}: level ${s.level}`));
    stage.resize();
    if (reframe) stage.frame(model.bounds.center, model.bounds.radius);
    const { depths, n, faces } = model;
    const l = s.level;
    const { vertices: cageVertices, edges: cageEdges } = model.cages[l];
    const cageOf = (k, coarse) => {
      const positions = new Float64Array(3 * model.cages[k].vertices.length);
      model.cages[k].vertices.forEach((v, q) => positions.set(coarse.subarray(3 * v, 3 * v + 3), 3 * q));
      return positions;
    };
    legend?.remove();
    legend = null;
    const wavelets = [];
    schemes.forEach((scheme, p) => {
      const data = loadScheme(scheme);
      const { approx, coarse } = data.levels[l];
      const scene = stage.panels[p].scene;
      let colors = null;
      if (s.wavelet !== null) {
        const w = waveletOf(scheme, s.wavelet);
        wavelets.push(w);
        scene.add(surface(w.shape, faces, { colors: w.colors }));
      } else if (s.details === 'colour') {
        colors = new Float32Array(approx.length);
        for (let i = 0; i < depths.length; i++) {
          const c = data.coefficients;
          const size = depths[i] > l ? Math.hypot(c[3 * i], c[3 * i + 1], c[3 * i + 2]) / (data.dmax || 1) : 0;
          colors.set(ramp(Math.sqrt(size)), 3 * i);
        }
      }
      if (s.wavelet === null) scene.add(surface(approx, faces, { colors }));
      // The coarser meshes, fainter the coarser, behind the current one.
      if (s.ghosts)
        for (let k = 0; k < l; k++)
          scene.add(wire(cageOf(k, data.levels[k].coarse), model.cages[k].edges, { color: 0x57606a, points: false, opacity: 0.18 + 0.3 * k / l }));
      scene.add(wire(cageOf(l, coarse), cageEdges, { points: cageVertices.length <= 700 }));
      if (s.details === 'arrows' && l < n && s.wavelet === null) {
        const from = [], vectors = [];
        for (let i = 0; i < depths.length; i++) if (depths[i] === l + 1) {
          from.push(approx[3 * i], approx[3 * i + 1], approx[3 * i + 2]);
          vectors.push(data.coefficients[3 * i], data.coefficients[3 * i + 1], data.coefficients[3 * i + 2]);
        }
        // Drawn to scale, or magnified so that the longest arrow is a fifth of the model's radius.
        let longest = 0;
        for (let i = 0; i < vectors.length; i += 3) longest = Math.max(longest, Math.hypot(vectors[i], vectors[i + 1], vectors[i + 2]));
        const scale = longest > 0 ? Math.max(1, 0.2 * model.radius / longest) : 1;
        model.arrowScale = scale;
        scene.add(arrows(from, vectors, { scale }));
      }
    });
    if (s.wavelet !== null) {
      const w = wavelets[0];
      legend = colorbar(layout.stage, { title: `wavelet ψ of d${sup(w.depth - 1)} at vertex ${w.vertex} (${schemes[0]})`, lo: (-w.max).toPrecision(2), hi: w.max.toPrecision(2), colors: (t) => diverging(2 * t - 1), testid: 'levels-colorbar' });
      set('levels-wavelet-info', `vertex ${w.vertex} (d${sup(w.depth - 1)}): support ${w.support} of ${depths.length} vertices, max ${w.max.toPrecision(3)}`, w.vertex);
    } else {
      set('levels-wavelet-info', 'off (the single wavelet button above shows one)');
      if (s.details === 'colour') {
        const d = loadScheme(schemes[0]).dmax;
        legend = colorbar(layout.stage, { title: '|d| of the zeroed details (square-root scale)', lo: '0', hi: d.toPrecision(3), testid: 'levels-colorbar' });
      }
    }
    model.wavelets = wavelets.map(({ vertex, depth, support, max, atVertex, nonZero }) => ({ vertex, depth, support, max, atVertex, nonZero }));
    const main = loadScheme(schemes[0]);
    let dmax = 0, zeroed = 0;
    for (let i = 0; i < depths.length; i++) {
      if (depths[i] > l) zeroed++;
      if (depths[i] === l + 1) dmax = Math.max(dmax, Math.hypot(...main.coefficients.subarray(3 * i, 3 * i + 3)));
    }
    slider.value = l;
    for (const b of bank.querySelectorAll('button')) b.classList.toggle('current', b.dataset.testid === `bank-${l}`);
    set('levels-current', `${l} of ${n}`, l);
    set('levels-cage-size', String(cageVertices.length), cageVertices.length);
    detailSelect.disabled = s.wavelet !== null; // the wavelet is drawn by its own colours
    if (s.wavelet !== null) set('levels-zeroed', `all but one: the single wavelet's (vertex ${s.wavelet})`, depths.length - 1);
    else set('levels-zeroed', l === n ? 'none: the finest level keeps every detail' : `${zeroed} vertices: d${sup(l)}${l < n - 1 ? ` … d${sup(n - 1)}` : ''}`, zeroed);
    set('levels-dmax', l < n ? dmax.toPrecision(4) + (s.details === 'arrows' && model.arrowScale > 1 ? ` (arrows ×${model.arrowScale.toFixed(1)})` : '') : '– (finest level)', dmax);
    set('levels-volume', schemes.map((x) => `${x} ${loadScheme(x).levels[l].volume.toFixed(6)}`).join('\n'), main.levels[l].volume);
    set('levels-volume-fine', model.fineVolume.toFixed(6) + (model.quads ? ' (bilinear patches)' : ''), model.fineVolume);
    setViewParams('learn/levels', { model: s.model, scheme: s.scheme, l: s.level, details: s.details, compare: s.compare });
    stage.requestRender();
  }

  function setLevel(l) {
    s.level = Math.max(0, Math.min(model.n, l));
    if (s.wavelet !== null && model.depths[s.wavelet] !== waveletDepth()) s.wavelet = firstWavelet();
    draw();
  }

  // The wavelet shown at level l is a detail of d^l (a vertex born at level l + 1); at the finest level, of d^(n-1).
  const waveletDepth = () => Math.min(s.level + 1, model.n);
  function firstWavelet(after = -1) {
    const depth = waveletDepth(), N = model.depths.length;
    for (let k = 1; k <= N; k++) {
      const v = (after + k + N) % N;
      if (model.depths[v] === depth) return v;
    }
    return null;
  }

  /**
   * The single wavelet of `vertex` in `scheme`: the synthesis of a coefficient vector that is 0 but
   * for a 1 in the x of that detail. Its x components are the basis function psi at every fine
   * vertex, drawn as a bump along the normals of the smooth level-0 surface.
   */
  function waveletOf(scheme, vertex) {
    const N = model.depths.length;
    const unit = new Float64Array(3 * N);
    unit[3 * vertex] = 1;
    const psi = model.mr.synthesize(unit, { level: 0, scheme });
    let max = 0, support = 0;
    for (let i = 0; i < N; i++) {
      max = Math.max(max, Math.abs(psi[3 * i]));
      if (Math.abs(psi[3 * i]) > 1e-12) support++;
    }
    const base = loadScheme(scheme).levels[0].approx;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(base), 3));
    geometry.setIndex(new THREE.BufferAttribute(model.faces, 1));
    geometry.computeVertexNormals();
    const normals = geometry.getAttribute('normal').array;
    geometry.dispose();
    const shape = new Float64Array(3 * N), colors = new Float32Array(3 * N);
    const lift = 0.3 * model.radius / (max || 1);
    for (let i = 0; i < N; i++) {
      for (let k = 0; k < 3; k++) shape[3 * i + k] = base[3 * i + k] + lift * psi[3 * i] * normals[3 * i + k];
      colors.set(diverging(psi[3 * i] / (max || 1)), 3 * i);
    }
    return { vertex, depth: model.depths[vertex], psi, shape, colors, max, support, atVertex: psi[3 * vertex], nonZero: unit.filter((x) => x !== 0).length };
  }

  /** The camera faces the wavelet's vertex. */
  function faceWavelet() {
    if (s.wavelet === null) return;
    const p = loadScheme(s.scheme).levels[0].approx, c = model.bounds.center;
    const direction = [0, 1, 2].map((k) => p[3 * s.wavelet + k] - c[k]);
    if (Math.hypot(...direction) > 1e-9) stage.frame(c, model.bounds.radius, direction.map((d, k) => d + [0.25, 0.35, 0][k] * Math.hypot(...direction)));
  }

  function toggleWavelet() {
    s.wavelet = s.wavelet === null ? firstWavelet() : null;
    faceWavelet();
    waveletButton.classList.toggle('current', s.wavelet !== null);
    waveletButton.textContent = s.wavelet === null ? 'single wavelet' : 'all details';
    draw();
  }

  // Playing the levels one way; its button reads "stop" meanwhile. A level chosen by hand stops it.
  function playLevels(direction) {
    const wasPlaying = playing;
    stopPlaying();
    if (wasPlaying === direction) return; // its own button: stop
    playing = direction;
    playButtons[direction].textContent = '■ stop';
    let l = direction === 'analysis' ? model.n : 0;
    setLevel(l);
    timer = setInterval(() => {
      l += direction === 'analysis' ? -1 : 1;
      if (l < 0 || l > model.n) return stopPlaying();
      setLevel(l);
    }, 900);
  }
  function stopPlaying() {
    clearInterval(timer);
    timer = null;
    playing = null;
    for (const [direction, b] of Object.entries(playButtons)) b.textContent = PLAY_LABELS[direction];
  }

  play.classList.add('learn-buttons');
  const waveletButton = button('single wavelet', 'levels-wavelet', toggleWavelet);
  const PLAY_LABELS = { analysis: '▶ analysis (n → 0)', synthesis: '▶ synthesis (0 → n)' };
  let playing = null;
  const playButtons = {
    analysis: button(PLAY_LABELS.analysis, 'levels-play-analysis', () => playLevels('analysis')),
    synthesis: button(PLAY_LABELS.synthesis, 'levels-play-synthesis', () => playLevels('synthesis')),
  };
  play.append(playButtons.analysis, playButtons.synthesis, waveletButton,
    button('next wavelet', 'levels-wavelet-next', () => {
      s.wavelet = firstWavelet(s.wavelet ?? -1);
      waveletButton.textContent = 'all details';
      faceWavelet();
      draw();
    }));
  ghosts.addEventListener('change', () => { s.ghosts = ghosts.checked; draw(); });
  slider.addEventListener('input', () => {
    stopPlaying();
    setLevel(Number(slider.value));
  });
  schemeSelect.addEventListener('change', () => { s.scheme = schemeSelect.value; draw(); });
  compare.addEventListener('change', () => { s.compare = compare.checked; draw(); });
  detailSelect.addEventListener('change', () => { s.details = detailSelect.value; draw(); });
  modelSelect.addEventListener('change', () => { s.model = modelSelect.value; openModel(s.model); });

  try {
    await openModel(s.model);
  } catch (e) {
    if (s.model !== EDITOR) throw e;
    layout.status.textContent = `The editor's model could not be shown (${e.message}); a sample instead.`;
    s.model = modelSelect.value = models[0];
    await openModel(s.model);
  }
  return {
    dispose() {
      clearInterval(timer);
      stage.dispose();
      model?.mr.delete();
    },
    actions: { setLevel, wavelet: (vertex) => { s.wavelet = vertex; draw(); } },
    debug: () => ({
      model: model?.name, levels: model?.n, level: s.level, compare: s.compare, details: s.details, scheme: s.scheme,
      quad: Boolean(model?.quads), cageEdges: model?.cages[s.level].edges.length / 2, cageVertices: model?.cages[s.level].vertices.length,
      cageFaces: model ? model.levelFaces[s.level].length / (model.quads ? 4 : 3) : 0,
      panels: stage.panels.map((p) => p.label), frames: stage.frames ?? 0,
      volumes: Object.fromEntries([...model.perScheme].map(([k, v]) => [k, v.levels.map((x) => x.volume)])),
      fineVolume: model.fineVolume, ghosts: s.ghosts ? s.level : 0, wavelets: model.wavelets,
      grid: stage.grid, cells: stage.cells, zeroedText: layout.readouts.querySelector('[data-testid="levels-zeroed"]').textContent,
    }),
  };
}

const EDITOR = '(editor)';
const SUP = '⁰¹²³⁴⁵⁶⁷⁸⁹';
function sup(n) {
  return String(n).replace(/\d/g, (d) => SUP[d]);
}
