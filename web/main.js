// The mrvol web editor: wires the WASM core (through lib/api.mjs), the view, the panel, the theta
// worker and its cache. Every geometric quantity (analysis, volume, correction, positions) comes
// from the core; this file only moves arrays between it and the screen.
import { sampleModels } from 'virtual:mrvol-models';
import { loadMrvol } from './mrvol.js';
import { Viewer } from './viewer.js';
import { CageDragger } from './drag.js';
import { cageEdges } from './cage.js';
import { History } from '../lib/three/history.mjs';
import { ThetaCache, thetaKey } from './theta-cache.js';
import { ThetaJobs } from './theta-jobs.js';
import { loadSession, saveSession, clearSession, decodeFloat64 } from './session.js';
import { createPanel, MAX_PARTS } from './panel.js';
import { learnRoute, startLearn, watchForLearnRoutes } from './learn/router.js';

const DEFAULT_MODEL = 'spiky-ball';
// The Loop weights of the paper (the API's defaults); part of theta's key for every scheme.
const ALPHA = -1.70943, BETA = 0.42954;
// Without 1-to-4 splits every vertex is a handle: fine for a small base mesh, not for a big one.
const MAX_FLAT_VERTICES = 64;
const FREE_SET_MODES = ['minus-held', 'all', 'painted', 'parts'];
const TOOLS = ['drag', 'paint', 'assign'];
// painted: the painted region (caller's indices of cage vertices); parts[p]: those of part p + 1.
// Both are replaced, never mutated.
const DEFAULT_SETTINGS = Object.freeze({
  model: DEFAULT_MODEL, scheme: 'loop', level: 0, preserve: true, freeSet: 'minus-held', tolerance: 1e-6,
  flat: true, showMesh: true, showCage: true,
  tool: 'drag', part: 1, painted: Object.freeze([]), parts: Object.freeze([]),
  showApprox: false, approxLevel: 0, showDetails: false,
});
const PAINT_COLOR = '#bf3989';
const PART_COLORS = ['#cf222e', '#8250df', '#0e8a94', '#9a6700', '#bf3989', '#57606a', '#24292f', '#7d8a00'];
// The layers are recomputed after every drag step while that costs less than this; otherwise once
// the drag ends.
const LAYER_BUDGET_MS = 4;

const $ = (id) => document.getElementById(id);

const app = {
  mrvol: null,
  viewer: null,
  panel: null,
  dragger: null,
  cache: null,
  jobs: new ThetaJobs(),
  settings: { ...DEFAULT_SETTINGS },
  model: null,   // { name, kind: 'sample' | 'file', text, mr, info, fingerprint, faces }
  editor: null,
  cageSize: 0,
  cageVertices: null, // caller's index of every cage vertex, cage order
  cageIndex: null,    // Map: caller's index -> cage index
  parts: [],          // part numbers (1..MAX_PARTS) of the editor's parts, in the editor's order
  partReferences: null,
  stroke: null,       // the paint stroke going on: { add }
  layers: { level: null, updates: 0, lastMs: null, dirty: false },
  heldAll: null, // Uint8Array of ones: every cage vertex held (restoring a cage)
  selection: new Set(),
  history: new History(),
  drag: null,    // the drag going on: { handles, held (flags), before (cage positions) }
  theta: { key: null, source: null, status: '', generation: 0, memory: new Map(), prefetch: null },
  lastReport: null,
  lastStepMs: null,
  ready: false,
  awaitingFrame: false,
  loadGeneration: 0,
  // ms since navigation start: script running, core loaded, model opened, first drag-ready frame,
  // theta in use; the worker's computeTheta time; per drag step and per frame (input to frame, render).
  stats: {
    scriptAt: null, coreAt: null, cacheAt: null, modelAt: null, readyAt: null, thetaReadyAt: null, thetaMs: null,
    steps: [], frames: [], renders: [], layers: [],
  },
  pendingInput: null,
};

// ---- messages -----------------------------------------------------------------------------------

function showError(message) {
  $('error-text').textContent = message;
  $('error').hidden = false;
}

function clearError() {
  $('error').hidden = true;
  $('error-text').textContent = '';
}

function notice(message) {
  $('notice').textContent = message ?? '';
}

// ---- readouts -------------------------------------------------------------------------------------

const SUPERSCRIPT = '⁰¹²³⁴⁵⁶⁷⁸⁹';
/** θ with its level as a superscript: θ⁰, θ¹² */
function thetaName(level) {
  return 'θ' + String(level).replace(/\d/g, (d) => SUPERSCRIPT[d]);
}

function formatVolume(v) {
  return Number.isFinite(v) ? v.toPrecision(12) : '–';
}

function updateReadouts() {
  const editor = app.editor;
  if (!editor) return;
  const reference = editor.referenceVolume();
  const current = editor.volume();
  const error = Math.abs(current - reference) / Math.max(Math.abs(reference), 1e-300);
  const set = (id, text, value) => {
    const element = $(id);
    element.textContent = text;
    if (value !== undefined) element.dataset.value = String(value);
  };
  set('volume-reference', formatVolume(reference), reference);
  set('volume-current', formatVolume(current), current);
  set('volume-error', error.toExponential(2), error);
  const report = app.lastReport;
  set('step-iterations', report ? String(report.iterations) : '–');
  set('step-ms', app.lastStepMs === null ? '–' : app.lastStepMs.toFixed(2));
  set('step-path', report ? report.path : editor.path());
  updateModeReadouts();
  if (report && !report.converged) notice(`The last step did not converge: ${report.message}`);
  else if (report && $('notice').textContent.startsWith('The last step did not converge')) notice('');
}

// Rows of the readout table made here, after the relative error, in this order.
const EXTRA_ROWS = [['free-set-info', 'free set'], ['part-volumes', 'part volumes'], ['layer-info', 'layers']];

