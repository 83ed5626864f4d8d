// The mrvol web editor: wires the editing session (lib/three/session.mjs: model, editor, history,
// free set, theta in use), the view and the drag controls, the panel, the readouts, theta's sources
// (memory, IndexedDB, worker), the stored session, the remesh offer and the file input. Every
// geometric quantity comes from the core; the modules here move arrays between it and the screen.
import { sampleModels } from 'virtual:mrvol-models';
import { DEFAULT_SCHEME } from '../lib/api.mjs';
import { EditingSession } from '../lib/three/session.mjs';
import { loadPageMrvol } from './mrvol.js';
import { Viewer } from './viewer.js';
import { CageDragger } from './drag.js';
import { ThetaCache, thetaKey } from './theta-cache.js';
import { ThetaJobs } from './theta-jobs.js';
import { ThetaSource } from './theta-source.js';
import { Layers } from './layers.js';
import { loadSession, saveSession, clearSession, decodeFloat64 } from './session.js';
import { SessionStore, sessionId } from './session-store.js';
import { createPanel } from './panel.js';
import { FreeSetTools } from './free-set-ui.js';
import { fetchSample, sourceText, openParsed, openQuadObj, firstFaceCorners, baseNameOf } from './models.js';
import { readMeshFile, cancelFileRead, showFileProgress, keepFileWorkerReady, startFileWorker, onFileProgressShown } from './file-open.js';
import { pageStage, addStage, openStages } from './open-stages.js';
import { rebuildsInWorker, rebuildInWorker, WORKER_THETA_BYTES } from './editor-rebuild.js';
import { setUpFileInput, setUpDrop, download } from './file-input.js';
import { sidecarHint } from './gltf-sidecars.js';
import { offerRemesh, hideRemeshOffer, cancelRemesh } from './remesh-offer.js';
import { showError, clearError, errorText, notice, showCacheStatus, showStorageProblem, followSession } from './readouts.js';
import { installDebugHook } from './debug-hook.js';
import { VolumeChart } from './volume-chart.js';
import { stepMultiplier } from './multiplier.js';
import { setUpKeyboardHandles } from './keyboard-handles.js';
import { SelfIntersectionChecker, MAX_FACES } from './self-intersection.js';
import { setUpBalance } from './balance.js';
import { shadowFaces } from './shadow-caster.js';
import { shareUrl, sharedState, decodeEdits, projectBlob, isProject, readProject, SHARE_PARAMS } from './share.js';
import { VIEWS } from './learn/router.js';
import { learnRoute, startLearn, watchForLearnRoutes } from './learn/router.js';

const DEFAULT_MODEL = 'spiky-ball';
// painted: the painted region (caller's indices of cage vertices); parts[p]: those of part p + 1.
// Both are replaced, never mutated.
const DEFAULT_SETTINGS = Object.freeze({
  model: DEFAULT_MODEL, scheme: DEFAULT_SCHEME.scheme, level: 0, preserve: true, freeSet: 'minus-held', tolerance: 1e-6,
  // 'polynomial': the editor's cage polynomial wherever theta^e would do (no tensor computed or handed
  // over); 'tensor': the paper's theta^e from the worker or the cache (?gradient=tensor)
  gradient: 'polynomial',
  flat: true, showMesh: true, showCage: true,
  tool: 'drag', part: 1, painted: Object.freeze([]), parts: Object.freeze([]),
  showApprox: false, approxLevel: 0, showDetails: false,
  keepBalance: false, surface: 'mesh', // web/balance.js: the centre of mass kept too; whose volume (mesh or limit)
});

const app = {
  mrvol: null,
  session: null,
  viewer: null,
  panel: null,
  dragger: null,
  theta: null,   // ThetaSource
  store: null,   // SessionStore (IndexedDB): the sessions of recent models
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
  chart: null,       // VolumeChart
  dragHandles: [],   // cage indices of the drag in progress
};

/**
 * Warns under the readouts when the surface intersects itself, or says that two pieces pass through
 * each other (checked after each edit, not during drags, in a worker). A crossing the model had when
 * it opened (a file's own, kept by the remesher) is said as such, without asking to undo it.
 */
let intersectionTimer = null;
const intersections = new SelfIntersectionChecker();
let crossedAtOpen = null; // whether the opened model crossed itself (null: not known yet)
function checkSelfIntersection({ detail } = {}) {
  const opening = detail?.reason === 'model';
  if (opening) crossedAtOpen = null;
  clearTimeout(intersectionTimer);
  intersectionTimer = setTimeout(async () => {
    const { session } = app;
    const warning = document.getElementById('self-intersection');
    if (!session.editor || session.dragging) return;
    // (a mesh over the check's limit is not copied: the positions are asked only when checked)
    const found = session.model.faces.length / 3 > MAX_FACES ? null : await intersections.check(session.positions(), session.model.faces);
    if (found === undefined) return; // a later check replaced it
    if (opening) crossedAtOpen = !!found?.intersects;
    const triangles = (pair) => `triangles ${pair[0]} and ${pair[1]}`;
    warning.textContent = found?.intersects
      ? crossedAtOpen
        ? `The surface intersects itself (${triangles(found.pair)}), as it did when opened: the volume counts the overlap with opposite signs.`
        : `The surface intersects itself (${triangles(found.pair)}): the volume counts the overlap with opposite signs. Undo or move the handles apart.`
      : found?.piecesOverlap
        ? `Two pieces pass through each other (${triangles(found.piecesOverlap)}): the volume kept is the sum of the pieces' volumes, their overlap counted in both.`
        : '';
    warning.dataset.checkedMs = found ? found.ms.toFixed(1) : '';
  }, 50);
}

function pushStat(list, value) {
  list.push(value);
  if (list.length > 2000) list.splice(0, list.length - 2000);
}

// ---- the stored session ---------------------------------------------------------------------------

let saveTimer = null, savePending = false;
// record id -> its saves sent to the store and not answered yet (one promise for all of them): what
// reads a record back waits for these first, or it reads the record as it was before the last edit
const savesUnderWay = new Map();

