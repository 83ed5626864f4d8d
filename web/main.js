// The mrvol web editor: wires the editing session (lib/three/session.mjs: model, editor, history,
// free set, theta in use), the view and the drag controls, the panel, the readouts, theta's sources
// (memory, IndexedDB, worker), the stored session, the remesh offer and the file input. Every
// geometric quantity comes from the core; the modules here move arrays between it and the screen.
import { sampleModels } from 'virtual:mrvol-models';
import { DEFAULT_SCHEME } from '../lib/api.mjs';
import { EditingSession } from '../lib/three/session.mjs';
import { loadMrvol } from './mrvol.js';
import { Viewer } from './viewer.js';
import { CageDragger } from './drag.js';
import { ThetaCache, thetaKey } from './theta-cache.js';
import { ThetaJobs } from './theta-jobs.js';
import { ThetaSource } from './theta-source.js';
import { Layers } from './layers.js';
import { loadSession, saveSession, clearSession, decodeFloat64 } from './session.js';
import { createPanel } from './panel.js';
import { FreeSetTools } from './free-set-ui.js';
import { fetchSample, sourceText, openObj } from './models.js';
import { setUpFileInput, setUpDrop, download } from './file-input.js';
import { offerRemesh, hideRemeshOffer } from './remesh-offer.js';
import { showError, clearError, errorText, notice, showCacheStatus, followSession } from './readouts.js';
import { installDebugHook } from './debug-hook.js';
import { learnRoute, startLearn, watchForLearnRoutes } from './learn/router.js';

const DEFAULT_MODEL = 'spiky-ball';
// painted: the painted region (caller's indices of cage vertices); parts[p]: those of part p + 1.
// Both are replaced, never mutated.
const DEFAULT_SETTINGS = Object.freeze({
  model: DEFAULT_MODEL, scheme: DEFAULT_SCHEME.scheme, level: 0, preserve: true, freeSet: 'minus-held', tolerance: 1e-6,
  flat: true, showMesh: true, showCage: true,
  tool: 'drag', part: 1, painted: Object.freeze([]), parts: Object.freeze([]),
  showApprox: false, approxLevel: 0, showDetails: false,
});

const app = {
  mrvol: null,
  session: null,
  viewer: null,
  panel: null,
  dragger: null,
  theta: null,   // ThetaSource
  layers: null,
  freeSet: null, // FreeSetTools
  settings: { ...DEFAULT_SETTINGS },
  model: null,   // where the model came from: { name, kind: 'sample' | 'file', text }
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
 * Opens an OBJ (web/models.js says whether it can be edited); on success replaces the current model
 * (and returns true), otherwise shows why, offers remeshing when that would help, and keeps the
 * current one (false). restore: { positions: Float64Array, reference, fingerprint } from a stored session.
 */
function openModelText({ name, kind, text }, restore = null) {
  const { session } = app;
  let mr, info;
  try {
    ({ mr, info } = openObj(app.mrvol, text));
  } catch (e) {
    showError(`Could not open ${name}: ${e.message}`);
    if (e.offer) offerRemesh({ name, text }, { repair: e.offer === 'repair', open: openModel, notice });
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
    text = await sourceText(source);
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
    app.freeSet.keepCageMarks();
    app.layers.update();
    if (frameNext) app.viewer.frameAll();
    frameNext = false;
    app.theta.request();
  });
  session.addEventListener('change', ({ detail }) => {
    if (detail.reason === 'step') return; // the drag handler draws and times its steps
    app.viewer.updateMesh(session.positions());
    app.viewer.updateCage(session.cagePositions());
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
    const drawing = performance.now();
    app.viewer.updateMesh(session.positions());
    app.viewer.updateCage(session.cagePositions());
    app.layers.afterStep();
    // The step as bench/web.mjs times it: the correction (the session's time) plus positions read back
    // and geometry updated (not the readouts, which follow the session's change event).
    pushStat(app.stats.steps, session.lastStepMs + performance.now() - drawing);
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
  painting: () => app.ready && app.session.editor !== null && app.freeSet.painting,
  paint: (index, first) => app.freeSet.paint(index, first),
  paintEnd() {
    app.freeSet.endStroke();
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
  changeFreeSet: () => { app.freeSet.changeMode(); saveSoon(); },
  changeTool: () => { app.freeSet.changeTool(); saveSoon(); },
  clearPainted: () => { app.freeSet.clearPainted(); saveSoon(); },
  clearParts: () => { app.freeSet.clearParts(); saveSoon(); },
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
  app.freeSet = new FreeSetTools({ session, viewer: app.viewer, panel: app.panel, settings: app.settings, defaults: DEFAULT_SETTINGS });
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