function readoutRow(id) {
  if (!$(id)) {
    let previous = $('volume-error').closest('tr');
    for (const [rowId, label] of EXTRA_ROWS) {
      if (!$(rowId)) {
        const row = document.createElement('tr');
        const th = document.createElement('th');
        th.textContent = label;
        const cell = document.createElement('td');
        cell.id = rowId;
        cell.dataset.testid = rowId;
        row.append(th, cell);
        row.hidden = rowId !== 'free-set-info';
        previous.after(row);
      }
      previous = $(rowId).closest('tr');
    }
  }
  return $(id);
}

function updateModeReadouts() {
  const { freeSet, painted } = app.settings;
  const free = readoutRow('free-set-info');
  free.textContent = freeSet === 'painted' ? `painted region: ${painted.length} handle${painted.length === 1 ? '' : 's'}`
    : freeSet === 'parts' ? `cage minus held; ${app.parts.length} part${app.parts.length === 1 ? '' : 's'} keep their volumes`
    : freeSet === 'all' ? 'all cage' : 'cage minus held';
  const cell = readoutRow('part-volumes');
  const volumes = app.parts.length ? app.editor.partVolumes() : null;
  cell.closest('tr').hidden = !volumes;
  if (!volumes) {
    cell.textContent = '';
    delete cell.dataset.value;
    return;
  }
  const lines = app.parts.map((number, p) => {
    const reference = app.partReferences[p];
    const error = Math.abs(volumes[p] - reference) / Math.max(Math.abs(reference), 1e-300);
    if (reference === 0 && volumes[p] === 0) return `${number}: no triangle (assign neighbouring handles)`;
    return `${number}: ${volumes[p].toPrecision(8)} / ${reference.toPrecision(8)} (${error.toExponential(1)})`;
  });
  cell.textContent = lines.join('\n');
  cell.style.whiteSpace = 'pre';
  cell.dataset.value = JSON.stringify({ parts: app.parts, volumes: Array.from(volumes), references: Array.from(app.partReferences) });
}

function updateLayerReadout() {
  const cell = readoutRow('layer-info');
  const shown = app.settings.showApprox || app.settings.showDetails;
  cell.closest('tr').hidden = !shown || app.layers.level === null;
  const { level, lastMs } = app.layers;
  cell.textContent = shown && level !== null ? `level ${level} approximation, ${lastMs.toFixed(2)} ms` +
    (app.layers.deferred ? ' (after each drag)' : '') : '';
}

function updateThetaReadout() {
  $('theta-source').textContent = app.theta.source ?? (app.theta.pending ? 'pending' : 'none');
  $('theta-status').textContent = app.theta.status;
}

function showProgress(fraction, label) {
  const box = $('theta-progress');
  if (fraction === null) {
    box.hidden = true;
    return;
  }
  box.hidden = false;
  $('theta-progress-bar').value = fraction;
  $('theta-progress-label').textContent = label;
}

function modelInfoText() {
  const { info } = app.model;
  return `${info.vertices} vertices, ${info.faces} faces, ${info.levels} levels, cage ${app.cageSize} vertices` +
    (info.closed ? '' : ' (open: the volume is that of the cone to the boundary centroid)');
}

// ---- session --------------------------------------------------------------------------------------

let saveTimer = null;
function saveSoon() {
  clearTimeout(saveTimer);
  saveTimer = setTimeout(saveNow, 150);
}

function saveNow() {
  clearTimeout(saveTimer);
  if (!app.model || !app.editor) return;
  saveSession({
    model: app.model,
    settings: { ...app.settings },
    fingerprint: app.model.fingerprint,
    positions: app.editor.positions(),
    reference: app.editor.referenceVolume(),
  });
}

// ---- models ---------------------------------------------------------------------------------------

function modelUrl(name) {
  return `${import.meta.env.BASE_URL}models/${encodeURIComponent(name)}.obj`;
}

async function fetchSample(name) {
  if (!/^[\w.-]+$/.test(name)) throw new Error(`'${name}' is not a model name`);
  const response = await fetch(modelUrl(name));
  if (!response.ok) throw new Error(`there is no sample model '${name}' (HTTP ${response.status})`);
  return response.text();
}

/**
 * Parses and checks an OBJ; on success replaces the current model (and resolves true), otherwise
 * shows why and keeps the current one (false).
 * restore: { positions: Float64Array, reference, fingerprint } from a stored session.
 */
function openModelText({ name, kind, text }, restore = null) {
  const { mrvol } = app;
  let mr = null, info, fingerprint, read = false;
  try {
    const mesh = mrvol.readObj(text);
    read = true;
    mr = mrvol.openMesh(mesh);
    info = mr.info();
    if (info.levels === 0 && info.vertices > MAX_FLAT_VERTICES)
      throw new mrvol.MrvolError(
        `this mesh is not semi-regular: no 1-to-4 subdivision levels were found in its ${info.vertices} vertices, ` +
        'so it has no coarse cage to edit (mrvol edits meshes made by repeated 1-to-4 splits of a base mesh)');
    fingerprint = mr.fingerprint();
  } catch (e) {
    const notSemiRegular = mr !== null && info?.levels === 0;
    // Read, but not a closed oriented 2-manifold (a raw scan: repeated faces, holes, pieces).
    const damaged = read && mr === null;
    mr?.delete();
    showError(`Could not open ${name}: ${e.message}`);
    if (notSemiRegular || damaged) offerRemesh({ name, text }, { repair: damaged });
    return false;
  }
  clearError();
  $('remesh-offer').hidden = true;
  notice('');
  // Commit: the previous model goes (its editors with it), with its cached tensors.
  cancelTheta();
  for (const { theta } of app.theta.memory.values()) theta.delete();
  app.theta.memory.clear();
  app.editor = null;
  app.model?.mr.delete();
  app.model = { name, kind, text, mr, info, fingerprint, faces: mr.faces(), depths: mr.depths() };
  app.settings.level = Math.min(app.settings.level, info.levels);
  app.settings.model = name;

  let reference = null;
  if (restore && restore.fingerprint === fingerprint && restore.positions?.length === 3 * info.vertices) {
    mr.setPositions(restore.positions);
    if (Number.isFinite(restore.reference)) reference = restore.reference;
  }
  app.ready = false;
  app.viewer.setMesh(mr.positions(), app.model.faces);
  applyViewLayers();
  app.panel.setLevels(info.levels);
  app.panel.update();
  buildEditor(reference);
  app.viewer.frameAll();
  $('model-name').textContent = name;
  $('model-info').textContent = modelInfoText();
  app.stats.modelAt ??= performance.now();
  app.awaitingFrame = true; // ready once the next frame (with this model) is drawn
  app.viewer.requestRender();
  saveSoon();
  return true;
}