// Tabs of the app: each says which record it wrote (BroadcastChannel). A tab whose model's record
// another tab wrote keeps its own edits apart from then on (a copy, its own record) rather than
// writing over the other's; and a reload opens the record this tab wrote (sessionStorage), not the
// newest of all tabs.
const TAB_ID = globalThis.crypto?.randomUUID?.() ?? `${Date.now()}-${Math.random()}`;
const TAB_RECORD = 'mrvol-tab-record';
const otherTabs = typeof BroadcastChannel === 'function' ? new BroadcastChannel('mrvol-sessions') : null;
let otherTabWrote = false, persistAsked = false;
otherTabs?.addEventListener('message', ({ data }) => {
  if (data?.tab !== TAB_ID && app.model && data?.id === sessionId(app.model)) otherTabWrote = true;
});
function tabRecord() {
  try {
    return sessionStorage.getItem(TAB_RECORD);
  } catch {
    return null;
  }
}

function saveSoon() {
  clearTimeout(saveTimer);
  savePending = true;
  saveTimer = setTimeout(saveNow, 150);
}

function saveNow() {
  clearTimeout(saveTimer);
  savePending = false;
  const { session } = app;
  if (!app.model || !session.editor) return;
  // the first save of a big file: a stage of its opening (not of a rebuild begun meanwhile)
  const started = performance.now(), timed = app.timeNextSave, what = openStages().what;
  app.timeNextSave = false;
  if (otherTabWrote) {
    otherTabWrote = false;
    const copy = `this tab, ${new Date().toLocaleTimeString()}`;
    app.model = { ...app.model, copy };
    const url = new URL(location.href); // a reload finds the copy as this tab's record, not by the sample's name
    url.searchParams.delete('model');
    window.history.replaceState(null, '', url);
    notice(`${app.model.name} was saved from another tab too: this tab's edits are kept apart, as "${app.model.name} (${copy})" in recent models.`);
  }
  const stored = {
    model: app.model,
    settings: { ...app.settings },
    fingerprint: session.model.fingerprint,
    positions: session.positions(),
    reference: session.referenceVolume(),
  };
  // localStorage: a small copy the teaching views read synchronously (web/session.js);
  // IndexedDB: the whole session at any size, with the undo history.
  saveSession(stored);
  if (!app.store) return;
  const history = { level: session.level, scheme: session.scheme, steps: session.history.steps() };
  const saving = app.store.save({ ...stored, history });
  if (timed) addStage('session saved: the page\'s part', 'page', performance.now() - started);
  const id = sessionId(app.model);
  const written = Promise.all([savesUnderWay.get(id), saving]).then(() => {}, () => {});
  savesUnderWay.set(id, written);
  written.then(() => {
    if (savesUnderWay.get(id) === written) savesUnderWay.delete(id);
  });
  saving.then((ok) => {
    if (ok) {
      // edits worth keeping: the browser asked once not to evict this site's storage under disk pressure
      if (!persistAsked && history.steps.undo.length > 0 && navigator.storage?.persist) {
        persistAsked = true;
        navigator.storage.persist().catch(() => {});
      }
      otherTabs?.postMessage({ id, tab: TAB_ID });
      try {
        sessionStorage.setItem(TAB_RECORD, id);
      } catch { /* storage off */ }
    }
    if (timed && app.store.lastWorkerMs !== null && openStages().what === what) {
      const read = app.store.lastFileRead; // the file read (from its File) or encoded there, not copied here
      if (read) addStage(`session saved: the file ${read.from === 'file' ? 'read from disk' : read.from === 'text' ? 'encoded' : 'taken'} for IndexedDB`, 'worker', read.ms, { bytes: read.bytes });
      addStage('session saved: written to IndexedDB', 'worker', app.store.lastWorkerMs);
    }
    showStorageProblem(app.store.problem);
    refreshRecent();
  });
}

async function refreshRecent() {
  if (!app.store) return;
  const entries = await app.store.recent();
  app.panel.showRecent(entries.map(({ id, name, kind, saved, copy }) => ({ id, name, kind, saved, copy, current: app.model && id === sessionId(app.model) })));
}

/**
 * Resolves once the records whose ids pass `which` hold the latest edits: a save waiting for its
 * moment is sent now, and those under way (written in the store's worker) are answered.
 */
async function savesWritten(which) {
  if (savePending) saveNow();
  await Promise.all([...savesUnderWay].filter(([id]) => which(id)).map(([, written]) => written));
}

/** Reopens a model of the recent list with its stored edits. */
async function openRecent(id) {
  await savesWritten((saving) => saving === id); // the current model's own entry: as last edited
  const stored = await app.store?.load(id);
  if (!stored) {
    showError('That session is no longer stored in this browser.');
    refreshRecent();
    return false;
  }
  applyStoredSettings(stored.settings);
  app.panel.update();
  return openModel(sourceOfStored(stored), restoreOfStored(stored));
}

function applyStoredSettings(settings) {
  if (!settings) return;
  for (const key of Object.keys(DEFAULT_SETTINGS))
    if (typeof settings[key] === typeof DEFAULT_SETTINGS[key]) app.settings[key] = settings[key];
}

/**
 * The stored session of a sample, or of a file of the same name and size (what its record's id
 * says), when it holds edits (undo history); else null.
 */
async function storedEditsOf(source) {
  if (!app.store?.available) return null;
  // its last edits stored first (the same model opened again just after an edit): read before, the
  // record has the edits before them, and the fresh model's first save would write over them
  const own = source.kind === 'sample' ? `sample:${source.name}` : `file:${source.name}:`;
  await savesWritten((id) => (source.kind === 'sample' ? id === own : id.startsWith(own) && !id.includes('#')));
  const size = source.kind === 'sample' ? null
    : source.file?.size ?? source.bytes?.byteLength ?? (typeof source.text === 'string' ? new TextEncoder().encode(source.text).byteLength : null);
  const record = (await app.store.recent()).find((r) => r.kind === source.kind && r.name === source.name && !r.copy &&
    (source.kind === 'sample' || (size !== null && r.textBytes === size)));
  const steps = record?.history?.steps;
  if (!record || !((steps?.undo?.length ?? 0) + (steps?.redo?.length ?? 0) > 0)) return null;
  return app.store.load(record.id);
}

