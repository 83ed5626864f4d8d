// The mrvol web editor: wires the editing session (lib/three/session.mjs: model, editor, history,
// free set, theta in use), the view and the drag controls, the panel, the readouts, theta's sources
// (memory, IndexedDB, worker), the stored session, the remesh offer and the file input. Every
// geometric quantity comes from the core; the modules here move arrays between it and the screen.
import { sampleModels } from 'virtual:mrvol-models';
import { DEFAULT_SCHEME } from '../lib/api.mjs';
import { EditingSession, FREE_SET_MODES, MAX_PARTS } from '../lib/three/session.mjs';
import { loadMrvol } from './mrvol.js';
import { Viewer } from './viewer.js';
import { CageDragger } from './drag.js';
import { ThetaCache, thetaKey } from './theta-cache.js';
import { ThetaJobs } from './theta-jobs.js';
import { ThetaSource } from './theta-source.js';
import { Layers } from './layers.js';
import { loadSession, saveSession, clearSession, decodeFloat64 } from './session.js';
import { createPanel, TOOLS } from './panel.js';
import { fetchSample } from './models.js';
import { setUpFileInput, setUpDrop, download } from './file-input.js';
import { offerRemesh, hideRemeshOffer } from './remesh-offer.js';
import { showError, clearError, errorText, notice, noticeText, showCacheStatus, followSession } from './readouts.js';
import { installDebugHook } from './debug-hook.js';
import { learnRoute, startLearn, watchForLearnRoutes } from './learn/router.js';

const DEFAULT_MODEL = 'spiky-ball';
// Without 1-to-4 splits every vertex is a handle: fine for a small base mesh, not for a big one.
const MAX_FLAT_VERTICES = 64;
// painted: the painted region (caller's indices of cage vertices); parts[p]: those of part p + 1.
// Both are replaced, never mutated.
const DEFAULT_SETTINGS = Object.freeze({
  model: DEFAULT_MODEL, scheme: DEFAULT_SCHEME.scheme, level: 0, preserve: true, freeSet: 'minus-held', tolerance: 1e-6,
  flat: true, showMesh: true, showCage: true,
  tool: 'drag', part: 1, painted: Object.freeze([]), parts: Object.freeze([]),
  showApprox: false, approxLevel: 0, showDetails: false,
});
const PAINT_COLOR = '#bf3989';
const PART_COLORS = ['#cf222e', '#8250df', '#0e8a94', '#9a6700', '#bf3989', '#57606a', '#24292f', '#7d8a00'];

const app = {
  mrvol: null,
  session: null,
  viewer: null,
  panel: null,
  dragger: null,
  theta: null,   // ThetaSource
  layers: null,
  settings: { ...DEFAULT_SETTINGS },
  model: null,   // where the model came from: { name, kind: 'sample' | 'file', text }
  stroke: null,  // the paint stroke going on: { add }
  selection: new Set(),
  ready: false,
  awaitingFrame: false,
  loadGeneration: 0,
  pickFile: null,
  // ms since navigation start: script running, core loaded, model opened, first drag-ready frame,
  // theta in use; the worker's computeTheta time; per drag step and per frame (input to frame, render).
  stats: {
    scriptAt: null, coreAt: null, cacheAt: null, modelAt: null, readyAt: null, thetaReadyAt: null, thetaMs: null,
    steps: [], frames: [], renders: [], layers: [],
  },
  pendingInput: null,
};

function pushStat(list, value) {
  list.push(value);
  if (list.length > 2000) list.splice(0, list.length - 2000);
}

// ---- the stored session ---------------------------------------------------------------------------

let saveTimer = null;
function saveSoon() {
  clearTimeout(saveTimer);
  saveTimer = setTimeout(saveNow, 150);
}

function saveNow() {
  clearTimeout(saveTimer);
  const { session } = app;
  if (!app.model || !session.editor) return;
  saveSession({
    model: app.model,
    settings: { ...app.settings },
    fingerprint: session.model.fingerprint,
    positions: session.positions(),
    reference: session.referenceVolume(),
  });
}

// ---- models ---------------------------------------------------------------------------------------