/**
 * A closed mesh that is not semi-regular: offers remeshing (lib/remesh.mjs in a worker) with its
 * parameters; the result opens as a new model. A mesh that is not a closed 2-manifold is offered
 * the repair stage first (`repair` checked).
 */
function offerRemesh(source, { repair = false } = {}) {
  $('remesh-why').textContent = repair ? 'Not a closed 2-manifold: repair and remesh it?' : 'Not semi-regular: remesh it?';
  $('remesh-repair').checked = repair;
  $('remesh-smooth').disabled = !repair;
  $('remesh-repair').onchange = () => { $('remesh-smooth').disabled = !$('remesh-repair').checked; };
  $('remesh-offer').hidden = false;
  $('remesh-progress').hidden = true;
  $('remesh-stage').textContent = '';
  $('remesh-go').disabled = false;
  $('remesh-go').onclick = () => {
    const levels = Number($('remesh-levels').value), base = Number($('remesh-base').value);
    const repairing = $('remesh-repair').checked, smooth = Number($('remesh-smooth').value);
    app.remeshWorker?.terminate();
    const worker = new Worker(new URL('./remesh-worker.js', import.meta.url), { type: 'module', name: 'mrvol-remesh' });
    app.remeshWorker = worker;
    $('remesh-go').disabled = true;
    $('remesh-progress').hidden = false;  // indeterminate: the stage text says where it is
    const started = performance.now();
    const finish = (stage) => {
      worker.terminate();
      if (app.remeshWorker === worker) app.remeshWorker = null;
      $('remesh-progress').hidden = true;
      $('remesh-go').disabled = false;
      $('remesh-stage').textContent = stage;
    };
    worker.onmessage = async ({ data }) => {
      if (data.type === 'stage') {
        $('remesh-stage').textContent = data.stage;
        return;
      }
      if (data.type === 'error') return finish(`remeshing failed: ${data.message}`);
      finish('');
      const r = data.report;
      const ok = await openModel({ name: `${source.name.replace(/\.obj$/i, '')}-remeshed`, kind: 'file', text: data.text });
      const fixes = r.repair
        ? `Repaired (${r.repair.finFaces + r.repair.duplicateFaces + r.repair.nonManifoldFaces + r.repair.foldedFaces} faces ` +
          `dropped, ${r.repair.droppedComponents} pieces dropped, ${r.repair.holesFilled} holes closed), then remeshed`
        : 'Remeshed';
      if (ok)
        notice(`${fixes} in ${((performance.now() - started) / 1000).toFixed(1)} s: ${r.levels} levels, ` +
          `${r.vertices} vertices, Hausdorff ${(100 * r.hausdorff).toFixed(2)}% of the diagonal, ` +
          `${r.flippedTriangles} flipped triangles, volume change ${(100 * r.volumeChange).toFixed(2)}%`);
    };
    worker.onerror = (e) => {
      e.preventDefault?.();
      finish(`remeshing failed: ${e.message || 'the worker could not start'}`);
    };
    worker.postMessage({ text: source.text, levels, baseFaces: base > 0 ? base : undefined,
      repair: repairing, smooth: repairing && smooth > 0 ? smooth : undefined });
  };
}

/** Loads a model from its source; false when it could not be read or opened. */
async function openModel(source, restore = null) {
  const generation = ++app.loadGeneration;
  let text;
  try {
    const prefetched = source.prefetch ? await source.prefetch : undefined;
    if (prefetched instanceof Error) throw prefetched;
    text = source.text ?? prefetched ?? (source.kind === 'sample' ? await fetchSample(source.name) : await source.file.text());
  } catch (e) {
    if (generation === app.loadGeneration) showError(`Could not open ${source.name}: ${e.message}`);
    return false;
  }
  if (generation !== app.loadGeneration) return false;
  const ok = openModelText({ name: source.name, kind: source.kind, text }, restore);
  if (ok) {
    const url = new URL(location.href);
    if (source.kind === 'sample') url.searchParams.set('model', source.name);
    else url.searchParams.delete('model');
    history.replaceState(null, '', url);
  } else {
    app.settings.model = app.model?.name ?? DEFAULT_MODEL;
    app.panel.update(); // the sample list goes back to the current model
  }
  return ok;
}

// ---- editor ---------------------------------------------------------------------------------------

/**
 * (Re)creates the editor at the current scheme and level from the current shape, keeping the
 * reference volume. Then asks for theta (cache or worker); until it arrives the editor runs
 * matrix-free.
 */
function buildEditor(reference = null) {
  const { mr } = app.model;
  if (app.editor) {
    mr.setPositions(app.editor.positions());
    reference ??= app.editor.referenceVolume();
    app.editor.delete();
    app.editor = null;
  }
  const { scheme, level } = app.settings;
  const editor = mr.createEditor({ level, scheme, alpha: ALPHA, beta: BETA });
  if (reference !== null) editor.setReferenceVolume(reference);
  app.editor = editor;
  app.cageSize = editor.cageSize;
  app.heldAll = new Uint8Array(editor.cageSize).fill(1);
  app.selection.clear();
  app.history.clear();
  app.drag = null;
  app.lastReport = null;
  app.lastStepMs = null;

  const cageVertices = editor.cageVertices();
  const cageIndex = new Map(Array.from(cageVertices, (v, i) => [v, i]));
  app.cageVertices = cageVertices;
  app.cageIndex = cageIndex;
  const edges = cageEdges(app.model.mr.levelFaces(level), cageIndex);
  app.viewer.setCage(editor.cagePositions(), edges);
  app.viewer.updateMesh(editor.positions());
  keepCageMarks();
  applyFreeSet();
  updateLayers();
  if (app.model) $('model-info').textContent = modelInfoText();
  requestTheta();
}