function sourceOfStored(stored) {
  const copy = stored.model.copy ? { copy: stored.model.copy } : {};
  return stored.model.kind === 'sample'
    ? { kind: 'sample', name: stored.model.name, ...copy }
    : { kind: 'file', name: stored.model.name, text: stored.model.text, bytes: stored.model.bytes, ...copy };
}

function restoreOfStored(stored) {
  return { fingerprint: stored.fingerprint, positions: stored.positions, reference: stored.reference, history: stored.history };
}

// ---- models ---------------------------------------------------------------------------------------

/**
 * Opens an OBJ text (samples, remeshed results, project files, older stored sessions); see openModelMesh.
 */
function openModelText({ name, kind, text, copy }, restore = null) {
  let mesh;
  try {
    mesh = app.mrvol.readObj(text);
  } catch (e) {
    showError(`Could not open ${name}: ${e.message}`);
    return false;
  }
  return openModelMesh({ name, kind, text, format: 'obj', ...(copy ? { copy } : {}) }, mesh, restore);
}

/**
 * Opens a mesh read from a model (web/models.js says whether it can be edited); on success replaces
 * the current model (and returns true), otherwise shows why, remeshes it in a worker when that
 * would help (repairing it first when it is not a closed 2-manifold), and keeps the current one
 * (false). model: { name, kind, format, text? (OBJ text) | bytes? (the file) }; restore:
 * { positions: Float64Array, reference, fingerprint } from a stored session.
 */
function openModelMesh(model, mesh, restore = null, found = null) {
  const { session } = app;
  const { name } = model;
  let mr, info;
  try {
    // a semi-regular quad OBJ opens as quads (Catmull-Clark); anything else as triangles, with what the
    // file's worker found (file-open.js): the hierarchy, or why it does not open
    const quad = openQuadObj(app.mrvol, model, mesh);
    if (quad) ({ mr, info } = quad);
    else {
      if (found?.openError) throw Object.assign(new Error(found.openError.message), { offer: found.openError.offer });
      ({ mr, info } = pageStage('mesh opened (from the worker\'s)', () => openParsed(app.mrvol, mesh, found ?? {})));
    }
  } catch (e) {
    showError(`Could not open ${name}: ${e.message}`);
    // a file of quads is remeshed into quads (Catmull-Clark), unless the offer's field says otherwise
    const quads = model.format === 'obj' && firstFaceCorners(model.text ?? model.bytes ?? '') === 4;
    if (e.offer) offerRemesh({ name, mesh }, { repair: e.offer === 'repair', open: openModel, notice, auto: true, quads });
    return false;
  }
  // what the app had, put back if the session cannot open this one (it keeps its model then)
  const kept = { model: app.model, ready: app.ready, settings: { ...app.settings } };
  clearError();
  hideRemeshOffer();
  notice('');
  app.theta.cancel();
  // what an export keeps: the file's own lines (OBJ) or data (glTF) while the vertices are its own
  app.model = { ...model, vertices: mesh.positions.length / 3, levelsFrom: found?.hierarchy ? 'worker' : 'page',
                editorFrom: found?.opened ? 'worker' : 'page' };
  app.settings.model = name;
  // a share link's edits carry no fingerprint: the vertex count decides (session.open)
  const fits = restore && (restore.fingerprint == null || restore.fingerprint === mr.fingerprint());
  app.settings.level = Math.min(app.settings.level, info.levels);
  app.ready = false;
  session.level = app.settings.level;
  session.scheme = app.settings.scheme;
  session.preserve = app.settings.preserve;
  session.surface = app.settings.surface === 'limit' ? 'limit' : 'mesh';
  session.keepCentroid = app.settings.keepBalance;
  try {
    pageStage('session and view set up', () => session.open(mr, { name, own: true, restore: fits ? restore : null }));  // emits model, editor
  } catch (e) {
    Object.assign(app, { model: kept.model, ready: kept.ready });
    Object.assign(app.settings, kept.settings);
    Object.assign(session, { level: kept.settings.level, scheme: kept.settings.scheme, preserve: kept.settings.preserve,
                             surface: kept.settings.surface === 'limit' ? 'limit' : 'mesh', keepCentroid: kept.settings.keepBalance });
    showError(`Could not open ${name}: ${e.message}`);
    return false;
  }
  app.settings.level = session.level;
  app.settings.surface = session.surface;        // the mesh's own when it has no limit volume
  app.settings.keepBalance = session.keepCentroid;
  const history = fits ? restore.history : null;
  if (history?.steps && history.level === session.level && history.scheme === session.scheme) {
    session.history.load(history.steps);
    session.dispatchEvent(new CustomEvent('change', { detail: { reason: 'history' } }));
  }
  app.stats.modelAt ??= performance.now();
  app.timeNextSave = Boolean(found?.hierarchy);
  app.awaitingFrame = true; // ready once the next frame (with this model) is drawn
  app.viewer.requestRender();
  saveSoon();
  return true;
}

const nextPaint = () => new Promise((resolve) => requestAnimationFrame(() => setTimeout(resolve, 0)));

/** Whether a chosen or dropped file is a project (JSON) rather than a mesh: by name, else its first byte. */
async function isProjectFile(file) {
  if (/\.json$/i.test(file.name)) return true;
  if (/\.(obj|stl|ply|off|coff|noff|gltf|glb)$/i.test(file.name)) return false;
  return isProject(await file.slice(0, 64).text());
}

/**
 * Loads a model from its source: a sample, an OBJ text, a file (any mesh format, big ones read in a
 * worker with progress and cancel) or a stored file's bytes; false when it could not be read or opened.
 */