/**
 * Parses and checks an OBJ; on success replaces the current model (and returns true), otherwise
 * shows why, offers remeshing when that would help, and keeps the current one (false).
 * restore: { positions: Float64Array, reference, fingerprint } from a stored session.
 */
function openModelText({ name, kind, text }, restore = null) {
  const { mrvol, session } = app;
  let mr = null, info, read = false;
  try {
    const mesh = mrvol.readObj(text);
    read = true;
    mr = mrvol.openMesh(mesh);
    info = mr.info();
    if (info.levels === 0 && info.vertices > MAX_FLAT_VERTICES)
      throw new mrvol.MrvolError(
        `this mesh is not semi-regular: no 1-to-4 subdivision levels were found in its ${info.vertices} vertices, ` +
        'so it has no coarse cage to edit (mrvol edits meshes made by repeated 1-to-4 splits of a base mesh)');
  } catch (e) {
    const notSemiRegular = mr !== null && info?.levels === 0;
    // Read, but not a closed oriented 2-manifold (a raw scan: repeated faces, holes, pieces).
    const damaged = read && mr === null;
    mr?.delete();
    showError(`Could not open ${name}: ${e.message}`);
    if (notSemiRegular || damaged) offerRemesh({ name, text }, { repair: damaged, open: openModel, notice });
    return false;
  }
  clearError();
  hideRemeshOffer();
  notice('');
  app.theta.cancel();
  app.model = { name, kind, text };
  app.settings.model = name;
  const fits = restore && restore.fingerprint === mr.fingerprint();
  app.settings.level = Math.min(app.settings.level, info.levels);
  app.ready = false;
  session.level = app.settings.level;
  session.scheme = app.settings.scheme;
  session.open(mr, { name, own: true, restore: fits ? restore : null });  // emits model, editor
  app.settings.level = session.level;
  app.stats.modelAt ??= performance.now();
  app.awaitingFrame = true; // ready once the next frame (with this model) is drawn
  app.viewer.requestRender();
  saveSoon();
  return true;
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

// ---- the session's events: the view follows ---------------------------------------------------------

function followSessionInView(session) {
  let frameNext = false;
  session.addEventListener('model', () => {
    frameNext = true;
    app.viewer.setMesh(session.model.mr.positions(), session.model.faces);
    applyViewLayers();
    app.panel.setLevels(session.model.info.levels);
    app.panel.update();
  });
  session.addEventListener('editor', () => {
    app.selection.clear();
    app.viewer.setCage(session.cagePositions(), session.cageEdges());
    app.viewer.updateMesh(session.positions());
    keepCageMarks();
    app.layers.update();
    if (frameNext) app.viewer.frameAll();
    frameNext = false;
    app.theta.request();
  });
  session.addEventListener('change', ({ detail }) => {
    if (detail.reason === 'step') return; // the drag handler draws and times its steps
    app.viewer.updateMesh(session.positions());
    app.viewer.updateCage(session.cagePositions());
    if (detail.reason === 'free-set') showCageMarks();
    if (detail.reason === 'undo' || detail.reason === 'redo' || detail.reason === 'cancel') app.layers.update();
  });
  session.addEventListener('error', ({ detail }) => showError(detail.message));
}

/** Rebuilds the editor at the panel's scheme and level (the session keeps shape and reference). */
function rebuildEditor() {
  const { session, settings } = app;
  if (!session.editor) return;
  session.scheme = settings.scheme;
  session.setLevel(settings.level);  // rebuilds with the scheme too: emits editor
}

// ---- free set: painted region, parts ----------------------------------------------------------------

/** Hands the panel's free set to the session (it keeps only this cage's vertices). */
function applyFreeSet() {
  const { settings, session } = app;
  if (!session.editor) return;
  session.setFreeSet({ mode: settings.freeSet, painted: settings.painted, parts: settings.parts });
}

/** After a new cage: the panel's marks keep only its vertices. */
function keepCageMarks() {
  const { settings, session } = app;
  if (!TOOLS_LIST.includes(settings.tool)) settings.tool = DEFAULT_SETTINGS.tool;
  if (!FREE_SET_MODES.includes(settings.freeSet)) settings.freeSet = DEFAULT_SETTINGS.freeSet;
  session.setFreeSet({ mode: settings.freeSet, painted: settings.painted, parts: settings.parts });
  Object.assign(settings, { painted: session.freeSet.painted, parts: session.freeSet.parts });
  app.panel.showModeControls();
  toolNotice();
}
const TOOLS_LIST = Object.values(TOOLS);

/** Painted handles (paint tool or painted free set) or the parts' colours (assign tool or parts). */
function showCageMarks() {
  const { tool, freeSet, painted, parts } = app.settings;
  const cageIndex = app.session.cageIndex;
  const marks = new Map();
  const showParts = tool === 'assign' || (tool !== 'paint' && freeSet === 'parts');
  const showPainted = tool === 'paint' || (tool !== 'assign' && freeSet === 'painted');
  if (showParts) parts.forEach((list, p) => list.forEach((v) => marks.set(cageIndex.get(v), PART_COLORS[p % PART_COLORS.length])));
  else if (showPainted) for (const v of painted) marks.set(cageIndex.get(v), PAINT_COLOR);
  app.viewer.setMarks(marks);
}

function toolNotice() {
  const { tool } = app.settings;
  const text = tool === 'paint' ? 'Painting: click or drag over handles to add them to the free set or take them out.'
    : tool === 'assign' ? 'Assigning: click or drag over handles to put them in the chosen part or take them out.' : '';
  if (text || /^(Painting|Assigning):/.test(noticeText())) notice(text);
}

/** A paint stroke passes over handle `index` (the first decides: add or remove). */
function paintHandle(index, first) {
  const s = app.settings;
  const vertex = app.session.cageVertices[index];
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

function applyViewLayers() {
  app.viewer.setLayers({
    mesh: app.settings.showMesh, cage: app.settings.showCage,
    approx: app.settings.showApprox, details: app.settings.showDetails,
  });
}

// ---- dragging: the drag controls emit, the session edits ---------------------------------------------

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
    app.session.beginDrag(handles);
  },
  drag(delta, eventTime) {
    const { session } = app;
    if (!session.dragging) return;
    session.preserve = app.settings.preserve;
    session.tolerance = app.settings.tolerance;
    const report = session.dragBy(delta);
    if (!report) {
      app.dragger.cancel(); // refused: the session put the cage back and said why
      return;
    }
    app.viewer.updateMesh(session.positions());
    app.viewer.updateCage(session.cagePositions());
    app.layers.afterStep();
    pushStat(app.stats.steps, session.lastStepMs);
    app.pendingInput ??= eventTime;
  },
  dragEnd() {
    if (!app.session.dragging) return;
    app.session.endDrag();
    app.layers.afterDrag();
    saveSoon();
  },
  dragCancel() {
    app.session.cancelDrag();
  },
  painting: () => app.ready && app.session.editor !== null && app.settings.tool !== 'drag',
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

function undo() {
  if (app.session.undo()) saveSoon();
}

function redo() {
  if (app.session.redo()) saveSoon();
}

// ---- actions from the panel and the keyboard ---------------------------------------------------------

function exportObj() {
  const { session } = app;
  if (!session.editor) return;
  const text = app.mrvol.writeObj({ positions: session.positions(), faces: session.model.faces });
  download(text, `${app.model.name.replace(/\.obj$/i, '')}-edited.obj`, 'export-link');
}

/** The level-e cage as its own OBJ: cage positions in cage order, the level-e triangles. */
function exportCage() {
  const { session } = app;
  if (!session.editor) return;
  const faces = Uint32Array.from(session.model.mr.levelFaces(session.level), (v) => session.cageIndex.get(v));
  const text = app.mrvol.writeObj({ positions: session.cagePositions(), faces });
  download(text, `${app.model.name.replace(/\.obj$/i, '')}-cage-level${session.level}.obj`, 'export-cage-link');
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
  openFile: () => app.pickFile(),
  exportObj,
  exportCage,
  reset,
  undo,
  redo,
  changeScheme: () => { rebuildEditor(); saveSoon(); },
  changeLevel: () => { rebuildEditor(); saveSoon(); },
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
    if (app.session.editor) showCageMarks();
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
    app.layers.update();
    saveSoon();
  },
  setReference: () => {
    if (!app.session.editor) return;
    app.session.setReferenceVolume();
    saveSoon();
  },
  recomputeTheta: () => (app.session.editor ? app.theta.recompute() : undefined),
  refreshCache: () => app.theta.refreshCacheList(),
  clearCache: () => app.theta.clearCache(),
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

// ---- start --------------------------------------------------------------------------------------------

async function start() {
  app.stats.scriptAt = performance.now();
  installDebugHook(app);
  // The core, the cache and the model file load in parallel.
  const coreLoading = loadMrvol();
  const cacheOpening = ThetaCache.open();
  const view = document.getElementById('view');
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

  const stored = loadSession();
  const params = new URLSearchParams(location.search);
  const urlModel = params.get('model');
  if (stored?.settings) {
    for (const key of Object.keys(DEFAULT_SETTINGS))
      if (typeof stored.settings[key] === typeof DEFAULT_SETTINGS[key]) app.settings[key] = stored.settings[key];
  }
  const useStored = stored && (urlModel === null || (stored.model.kind === 'sample' && stored.model.name === urlModel)) &&
    (stored.model.kind === 'sample' || typeof stored.model.text === 'string');

  app.panel = createPanel({ settings: app.settings, samples: sampleModels, actions });
  app.viewer.setFlat(app.settings.flat);
  app.viewer.precompile(); // while the core, the cache and the model load
  document.getElementById('error-close').addEventListener('click', clearError);
  document.getElementById('theta-cancel').addEventListener('click', () => app.theta?.cancelJob());
  app.pickFile = setUpFileInput((file) => file && openModel({ kind: 'file', name: file.name, file }));
  // Capture phase: lil-gui stops keydown events of its controls from bubbling.
  window.addEventListener('keydown', onKeyDown, { capture: true });
  setUpDrop((file) => file && openModel({ kind: 'file', name: file.name, file }));

  let restore = null, source;
  if (useStored) {
    try {
      restore = {
        fingerprint: stored.fingerprint,
        positions: stored.positions ? decodeFloat64(stored.positions) : null,
        reference: stored.reference,
      };
    } catch {
      restore = null;
    }
    source = stored.model.kind === 'sample'
      ? { kind: 'sample', name: stored.model.name }
      : { kind: 'file', name: stored.model.name, text: stored.model.text };
  } else {
    source = { kind: 'sample', name: urlModel ?? DEFAULT_MODEL };
  }
  if (source.kind === 'sample') source.prefetch = fetchSample(source.name).catch((e) => e);
  let prefetch = null;
  if (useStored && typeof stored.fingerprint === 'string') {
    // The stored session says which theta the editor will want: read it while the core loads.
    const key = thetaKey({ fingerprint: stored.fingerprint, ...DEFAULT_SCHEME, scheme: app.settings.scheme, level: app.settings.level });
    prefetch = { key, bytes: cacheOpening.then((cache) => cache.get(key)) };
  }

  const jobs = new ThetaJobs();
  try {
    app.mrvol = await coreLoading;
  } catch (e) {
    showError(`The WebAssembly core could not be loaded: ${e.message}`);
    return;
  }
  app.stats.coreAt = performance.now();
  const session = new EditingSession(app.mrvol, {
    level: app.settings.level, scheme: app.settings.scheme, preserve: app.settings.preserve, tolerance: app.settings.tolerance,
  });
  app.session = session;
  app.theta = new ThetaSource(session, { jobs, stats: app.stats, showCache: (entries, note) => app.panel.showCache(entries, note) });
  app.theta.prefetch = prefetch;
  app.layers = new Layers(session, app.viewer, app.settings, (ms) => pushStat(app.stats.layers, ms));
  followSession(session);
  followSessionInView(session);
  // Without a stored session theta is likely not cached: the worker loads its copy of the core
  // while the model opens. (With one, the cache most likely has it, and the worker would compete
  // for the CPU.)
  if (!prefetch) jobs.prepare();
  const cache = await cacheOpening;
  app.theta.cache = cache;
  app.stats.cacheAt = performance.now();
  showCacheStatus(cache.available ? 'IndexedDB' : `none: ${cache.reason}; θ is computed on every load`);
  app.theta.refreshCacheList();
  applyViewLayers();
  if (!(await openModel(source, restore)) && !app.model && source.name !== DEFAULT_MODEL) {
    const why = errorText();
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