function showEditorState() {
  app.viewer.updateMesh(app.editor.positions());
  app.viewer.updateCage(app.editor.cagePositions());
  updateLayers();
  updateReadouts();
}

// ---- free set: painted region, parts ----------------------------------------------------------------

/** Keeps of the painted region and the parts only this cage's vertices (after a level or model change). */
function keepCageMarks() {
  const s = app.settings;
  const ok = (v) => Number.isInteger(v) && app.cageIndex.has(v);
  if (!FREE_SET_MODES.includes(s.freeSet)) s.freeSet = DEFAULT_SETTINGS.freeSet;
  if (!TOOLS.includes(s.tool)) s.tool = DEFAULT_SETTINGS.tool;
  s.painted = Array.isArray(s.painted) ? [...new Set(s.painted.filter(ok))] : [];
  const seen = new Set();
  s.parts = Array.from({ length: MAX_PARTS }, (_, p) => {
    const list = Array.isArray(s.parts?.[p]) ? s.parts[p] : [];
    return list.filter((v) => ok(v) && !seen.has(v) && seen.add(v));
  });
  app.panel.showModeControls();
  toolNotice();
}

/**
 * Hands the free set to the editor: cage minus held, all cage, the painted region (a list), or the
 * parts (cage minus held, each part keeping its own volume, references = the volumes now).
 */
function applyFreeSet() {
  const editor = app.editor;
  if (!editor) return;
  const { freeSet, painted, parts } = app.settings;
  const active = freeSet === 'parts'
    ? parts.map((vertices, p) => ({ number: p + 1, vertices })).filter((part) => part.vertices.length > 0) : [];
  try {
    editor.setFreeSet({ cage: freeSet === 'painted' ? painted : freeSet === 'all' ? 'all' : 'minus-held' });
    editor.setParts(active.map((part) => part.vertices));
    app.parts = active.map((part) => part.number);
    app.partReferences = active.length ? Array.from(editor.partVolumes()) : null;
  } catch (e) {
    app.parts = [];
    app.partReferences = null;
    showError(`The free set could not be set: ${e.message}`);
  }
  showCageMarks();
  updateReadouts();
}

/** Painted handles (paint tool or painted free set) or the parts' colours (assign tool or parts). */
function showCageMarks() {
  const { tool, freeSet, painted, parts } = app.settings;
  const marks = new Map();
  const showParts = tool === 'assign' || (tool !== 'paint' && freeSet === 'parts');
  const showPainted = tool === 'paint' || (tool !== 'assign' && freeSet === 'painted');
  if (showParts) parts.forEach((list, p) => list.forEach((v) => marks.set(app.cageIndex.get(v), PART_COLORS[p % PART_COLORS.length])));
  else if (showPainted) for (const v of painted) marks.set(app.cageIndex.get(v), PAINT_COLOR);
  app.viewer.setMarks(marks);
}

function toolNotice() {
  const { tool } = app.settings;
  const text = tool === 'paint' ? 'Painting: click or drag over handles to add them to the free set or take them out.'
    : tool === 'assign' ? 'Assigning: click or drag over handles to put them in the chosen part or take them out.' : '';
  if (text || /^(Painting|Assigning):/.test($('notice').textContent)) notice(text);
}

/** A paint stroke passes over handle `index` (the first decides: add or remove). */
function paintHandle(index, first) {
  const s = app.settings;
  const vertex = app.cageVertices[index];
  if (s.tool === 'paint') {
    const painted = new Set(s.painted);
    if (first || !app.stroke) app.stroke = { add: !painted.has(vertex) };
    if (app.stroke.add) painted.add(vertex);
    else painted.delete(vertex);
    s.painted = [...painted];
  } else {
    const p = Math.min(MAX_PARTS, Math.max(1, Math.round(s.part))) - 1;
    if (first || !app.stroke) app.stroke = { add: !s.parts[p].includes(vertex) };
    s.parts = s.parts.map((list, q) => (app.stroke.add || q === p ? list.filter((v) => v !== vertex) : list));
    if (app.stroke.add) s.parts[p] = [...s.parts[p], vertex];
  }
  applyFreeSet();
}

// ---- layers: the level-l approximation and the detail vectors -----------------------------------------

function layersShown() {
  return app.settings.showApprox || app.settings.showDetails;
}

function applyViewLayers() {
  app.viewer.setLayers({
    mesh: app.settings.showMesh, cage: app.settings.showCage,
    approx: app.settings.showApprox, details: app.settings.showDetails,
  });
}

/**
 * The level-l approximation of the current shape: its analysis at level min(l, e) with the details
 * of levels >= l (the vertices born after level l) set to zero, synthesized (both by the core); the
 * detail vectors go from it to the fine positions.
 */
function updateLayers() {
  app.layers.dirty = false;
  if (!app.editor || !layersShown()) {
    updateLayerReadout();
    return;
  }
  const started = performance.now();
  const { mr, depths, info } = app.model;
  const l = Math.max(0, Math.min(info.levels, Math.round(app.settings.approxLevel)));
  const options = { level: Math.min(l, app.settings.level), scheme: app.settings.scheme, alpha: ALPHA, beta: BETA };
  const fine = app.editor.positions();
  const coefficients = mr.analyze(fine, options);
  for (let i = 0; i < depths.length; i++)
    if (depths[i] > l) coefficients[3 * i] = coefficients[3 * i + 1] = coefficients[3 * i + 2] = 0;
  const approx = mr.synthesize(coefficients, options);
  if (app.settings.showApprox) app.viewer.updateApprox(approx);
  if (app.settings.showDetails) app.viewer.updateDetails(approx, fine);
  const ms = performance.now() - started;
  app.layers.level = l;
  app.layers.updates++;
  app.layers.lastMs = ms;
  pushStat(app.stats.layers, ms);
  updateLayerReadout();
}