async function openModel(source, restore = null) {
  // the model before: its last edit stored now (a save waiting for the next idle moment would be
  // dropped when this model's first save replaces it)
  if (savePending) saveNow();
  otherTabWrote = false;
  const generation = ++app.loadGeneration;
  // A sample or file opened afresh that has stored edits (the same sample, or a file of the same name
  // and size): they come back with their undo history, rather than the fresh model's first save
  // writing over them. ("reset (forget edits)" starts over.)
  let restoredSteps = 0;
  if (!restore && !source.copy && (source.kind === 'sample' || source.kind === 'file')) {
    const stored = await storedEditsOf(source);
    if (generation !== app.loadGeneration) return false;
    if (stored) {
      applyStoredSettings(stored.settings);
      app.panel.update();
      restore = restoreOfStored(stored);
      restoredSteps = (stored.history?.steps?.undo?.length ?? 0) + (stored.history?.steps?.redo?.length ?? 0);
    }
  }
  const fail = (e) => {
    if (generation === app.loadGeneration && !e.cancelled) showError(`Could not open ${source.name}: ${sidecarHint(e.message)}`);
    if (e.cancelled && generation === app.loadGeneration) notice(`Opening ${source.name} was cancelled.`);
    return false;
  };
  let opened;
  if (source.kind === 'file' && source.text === undefined && (source.file || source.bytes)) {
    try {
      if (source.file && await isProjectFile(source.file)) {
        // a big project's JSON is read and decoded on the page (0.6 s at 655k vertices): said first
        const big = source.file.size > BIG_FILE_BYTES;
        if (big) {
          showFileProgress(`Reading the project ${source.name} (${(source.file.size / 1e6).toFixed(1)} MB)…`, null);
          await nextPaint();
        }
        let text;
        try {
          text = await source.file.text();
        } finally {
          if (big) showFileProgress(null);
        }
        if (generation !== app.loadGeneration) return false;
        return openProjectText(text, source.name);
      }
      const read = await readMeshFile(app.mrvol, { file: source.file, bytes: source.bytes, name: source.name,
        editor: { level: app.settings.level, scheme: app.settings.scheme, positions: restore?.positions,
                  surface: app.settings.surface === 'limit' ? 'limit' : 'mesh', keepCentroid: app.settings.keepBalance, path: sessionPath() } });
      if (generation !== app.loadGeneration) return false;
      // the page makes the editor itself only when the worker's could not be taken: say so first
      const big = read.bytes.byteLength > BIG_FILE_BYTES && !read.opened;
      if (big) {
        showFileProgress(`Opening ${source.name} (${(read.bytes.byteLength / 1e6).toFixed(1)} MB)${read.opened ? '' : ': making the editor'}…`, null);
        await nextPaint(); // the indicator shows before the page is busy with the hierarchy
      }
      try {
        // the File too: the first save hands it to the store's worker, which reads it there (no copy here)
        opened = openModelMesh({ name: source.name, kind: 'file', format: read.format, bytes: read.bytes, file: source.file,
                                 ...(source.copy ? { copy: source.copy } : {}) }, read.mesh, restore, read);
      } finally {
        if (big) showFileProgress(null);
      }
    } catch (e) {
      return fail(e);
    }
  } else {
    let text;
    try {
      text = await sourceText(source);
    } catch (e) {
      return fail(e);
    }
    if (generation !== app.loadGeneration) return false;
    opened = openModelText({ name: source.name, kind: source.kind, text, copy: source.copy }, restore);
  }
  // (or a fresh copy of its own beside them, the stored edits left as they are)
  if (opened && restoredSteps > 0 && app.session.history.size.undo + app.session.history.size.redo > 0)
    notice(`Your edits of ${source.name} are back (${restoredSteps} step${restoredSteps === 1 ? '' : 's'} of undo history); "reset (forget edits)" starts over.`,
           { action: { label: 'open a fresh copy instead', testid: 'open-fresh-copy',
                       run: () => openModel({ ...source, copy: `fresh copy, ${new Date().toLocaleTimeString()}` }) } });
  if (opened) {
    const url = new URL(location.href);
    // (a copy is not the sample's own session: a reload finds it as this tab's, not by the sample's name)
    if (source.kind === 'sample' && !source.copy) url.searchParams.set('model', source.name);
    else url.searchParams.delete('model');
    history.replaceState(null, '', url);
  } else {
    app.settings.model = app.model?.name ?? DEFAULT_MODEL;
    app.panel.update(); // the sample list goes back to the current model
  }
  return opened;
}
// Opening a file this big keeps the page busy while the editor is made: say so first.
const BIG_FILE_BYTES = 2_000_000;

// ---- the session's events: the view follows ---------------------------------------------------------

function followSessionInView(session) {
  let frameNext = false;
  session.addEventListener('model', () => {
    frameNext = true;
    app.viewer.setMesh(session.model.mr.positions(), session.model.faces, {
      editorNormals: true,
      shadowFaces: session.model.quads ? null : (most) => shadowFaces(session.model.mr, session.model.info.levels, session.model.faces.length / 3, most),
    });
    applyViewLayers();
    app.panel.setQuad(session.quad);
    app.panel.setLevels(session.model.info.levels, session.lowestLevel);
    app.panel.update();
  });
  session.addEventListener('editor', () => {
    app.selection.clear();
    app.viewer.setCage(session.cagePositions(), session.cageEdges());
    // a new editor of the shape the view draws: a model just opened (what setMesh drew), or a level,
    // scheme or surface change (the shape as it was): a big one's buffers are made when the page is idle
    app.viewer.updateMeshFrom(session.editor, { opened: true });
    app.freeSet.keepCageMarks();
    app.layers.update();
    if (frameNext) app.viewer.frameAll();
    frameNext = false;
    syncSettings();
    app.theta.request();
  });
  session.addEventListener('change', ({ detail }) => {
    if (detail.reason === 'step') return; // the drag handler draws and times its steps
    app.viewer.updateMeshFrom(session.editor, { opened: detail.reason === 'model', unmoved: detail.reason === 'free-set' });
    app.viewer.updateCage(session.cagePositions());
    if (detail.reason === 'undo' || detail.reason === 'redo' || detail.reason === 'cancel') app.layers.update();
    if (detail.reason === 'undo' || detail.reason === 'redo') syncSettings();
  });
  session.addEventListener('error', ({ detail }) => showError(detail.message));
  // The undo history keeps its last steps: said once per model when it first lets one go.
  let historyFullSaid = false;
  session.addEventListener('model', () => { historyFullSaid = false; });
  session.addEventListener('history-full', ({ detail }) => {
    if (historyFullSaid) return;
    historyFullSaid = true;
    notice(`Undo keeps the last ${detail.limit} steps: from now on the oldest edit of ${app.model?.name ?? 'this model'} ` +
           'cannot be undone when a new one is made (the shape keeps it).');
  });
  session.addEventListener('change', (event) => {
    if (event.detail.reason !== 'step' || !session.dragging) checkSelfIntersection(event);
  });
  session.addEventListener('dragend', () => checkSelfIntersection());
}

/**
 * Rebuilds the editor at the panel's scheme or level (the session keeps shape, reference and
 * history); a big model's in a worker (web/editor-rebuild.js), the page drawing meanwhile.
 */
async function rebuildEditor() {
  const { session, settings } = app;
  if (!session.editor || app.rebuilding) return;
  const target = { level: settings.level, scheme: settings.scheme };
  if (rebuildsInWorker(session, target)) return rebuildBig(target, (mr) => session.adoptRebuilt(mr, target));
  if (settings.scheme !== session.scheme) session.setScheme(settings.scheme); // emits editor
  else session.setLevel(settings.level);
  saveSoon();
}

/** The surface switch (balance.js): a big model's editor for the other surface made in the worker. */
function changeSurface(surface) {
  const { session } = app;
  const target = { level: session.level, scheme: session.scheme, surface };
  if (app.rebuilding || !session.editor || surface === session.surface) return undefined;
  if (rebuildsInWorker(session, target))
    return rebuildBig(target, (mr) => session.adoptRebuilt(mr, target), `The ${surface} surface cannot be used`);
  return session.setSurface(surface);
}

/**
 * The editor at target made in a worker, then `apply(mr)` swaps it in; drags and undo wait meanwhile.
 * `failed`: the error's words (null: not shown, the caller says); `options`: rebuildInWorker's (theta).
 * Resolves to { swapped, error }.
 */
async function rebuildBig(target, apply, failed = `The level ${target.level} editor could not be made`, options = {}) {
  app.rebuilding = true;
  app.ready = false; // no drags on the editor being replaced
  let swapped = false, error = null;
  try {
    swapped = await rebuildInWorker(app.session, target, { name: app.model.name, apply, ...options });
    if (!swapped) syncSettings(); // cancelled: the panel shows the editor kept
  } catch (e) {
    error = e;
    if (failed) showError(`${failed}: ${e.message}`);
    syncSettings();
  } finally {
    app.rebuilding = false;
    app.awaitingFrame = true;
    app.viewer.requestRender();
  }
  saveSoon();
  return { swapped, error };
}

/** The settings and panel follow what undo and redo changed in the session: level, scheme, preservation, balance, surface. */
function syncSettings() {
  const { session, settings } = app;
  if (settings.level === session.level && settings.scheme === session.scheme && settings.preserve === session.preserve &&
      settings.keepBalance === session.keepCentroid && settings.surface === session.surface) return;
  settings.level = session.level;
  settings.scheme = session.scheme;
  settings.preserve = session.preserve;
  settings.keepBalance = session.keepCentroid;
  settings.surface = session.surface;
  app.panel.update();
  saveSoon();
}

/**
 * Preservation from the panel. Turned back on while the volume is off its reference, the user
 * chooses: restore the reference volume now, or take the current volume as the new reference.
 */
function changePreserve() {
  const { session, settings } = app;
  if (!session.editor) return;
  session.setPreserve(settings.preserve);
  const reference = session.referenceVolume(), volume = session.volume();
  const off = Math.abs(volume - reference) / Math.max(Math.abs(reference), 1e-300);
  if (settings.preserve && off > session.tolerance) askRestore(off);
  saveSoon();
}

function askRestore(off) {
  const dialog = document.getElementById('preserve-dialog');
  document.getElementById('preserve-off').textContent = `${(100 * off).toPrecision(3)}%`;
  const choose = (restore) => {
    dialog.close();
    if (restore) {
      if (!app.session.restoreReferenceVolume()) return;
      // a step outside a drag: the view draws it here (the change listener leaves steps to the drag)
      app.viewer.updateMeshFrom(app.session.editor);
      app.viewer.updateCage(app.session.cagePositions());
      app.layers.update();
    } else {
      app.session.setReferenceVolume();
    }
    saveSoon();
  };
  document.getElementById('preserve-restore').onclick = () => choose(true);
  document.getElementById('preserve-keep').onclick = () => choose(false);
  dialog.showModal();
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
    app.dragHandles = handles;
    app.chart.startDrag();
  },
  drag(delta, eventTime) {
    const { session } = app;
    if (!session.dragging) return;
    session.tolerance = app.settings.tolerance;
    const before = session.cagePositions();
    const report = session.dragBy(delta);
    if (report) app.chart.pushLambda(stepMultiplier(session, before, app.dragHandles)); // drawn on the change
    if (!report) {
      app.dragger.cancel(); // refused: the session put the cage back and said why
      return;
    }
    const drawing = performance.now();
    app.viewer.updateMeshFrom(session.editor);
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
  if (app.rebuilding) return; // not while the next editor is made
  // undoing a big model's level or scheme change: the editor before made in the worker
  const step = app.session.editor && !app.session.dragging ? app.session.history.peekUndo() : null;
  if (step?.label === 'editor' && rebuildsInWorker(app.session, step.before))
    return rebuildBig(step.before, (mr) => { app.session.history.undo(); app.session.adoptRebuilt(mr, step.before, { record: false }); });
  const surface = step?.label === 'surface' ? surfaceTarget(step.before) : null;
  if (surface && rebuildsInWorker(app.session, surface))
    return rebuildBig(surface, (mr) => { app.session.history.undo(); app.session.adoptRebuilt(mr, surface, { record: false, reason: 'undo' }); });
  if (app.session.undo()) saveSoon();
}

function redo() {
  if (app.rebuilding) return;
  const step = app.session.editor && !app.session.dragging ? app.session.history.peekRedo() : null;
  if (step?.label === 'editor' && rebuildsInWorker(app.session, step.after))
    return rebuildBig(step.after, (mr) => { app.session.history.redo(); app.session.adoptRebuilt(mr, step.after, { record: false }); });
  const surface = step?.label === 'surface' ? surfaceTarget(step.after) : null;
  if (surface && rebuildsInWorker(app.session, surface))
    return rebuildBig(surface, (mr) => { app.session.history.redo(); app.session.adoptRebuilt(mr, surface, { record: false, reason: 'redo' }); });
  if (app.session.redo()) saveSoon();
}