function editOptions() {
  return { tolerance: app.settings.tolerance, preserve: app.settings.preserve };
}

/** Puts the cage back where a snapshot had it (details unchanged: the shape comes back). */
function restoreCage(cage) {
  app.editor.deformCage(cage, app.heldAll, { preserve: false });
  app.lastReport = null;
  showEditorState();
}

// ---- dragging -------------------------------------------------------------------------------------

const dragHandlers = {
  pick(index, shiftKey) {
    if (!app.ready) return null;
    if (shiftKey) {
      if (app.selection.has(index)) {
        app.selection.delete(index);
        app.viewer.setSelection(app.selection);
        return null;
      }
      app.selection.add(index);
    } else if (!app.selection.has(index)) {
      app.selection = new Set([index]);
    }
    app.viewer.setSelection(app.selection);
    return [...app.selection];
  },
  dragStart(handles) {
    const before = app.editor.cagePositions();
    const held = new Uint8Array(app.cageSize);
    for (const h of handles) held[h] = 1;
    app.drag = { handles, held, before };
  },
  drag(delta, eventTime) {
    const drag = app.drag;
    if (!drag) return;
    const started = performance.now();
    const target = app.editor.cagePositions();
    for (const h of drag.handles)
      for (let k = 0; k < 3; k++) target[3 * h + k] = drag.before[3 * h + k] + delta[k];
    try {
      app.lastReport = app.editor.deformCage(target, drag.held, editOptions());
    } catch (e) {
      // e.g. a boundary vertex of an open mesh: it stays fixed. The drag ends and the cage goes back.
      showError(`This edit is not possible: ${e.message}`);
      app.dragger.cancel();
      return;
    }
    app.viewer.updateMesh(app.editor.positions());
    app.viewer.updateCage(app.editor.cagePositions());
    if (layersShown()) {
      // Every step while cheap, else once the drag ends.
      app.layers.deferred = app.layers.lastMs !== null && app.layers.lastMs > LAYER_BUDGET_MS;
      if (app.layers.deferred) app.layers.dirty = true;
      else updateLayers();
    }
    app.lastStepMs = performance.now() - started;
    pushStat(app.stats.steps, app.lastStepMs);
    app.pendingInput ??= eventTime;
    updateReadouts();
  },
  dragEnd() {
    const drag = app.drag;
    app.drag = null;
    if (!drag) return;
    const after = app.editor.cagePositions();
    if (after.some((v, i) => v !== drag.before[i])) app.history.push(drag.before, after);
    if (app.layers.dirty) updateLayers();
    saveSoon();
  },
  dragCancel() {
    const drag = app.drag;
    app.drag = null;
    if (drag) restoreCage(drag.before);
  },
  painting: () => app.ready && app.editor !== null && app.settings.tool !== 'drag',
  paint: (index, first) => paintHandle(index, first),
  paintEnd() {
    app.stroke = null;
    saveSoon();
  },
  boxSelect(indices) {
    for (const i of indices) app.selection.add(i);
    app.viewer.setSelection(app.selection);
  },
  clickEmpty() {
    if (app.selection.size === 0) return;
    app.selection.clear();
    app.viewer.setSelection(app.selection);
  },
};

function pushStat(list, value) {
  list.push(value);
  if (list.length > 2000) list.splice(0, list.length - 2000);
}

function undo() {
  if (app.drag || !app.editor) return;
  const step = app.history.undo();
  if (!step) return;
  restoreCage(step.before);
  saveSoon();
}

function redo() {
  if (app.drag || !app.editor) return;
  const step = app.history.redo();
  if (!step) return;
  restoreCage(step.after);
  saveSoon();
}

// ---- theta: memory, IndexedDB, worker -------------------------------------------------------------

function currentThetaKey() {
  return thetaKey({
    fingerprint: app.model.fingerprint, scheme: app.settings.scheme, alpha: ALPHA, beta: BETA, level: app.settings.level,
  });
}

function cancelTheta() {
  app.theta.generation++;
  app.jobs.cancel();
  showProgress(null);
}

/** source: 'computed' | 'cache' | null; pending: null source while theta is on its way (else 'none'). */
function setThetaState(source, status, pending = true) {
  app.theta.source = source;
  app.theta.pending = source === null && pending;
  app.theta.status = status;
  updateThetaReadout();
}

/** Hands theta to the editor; false (and the reason) when the core refuses it. */
function useTheta(theta) {
  try {
    app.editor.useTheta(theta);
    return { ok: true };
  } catch (e) {
    return { ok: false, reason: e.message };
  }
}

function thetaArrived(source, theta, started) {
  app.theta.memory.set(app.theta.key, { theta, source });
  const info = theta.info();
  setThetaState(source, `${thetaName(info.level)}: ${(info.nnzStored / 1e6).toFixed(2)}M entries, ` +
    `${(info.bytes / 2 ** 20).toFixed(1)} MB, ${Math.round(performance.now() - started)} ms`);
  app.stats.thetaReadyAt ??= performance.now();
  updateReadouts();
}

/**
 * Puts theta^e of the current model, scheme and level into the editor: from memory, from the cache
 * or from the worker. A cache lookup at start-up takes a few hundred ms, so when the cache probably
 * has nothing (no session said so) the worker starts at once beside the lookup, and a hit cancels it.
 */
async function requestTheta() {
  cancelTheta();
  const generation = app.theta.generation;
  const stale = () => generation !== app.theta.generation;
  const key = currentThetaKey();
  app.theta.key = key;
  const started = performance.now();

  // The tensor when it fits, the matrix-free gradient otherwise (the core's estimate, cheap).
  const estimate = app.model.mr.estimateTheta({ level: app.settings.level, scheme: app.settings.scheme });
  if (!estimate.fits) {
    setThetaState(null, `not computed: ${thetaName(app.settings.level)} would need about ` +
      `${Math.round(estimate.bytes / 2 ** 20)} MB and ${(estimate.milliseconds / 1000).toFixed(0)} s; editing runs matrix-free`, false);
    return;
  }

  const inMemory = app.theta.memory.get(key);
  if (inMemory && useTheta(inMemory.theta).ok) {
    thetaArrived(inMemory.source, inMemory.theta, started);
    return;
  }
  setThetaState(null, app.cache?.available ? 'looking in the cache…' : '');

  let job = null;
  if (app.cache?.available) {
    const prefetched = app.theta.prefetch?.key === key ? app.theta.prefetch.bytes : null;
    app.theta.prefetch = null;
    if (!prefetched) job = startJob(generation);
    const lookup = performance.now();
    const bytes = (await prefetched) ?? (await app.cache.get(key));
    app.stats.cacheLookupMs ??= performance.now() - lookup;
    if (stale()) return;
    if (bytes) {
      let theta = null, problem;
      try {
        const read = performance.now();
        theta = app.mrvol.readTheta(bytes);
        const use = performance.now();
        const used = useTheta(theta);
        app.stats.cacheLoad = { get: read - lookup, readTheta: use - read, useTheta: performance.now() - use };
        if (!used.ok) problem = used.reason;
      } catch (e) {
        problem = e.message;
      }
      if (!problem) {
        if (job) app.jobs.cancel();
        showProgress(null);
        thetaArrived('cache', theta, started);
        return;
      }
      theta?.delete();
      notice(`The cached θ was unusable (${problem}): it was deleted and is being recomputed.`);
      await app.cache.delete(key);
      refreshCacheList();
      if (stale()) return;
    }
  }
  finishJob(generation, key, started, job ?? startJob(generation));
}

/** Posts the theta job to the worker. Resolves to { result } or { error }; never rejects. */
function startJob(generation) {
  const stale = () => generation !== app.theta.generation;
  const { level, scheme } = app.settings;
  setThetaState(null, 'computing in a worker (editing runs matrix-free meanwhile)');
  showProgress(0, `Computing ${thetaName(level)} (${scheme})`);
  const posted = performance.now();
  return app.jobs.compute({
    meshKey: app.model.fingerprint,
    positions: app.model.mr.positions(),
    faces: app.model.faces,
    level, scheme, alpha: ALPHA, beta: BETA,
  }, (fraction) => {
    if (!stale()) showProgress(fraction, `Computing ${thetaName(level)} (${scheme}) ${Math.round(fraction * 100)}%`);
  }).then((result) => ({ result, posted }), (error) => ({ error }));
}

async function finishJob(generation, key, started, job) {
  const stale = () => generation !== app.theta.generation;
  const { result, posted, error } = await job;
  if (stale()) return;
  showProgress(null);
  if (error) {
    if (error.cancelled) setThetaState(null, 'cancelled: editing runs matrix-free', false);
    else setThetaState(null, `failed: ${error.message}; editing runs matrix-free`, false);
    return;
  }
  const received = performance.now();
  let theta;
  try {
    theta = app.mrvol.readTheta(result.bytes);
  } catch (e) {
    setThetaState(null, `the worker's θ was unreadable (${e.message}); editing runs matrix-free`, false);
    return;
  }
  const used = useTheta(theta);
  if (!used.ok) {
    theta.delete();
    setThetaState(null, `θ was refused (${used.reason}); editing runs matrix-free`, false);
    return;
  }
  app.stats.thetaMs = result.ms;
  app.stats.thetaJob = { roundTrip: received - posted, ...result.timings, readAndUse: performance.now() - received };
  thetaArrived('computed', theta, started);
  if (app.cache?.available) {
    const stored = await app.cache.put(key, result.bytes, { model: app.model?.name });
    if (!stored.ok) {
      notice(`θ is not cached: ${stored.reason}. Editing goes on; θ will be computed again next time.`);
      $('cache-status').textContent = `IndexedDB (the last write failed: ${stored.reason})`;
    }
    refreshCacheList();
  }
}

async function refreshCacheList() {
  if (!app.cache?.available) {
    app.panel.showCache([], `IndexedDB unavailable (${app.cache?.reason ?? 'not opened'}): no cache`);
    return;
  }
  app.panel.showCache(await app.cache.list());
}

// ---- actions from the panel, the keyboard, drops ---------------------------------------------------

function pickFile() {
  $('open-file').value = '';
  $('open-file').click();
}

async function openFile(file) {
  if (!file) return;
  await openModel({ kind: 'file', name: file.name, file });
}

function download(text, name, testid) {
  const blob = new Blob([text], { type: 'text/plain' });
  const link = document.createElement('a');
  link.href = URL.createObjectURL(blob);
  link.download = name;
  link.dataset.testid = testid;
  document.body.appendChild(link);
  link.click();
  setTimeout(() => {
    URL.revokeObjectURL(link.href);
    link.remove();
  }, 1000);
}

function exportObj() {
  if (!app.editor) return;
  const text = app.mrvol.writeObj({ positions: app.editor.positions(), faces: app.model.faces });
  download(text, `${app.model.name.replace(/\.obj$/i, '')}-edited.obj`, 'export-link');
}