/** A surface undo step's side ({ surface, keepCentroid, reference }) as a rebuild's target at the current level and scheme. */
function surfaceTarget(state) {
  return { level: app.session.level, scheme: app.session.scheme, ...state };
}

// ---- tools: screenshot, share link, project file, keyboard help ----------------------------------------

function baseName() {
  return baseNameOf(app.model.name);
}

/** The view as a PNG file (drawn now, so the drawing buffer holds the frame). */
function screenshot() {
  app.viewer.renderer.render(app.viewer.scene, app.viewer.camera);
  app.viewer.canvas.toBlob((blob) => {
    if (blob) download(blob, `${baseName()}.png`, 'screenshot-link');
  }, 'image/png');
}

/** A link that opens this sample with its edits and settings; copied to the clipboard when allowed. */
async function shareLink() {
  const { session } = app;
  if (!session.editor) return;
  const field = document.getElementById('share-url');
  field.value = ''; // never show (or copy) the last link while this one is made
  if (app.model.kind !== 'sample') {
    notice('A share link can carry a sample model\'s edits only; save a project file to pass on an opened file.', { reveal: true });
    return;
  }
  const original = app.mrvol.readObj(await fetchSample(app.model.name)).positions;
  const url = await shareUrl({ name: app.model.name, positions: session.positions(), original, reference: session.referenceVolume(), settings: app.settings });
  field.value = url;
  document.getElementById('share').hidden = false;
  field.select();
  try {
    await navigator.clipboard.writeText(url);
    notice('The share link is copied to the clipboard.');
  } catch {
    notice('The share link is below the readouts: copy it from there.');
  }
  // The link itself into the view (the panel's Tools are far below it on a phone).
  document.getElementById('share').scrollIntoView({ block: 'nearest', inline: 'nearest' });
}

function saveProject() {
  const { session } = app;
  if (!session.editor) return;
  const blob = projectBlob({ model: app.model, positions: session.positions(), reference: session.referenceVolume(), settings: app.settings });
  download(blob, `${baseName()}.mrvol.json`, 'project-link');
}

/** Opens a project file's model with its edits and settings. */
function openProjectText(text, fileName) {
  let project;
  try {
    project = readProject(text, fileName);
  } catch (e) {
    showError(`Could not open ${fileName}: ${e.message}`);
    return false;
  }
  applyStoredSettings(project.settings);
  app.panel.update();
  const restore = { fingerprint: null, positions: project.positions, reference: project.reference };
  // a big OBJ text (a project of an earlier version) as bytes: read in the file's worker, with progress
  const { model } = project;
  if (!model.bytes && model.text.length > BIG_FILE_BYTES)
    return openModel({ name: model.name, kind: model.kind, format: 'obj', bytes: new TextEncoder().encode(model.text) }, restore);
  return model.bytes ? openModel(model, restore) : openModelText(model, restore);
}

function showKeyboardHelp() {
  document.getElementById('keys').showModal();
}

// ---- actions from the panel and the keyboard ---------------------------------------------------------

/**
 * The edited mesh as OBJ: an OBJ file's own text with its positions replaced (vt, vn, groups,
 * materials kept) while its vertices are the file's; else a plain OBJ.
 */
function exportObj() {
  const { session } = app;
  if (!session.editor) return;
  const positions = session.positions();
  const own = app.model.format === 'obj' && app.model.vertices === positions.length / 3 && (app.model.bytes ?? app.model.text);
  let data = null;
  if (own) {
    try {
      data = app.mrvol.writeObjLike(own, positions);
    } catch { /* a plain OBJ below */ }
  }
  const { quads, faces } = session.model;
  data ??= quads ? app.mrvol.writeObjQuads({ positions, quads }) : app.mrvol.writeObj({ positions, faces });
  download(data instanceof Uint8Array ? new Blob([data], { type: 'text/plain' }) : data, `${baseName()}-edited.obj`, 'export-link');
}

/**
 * The edited mesh as GLB: a glTF file's own data (materials, textures, other attributes) with its
 * positions replaced while the triangles are the file's; else positions, normals and triangles.
 */
function exportGlb() {
  const { session } = app;
  if (!session.editor) return;
  const mesh = { positions: session.positions(), faces: session.model.faces };
  const { format, bytes } = app.model;
  let glb = null;
  if ((format === 'glb' || format === 'gltf') && bytes && app.model.vertices === mesh.positions.length / 3) {
    try {
      glb = app.mrvol.writeGlb(mesh, { source: { bytes, format } });
    } catch { /* a plain GLB below */ }
  }
  glb ??= app.mrvol.writeGlb(mesh);
  download(new Blob([glb], { type: 'model/gltf-binary' }), `${baseName()}-edited.glb`, 'export-glb-link');
  // what a GLB cannot hold of this model, said rather than dropped unseen
  if (session.quad) notice('The GLB holds the quads as triangles (glTF has no quads): export OBJ keeps the quads and their Catmull-Clark levels.');
}

/** The level-e cage as its own OBJ: cage positions in cage order, the level-e triangles (or quads). */
function exportCage() {
  const { session } = app;
  if (!session.editor) return;
  const { corners, faces } = session.cageFaces();
  const positions = session.cagePositions();
  const text = corners === 4 ? app.mrvol.writeObjQuads({ positions, quads: faces }) : app.mrvol.writeObj({ positions, faces });
  download(text, `${baseName()}-cage-level${session.level}.obj`, 'export-cage-link');
}

async function reset() {
  const { undo, redo } = app.session.history.size;
  const steps = undo + redo;
  // edits are forgotten for good (no undo): asked first when there are any
  if (steps > 0 && !window.confirm(`Forget the edits of ${app.model?.name ?? 'this model'} (${steps} step${steps === 1 ? '' : 's'} of undo history)? ` +
                                   'They cannot be brought back.')) return;
  clearSession();
  if (app.model) await app.store?.remove(sessionId(app.model));
  Object.assign(app.settings, DEFAULT_SETTINGS, { model: app.model?.name ?? DEFAULT_MODEL });
  app.viewer.setFlat(app.settings.flat, app.session?.editor);
  applyViewLayers();
  if (app.model) await openModel({ kind: app.model.kind, name: app.model.name, text: app.model.kind === 'file' ? app.model.text : undefined, bytes: app.model.bytes });
  app.panel.update();
}