/** The level-e cage as its own OBJ: cage positions in cage order, the level-e triangles. */
function exportCage() {
  if (!app.editor) return;
  const cageIndex = new Map(Array.from(app.editor.cageVertices(), (v, i) => [v, i]));
  const faces = Uint32Array.from(app.model.mr.levelFaces(app.editor.level), (v) => cageIndex.get(v));
  const text = app.mrvol.writeObj({ positions: app.editor.cagePositions(), faces });
  download(text, `${app.model.name.replace(/\.obj$/i, '')}-cage-level${app.editor.level}.obj`, 'export-cage-link');
}

async function reset() {
  clearSession();
  Object.assign(app.settings, DEFAULT_SETTINGS, { model: app.model?.name ?? DEFAULT_MODEL });
  app.viewer.setFlat(app.settings.flat);
  applyViewLayers();
  if (app.model) await openModel({ kind: app.model.kind, name: app.model.name, text: app.model.kind === 'file' ? app.model.text : undefined });
  app.panel.update();
}

const actions = {
  openSample: (name) => openModel({ kind: 'sample', name }),
  openFile: pickFile,
  exportObj,
  exportCage,
  reset,
  undo,
  redo,
  changeScheme: () => { if (app.editor) buildEditor(); saveSoon(); },
  changeLevel: () => { if (app.editor) buildEditor(); saveSoon(); },
  changePreserve: () => saveSoon(),
  changeTolerance: () => saveSoon(),
  changeFreeSet: () => {
    // The pointer follows: painting for the painted region, assigning for the parts.
    const mode = app.settings.freeSet;
    app.settings.tool = mode === 'painted' ? 'paint' : mode === 'parts' ? 'assign' : 'drag';
    app.panel.update();
    app.panel.showModeControls();
    toolNotice();
    applyFreeSet();
    saveSoon();
  },
  changeTool: () => {
    app.panel.showModeControls();
    toolNotice();
    if (app.editor) showCageMarks();
    saveSoon();
  },
  clearPainted: () => {
    app.settings.painted = [];
    applyFreeSet();
    saveSoon();
  },
  clearParts: () => {
    app.settings.parts = Array.from({ length: MAX_PARTS }, () => []);
    applyFreeSet();
    saveSoon();
  },
  changeView: () => {
    app.viewer.setFlat(app.settings.flat);
    applyViewLayers();
    saveSoon();
  },
  changeLayers: () => {
    applyViewLayers();
    updateLayers();
    saveSoon();
  },
  setReference: () => {
    if (!app.editor) return;
    app.editor.setReferenceVolume(app.editor.volume());
    if (app.parts.length) applyFreeSet(); // the parts' references too
    updateReadouts();
    saveSoon();
  },
  recomputeTheta: async () => {
    if (!app.model) return;
    const key = currentThetaKey();
    app.theta.memory.get(key)?.theta.delete();
    app.theta.memory.delete(key);
    app.editor.useMatrixFree();
    await app.cache?.delete(key);
    requestTheta();
  },
  refreshCache: refreshCacheList,
  clearCache: async () => {
    await app.cache?.clear();
    refreshCacheList();
  },
};

function onKeyDown(e) {
  const target = e.target;
  if (target instanceof HTMLElement && (target.isContentEditable || /^(INPUT|TEXTAREA|SELECT)$/.test(target.tagName)) &&
      target.type !== 'checkbox')
    return;
  const ctrl = e.ctrlKey || e.metaKey;
  if (e.key === 'Escape') {
    if (!app.dragger.cancel() && app.selection.size) {
      app.selection.clear();
      app.viewer.setSelection(app.selection);
    }
  } else if (ctrl && (e.key === 'z' || e.key === 'Z')) {
    e.preventDefault();
    if (e.shiftKey) redo();
    else undo();
  } else if (ctrl && (e.key === 'y' || e.key === 'Y')) {
    e.preventDefault();
    redo();
  }
}

function setUpDrop() {
  const hint = $('drop-hint');
  let depth = 0;
  const hasFiles = (e) => [...(e.dataTransfer?.types ?? [])].includes('Files');
  window.addEventListener('dragenter', (e) => {
    if (!hasFiles(e)) return;
    depth++;
    hint.hidden = false;
  });
  window.addEventListener('dragleave', () => {
    depth = Math.max(0, depth - 1);
    if (depth === 0) hint.hidden = true;
  });
  window.addEventListener('dragover', (e) => {
    if (hasFiles(e)) e.preventDefault();
  });
  window.addEventListener('drop', (e) => {
    e.preventDefault();
    depth = 0;
    hint.hidden = true;
    openFile(e.dataTransfer?.files?.[0]);
  });
}

// ---- read-only hook for tests and benchmarks --------------------------------------------------------

function installDebugHook() {
  const hook = {
    /** Handle (cage) index -> [x, y] in CSS pixels of the page's viewport (what page.mouse uses). */
    cageScreenPositions() {
      if (!app.editor) return [];
      const rect = app.viewer.canvas.getBoundingClientRect();
      const screen = app.viewer.projectHandles();
      const out = [];
      for (let i = 0; i < app.cageSize; i++) out.push([rect.left + screen[2 * i], rect.top + screen[2 * i + 1]]);
      return out;
    },
    volume: () => app.editor?.volume() ?? null,
    referenceVolume: () => app.editor?.referenceVolume() ?? null,
    thetaSource: () => app.theta.source,
    thetaKey: () => app.theta.key,
    modelName: () => app.model?.name ?? null,
    cageSize: () => app.cageSize,
    gradientPath: () => app.editor?.path() ?? null,
    historySize: () => app.history.size,
    /** The core's report of the last drag step (volumes, iterations, path), or null. */
    lastReport: () => (app.lastReport ? { ...app.lastReport, partVolumes: undefined, partReferences: undefined } : null),
    /** Cage positions (world), 3 per handle, cage order. */
    cagePositions: () => (app.editor ? Array.from(app.editor.cagePositions()) : []),
    selection: () => [...app.selection],
    settings: () => ({ ...app.settings }),
    ready: () => app.ready,
    thetaReady: () => app.ready && app.theta.source !== null && app.editor?.path() === 'tensor',
    /** ms since navigation: first drag-ready frame, theta in use; step and input-to-frame times. */
    stats: () => ({
      ...app.stats, steps: [...app.stats.steps], frames: [...app.stats.frames], renders: [...app.stats.renders],
      layers: [...app.stats.layers],
    }),
    /** The layers: shown or not, what the viewer draws (counts), the level l, updates and their cost. */
    layers: () => {
      const drawn = app.viewer.overlayInfo();
      return {
        approx: { shown: app.settings.showApprox, ...drawn.approx },
        details: { shown: app.settings.showDetails, ...drawn.details },
        level: app.layers.level, updates: app.layers.updates, lastMs: app.layers.lastMs, deferred: Boolean(app.layers.deferred),
      };
    },
    /** The free set: mode, pointer tool, painted handles and parts' handles (cage indices, sorted). */
    freeSet: () => {
      const toCage = (list) => list.map((v) => app.cageIndex?.get(v)).filter((i) => i !== undefined).sort((a, b) => a - b);
      return {
        mode: app.settings.freeSet, tool: app.settings.tool,
        painted: toCage(app.settings.painted), parts: app.settings.parts.map(toCage),
      };
    },
    /** Localized preservation: part numbers, their volumes now and their references; null without parts. */
    partVolumes: () => (app.editor && app.parts.length ? {
      parts: [...app.parts], volumes: Array.from(app.editor.partVolumes()), references: [...app.partReferences],
    } : null),
  };
  Object.defineProperty(window, 'mrvolDebug', { value: Object.freeze(hook), writable: false, configurable: false });
}

// ---- start --------------------------------------------------------------------------------------------

async function start() {
  app.stats.scriptAt = performance.now();
  installDebugHook();
  // The core, the cache and the model file load in parallel.
  const coreLoading = loadMrvol();
  const cacheOpening = ThetaCache.open();
  const view = $('view');
  app.viewer = new Viewer(view);
  app.viewer.onFrame = (renderMs) => {
    if (app.awaitingFrame) {
      app.awaitingFrame = false;
      app.ready = true;
      app.stats.readyAt ??= performance.now();
    }
    if (app.pendingInput !== null) {
      pushStat(app.stats.frames, performance.now() - app.pendingInput);
      pushStat(app.stats.renders, renderMs);
      app.pendingInput = null;
    }
  };
  app.dragger = new CageDragger(app.viewer, view, dragHandlers);

  const session = loadSession();
  const params = new URLSearchParams(location.search);
  const urlModel = params.get('model');
  if (session?.settings) {
    for (const key of Object.keys(DEFAULT_SETTINGS))
      if (typeof session.settings[key] === typeof DEFAULT_SETTINGS[key]) app.settings[key] = session.settings[key];
  }
  const useSession = session && (urlModel === null || (session.model.kind === 'sample' && session.model.name === urlModel)) &&
    (session.model.kind === 'sample' || typeof session.model.text === 'string');

  app.panel = createPanel({ settings: app.settings, samples: sampleModels, actions });
  app.viewer.setFlat(app.settings.flat);
  app.viewer.precompile(); // while the core, the cache and the model load
  $('error-close').addEventListener('click', clearError);
  $('theta-cancel').addEventListener('click', () => {
    const generation = app.theta.generation;
    app.jobs.cancel();
    if (generation === app.theta.generation) showProgress(null);
  });
  $('open-file').addEventListener('change', (e) => openFile(e.target.files?.[0]));
  // Capture phase: lil-gui stops keydown events of its controls from bubbling.
  window.addEventListener('keydown', onKeyDown, { capture: true });
  setUpDrop();

  let restore = null, source;
  if (useSession) {
    try {
      restore = {
        fingerprint: session.fingerprint,
        positions: session.positions ? decodeFloat64(session.positions) : null,
        reference: session.reference,
      };
    } catch {
      restore = null;
    }
    source = session.model.kind === 'sample'
      ? { kind: 'sample', name: session.model.name }
      : { kind: 'file', name: session.model.name, text: session.model.text };
  } else {
    source = { kind: 'sample', name: urlModel ?? DEFAULT_MODEL };
  }
  if (source.kind === 'sample') source.prefetch = fetchSample(source.name).catch((e) => e);
  if (useSession && typeof session.fingerprint === 'string') {
    // The session says which theta the editor will want: read it while the core loads.
    const key = thetaKey({
      fingerprint: session.fingerprint, scheme: app.settings.scheme, alpha: ALPHA, beta: BETA, level: app.settings.level,
    });
    app.theta.prefetch = { key, bytes: cacheOpening.then((cache) => cache.get(key)) };
  }

  try {
    app.mrvol = await coreLoading;
  } catch (e) {
    showError(`The WebAssembly core could not be loaded: ${e.message}`);
    return;
  }
  app.stats.coreAt = performance.now();
  // Without a session theta is likely not cached: the worker loads its copy of the core while the
  // model opens. (With one, the cache most likely has it, and the worker would compete for the CPU.)
  if (!app.theta.prefetch) app.jobs.prepare();
  app.cache = await cacheOpening;
  app.stats.cacheAt = performance.now();
  $('cache-status').textContent = app.cache.available ? 'IndexedDB'
    : `none: ${app.cache.reason}; θ is computed on every load`;
  refreshCacheList();
  applyViewLayers();
  if (!(await openModel(source, restore)) && !app.model && source.name !== DEFAULT_MODEL) {
    const why = $('error-text').textContent;
    if (await openModel({ kind: 'sample', name: DEFAULT_MODEL })) showError(`${why}\nOpened ${DEFAULT_MODEL} instead.`);
  }
  applyViewLayers();
  window.addEventListener('pagehide', saveNow);
}

// #learn/... and #demo/...: the teaching views (web/learn/) instead of the editor.
if (learnRoute()) startLearn();
else {
  watchForLearnRoutes();
  start();
}