const actions = {
  openSample: (name) => openModel({ kind: 'sample', name }),
  openFile: () => app.pickFile(),
  openRecent: (id) => openRecent(id),
  showGlossary: () => document.getElementById('glossary').showModal(),
  showKeyboardHelp,
  frame: () => app.viewer.frameAll(),
  screenshot,
  shareLink,
  saveProject,
  exportObj,
  exportGlb,
  exportCage,
  reset,
  undo,
  redo,
  changeScheme: () => rebuildEditor(),
  changeLevel: () => rebuildEditor(),
  changePreserve,
  changeTolerance: () => saveSoon(),
  changeGradient: () => {
    app.session.path = sessionPath();
    rebuildEditor(); // on the chosen path (a big model's in the worker)
  },
  changeFreeSet: () => { app.freeSet.changeMode(); saveSoon(); },
  changeTool: () => { app.freeSet.changeTool(); saveSoon(); },
  clearPainted: () => { app.freeSet.clearPainted(); saveSoon(); },
  clearParts: () => { app.freeSet.clearParts(); saveSoon(); },
  changeView: () => {
    app.viewer.setFlat(app.settings.flat, app.session?.editor);
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
  const ctrl = e.ctrlKey || e.metaKey;
  // text fields keep their own keys; a select has no Ctrl keys of its own: Ctrl+Z, Y, O, S there are the app's
  if (target instanceof HTMLElement && (target.isContentEditable || /^(INPUT|TEXTAREA|SELECT)$/.test(target.tagName)) &&
      target.type !== 'checkbox' && !(target.tagName === 'SELECT' && ctrl && /^[zZyYoOsS]$/.test(e.key)))
    return;
  if (document.querySelector('dialog[open]')) return; // a dialog has the keys
  if (ctrl && !e.altKey && !e.shiftKey && (e.key === 'o' || e.key === 'O')) {
    e.preventDefault();
    app.pickFile();
    return;
  }
  if (ctrl && !e.altKey && !e.shiftKey && (e.key === 's' || e.key === 'S')) {
    e.preventDefault();
    saveProject();
    return;
  }
  if (e.key === '?' && !ctrl) {
    e.preventDefault();
    showKeyboardHelp();
  } else if ((e.key === 'f' || e.key === 'F') && !ctrl && !e.altKey) {
    app.viewer.frameAll();
  } else if (e.key === 'Escape') {
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

/** The phone layout's sheet (panel and readouts below the view) folds to its title bar and back. */
function setUpSheet() {
  const side = document.getElementById('side');
  const toggle = document.getElementById('sheet-toggle');
  toggle.addEventListener('click', () => {
    const collapsed = side.classList.toggle('collapsed');
    toggle.setAttribute('aria-expanded', String(!collapsed));
  });
}

/** The session's gradient path for the panel's choice (lib/three/session.mjs). */
function sessionPath() {
  return app.settings.gradient === 'tensor' ? 'matrix-free' : 'auto';
}

// ---- start --------------------------------------------------------------------------------------------

async function start() {
  app.stats.scriptAt = performance.now();
  installDebugHook(app);
  // The core, the cache and the model file load in parallel.
  const coreLoading = loadPageMrvol(); // threaded where the page is cross-origin isolated
  const cacheOpening = ThetaCache.open();
  const view = document.getElementById('view');
  app.viewer = new Viewer(view);
  app.viewer.onFrame = (renderMs) => {
    if (app.awaitingFrame) {
      app.awaitingFrame = false;
      app.ready = true;
      app.stats.readyAt ??= performance.now();
      performance.mark('mrvol: first frame with the model');
    }
    if (app.pendingInput !== null) {
      pushStat(app.stats.frames, performance.now() - app.pendingInput);
      pushStat(app.stats.renders, renderMs);
      app.pendingInput = null;
    }
  };
  app.dragger = new CageDragger(app.viewer, view, dragHandlers);
  // a file's progress strip shrinks the view for a few seconds: its canvas is cut meanwhile, not drawn again
  onFileProgressShown((shown) => app.viewer.holdSize(shown));

  const params = new URLSearchParams(location.search);
  const urlModel = params.get('model');
  const shared = sharedState(params);
  const gradientParam = params.get('gradient');
  app.store = await SessionStore.open();
  app.store.writeInWorker(); // big files and positions are cloned into IndexedDB off the page's thread
  // The newest session in IndexedDB (or, with ?model=NAME, that sample's); else the localStorage copy.
  // (This tab's own record first, after a reload: another tab may have saved a newer one.)
  const ownRecord = tabRecord();
  const ownFits = ownRecord && (urlModel === null || ownRecord === `sample:${urlModel}` || ownRecord.startsWith(`sample:${urlModel}#`));
  let stored = ownFits ? await app.store.load(ownRecord) : null;
  stored ??= await app.store.load(urlModel === null ? null : `sample:${urlModel}`);
  // The localStorage copy is written at once; the IndexedDB write can be cut short by a reload. The
  // newer of the two wins (the copy without the undo history, which may not reach its state).
  const small = loadSession();
  const sameModel = (a, b) => a.model.kind === b.model.kind && a.model.name === b.model.name && (a.model.copy ?? null) === (b.model.copy ?? null);
  if (small && (!stored || (small.saved > (stored.saved ?? 0) && sameModel(small, stored)))) {
    let positions = null;
    try {
      positions = small.positions ? decodeFloat64(small.positions) : null;
    } catch { /* a damaged session: the file's own positions */ }
    const text = small.model.text ?? stored?.model.text;
    if (positions || !stored) stored = { ...small, model: { ...small.model, text, bytes: text === undefined ? stored?.model.bytes : undefined, format: stored?.model.format }, positions, history: null };
  }
  applyStoredSettings(stored?.settings);
  if (gradientParam === 'tensor' || gradientParam === 'polynomial') app.settings.gradient = gradientParam;
  if (gradientParam !== null) {
    // applied: the stored settings keep it from now on
    const url = new URL(location.href);
    url.searchParams.delete('gradient');
    history.replaceState(null, '', url);
  }
  const useStored = stored && (urlModel === null || (stored.model.kind === 'sample' && stored.model.name === urlModel)) &&
    (stored.model.kind === 'sample' || typeof stored.model.text === 'string' || stored.model.bytes instanceof Uint8Array);

  app.panel = createPanel({ settings: app.settings, samples: sampleModels, actions, learnViews: VIEWS });
  app.viewer.setFlat(app.settings.flat, app.session?.editor);
  app.viewer.precompile(); // while the core, the cache and the model load
  // Dismissing the message dismisses what runs under it: a remesh would otherwise open its result later, unseen.
  document.getElementById('error-close').addEventListener('click', () => {
    if (cancelRemesh()) notice('Remeshing cancelled.');
    hideRemeshOffer();
    clearError();
  });
  setUpSheet();
  document.getElementById('theta-cancel').addEventListener('click', () => app.theta?.cancelJob());
  document.getElementById('busy-cancel').addEventListener('click', cancelFileRead);
  app.pickFile = setUpFileInput((file) => file && openModel({ kind: 'file', name: file.name, file }));
  document.getElementById('share-close').addEventListener('click', () => { document.getElementById('share').hidden = true; });
  // Capture phase: lil-gui stops keydown events of its controls from bubbling.
  window.addEventListener('keydown', onKeyDown, { capture: true });
  setUpDrop((file) => file && openModel({ kind: 'file', name: file.name, file }));

  let restore = null, source;
  if (shared) {
    Object.assign(app.settings, { level: shared.level, preserve: shared.preserve, keepBalance: shared.keepBalance, surface: shared.surface },
      shared.scheme ? { scheme: shared.scheme } : {});
    source = { kind: 'sample', name: shared.name };
  } else if (useStored) {
    restore = restoreOfStored(stored);
    source = sourceOfStored(stored);
  } else {
    source = { kind: 'sample', name: urlModel ?? DEFAULT_MODEL };
  }
  if (source.kind === 'sample') source.prefetch = fetchSample(source.name).catch((e) => e);
  let prefetch = null;
  if (useStored && typeof stored.fingerprint === 'string' && app.settings.gradient === 'tensor') {
    // The stored session says which theta the editor will want: read it while the core loads.
    const key = thetaKey({ fingerprint: stored.fingerprint, ...DEFAULT_SCHEME, scheme: app.settings.scheme, level: app.settings.level });
    // a big one is read in the editor worker instead (theta-source.js)
    prefetch = { key, bytes: cacheOpening.then(async (cache) => ((await cache.size(key)) >= WORKER_THETA_BYTES ? null : cache.get(key))) };
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
    level: app.settings.level, scheme: app.settings.scheme, preserve: app.settings.preserve, tolerance: app.settings.tolerance, path: sessionPath(),
  });
  app.session = session;
  app.theta = new ThetaSource(session, {
    jobs, stats: app.stats, showCache: (entries, note) => app.panel.showCache(entries, note),
    rebuild: (target, apply, options) => (app.rebuilding ? { swapped: false, error: new Error('another editor is being made') }
      : rebuildBig(target, apply, null, options)),
  });
  app.theta.prefetch = prefetch;
  app.layers = new Layers(session, app.viewer, app.settings, (ms) => pushStat(app.stats.layers, ms));
  app.freeSet = new FreeSetTools({ session, viewer: app.viewer, panel: app.panel, settings: app.settings, defaults: DEFAULT_SETTINGS });
  followSession(session);
  const keyboard = setUpKeyboardHandles({
    app,
    canNudge: () => app.ready && !session.dragging && !app.freeSet.painting,
    onMoved: () => {
      app.viewer.updateMeshFrom(session.editor);
      app.viewer.updateCage(session.cagePositions());
      app.layers.afterDrag();
      saveSoon();
    },
  });
  session.addEventListener('editor', () => keyboard.describe());
  const chart = new VolumeChart(document.getElementById('chart'));
  app.chart = chart;
  session.addEventListener('model', () => chart.reset());
  session.addEventListener('change', () => chart.push(session.volumeNow(), session.referenceVolume()));
  followSessionInView(session);
  app.balance = setUpBalance({ session, viewer: app.viewer, onChanged: () => { syncSettings(); saveSoon(); }, changeSurface });
  const cache = await cacheOpening;
  app.theta.cache = cache;
  app.stats.cacheAt = performance.now();
  showCacheStatus(cache.available ? 'IndexedDB' : `none: ${cache.reason}; θ is computed on every load`);
  showStorageProblem(app.store.problem);
  app.theta.refreshCacheList();
  refreshRecent();
  applyViewLayers();
  if (shared) {
    // A share link: the sample, then its edits over the sample's own positions.
    try {
      const text = await sourceText({ ...source, prefetch: source.prefetch });
      const positions = await decodeEdits(shared.edits, app.mrvol.readObj(text).positions);
      restore = { fingerprint: null, positions, reference: shared.reference };
      // a record of its own: the sample's own stored edits stay as they are (recent models has both)
      source = { ...source, text, prefetch: undefined, copy: 'shared link' };
    } catch (e) {
      showError(`The share link's edits could not be applied: ${e.message}`);
    }
  }
  if (!(await openModel(source, restore)) && !app.model && source.name !== DEFAULT_MODEL) {
    const why = errorText();
    if (await openModel({ kind: 'sample', name: DEFAULT_MODEL })) showError(`${why}\nOpened ${DEFAULT_MODEL} instead.`);
  }
  applyViewLayers();
  startFileWorker(); // now, not when idle: a file dropped as soon as the model shows is read at once
  keepFileWorkerReady(); // a big file dropped later is read at once
  if (shared) {
    // applied: a reload opens the stored session (which now holds these edits)
    const url = new URL(location.href);
    for (const key of SHARE_PARAMS) url.searchParams.delete(key);
    history.replaceState(null, '', url);
    saveSoon();
  }
  // Only a save still waiting: a needless one would give the localStorage copy (no undo history) a
  // newer time than the IndexedDB record, whose write the unload cuts short, and it would win on reload.
  window.addEventListener('pagehide', () => savePending && saveNow());
}

// #learn/... and #demo/...: the teaching views (web/learn/) instead of the editor.
if (learnRoute()) startLearn();
else {
  watchForLearnRoutes();
  start();
}
