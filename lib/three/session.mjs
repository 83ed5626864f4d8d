// The editing session: one model, its volume-preserving editor at a level and scheme, undo history,
// free set and parts, the volume tensor in use. No DOM and no three.js (it runs under Node): views
// subscribe to its events and draw; the web app, the teaching views and the three.js component
// (lib/three/index.mjs) are built on it.
//
// Events (CustomEvent, `detail` as said):
//   model   a model was opened (the cage, faces, everything changed)
//   editor  the editor was rebuilt (level or scheme changed: a new cage)
//   step    one drag step: { report, ms } (the core's report: volumes, iterations, path)
//   change  the shape or the editing state changed: { reason } ('step', 'undo', 'redo', 'cancel',
//           'free-set', 'reference', 'preserve', 'editor', 'model', 'history', 'keep')
//
// Undo/redo covers every change of the shape or the reference: drags (cage positions before and
// after, at the level and scheme they were made), reference volume changes, preservation toggles,
// keep-balance toggles, surface changes (mesh / limit, with each one's reference volume),
// and level and scheme changes themselves (undoing one goes back to the earlier cage, so the
// earlier drags undo at the level they were made). Opening a model starts a new history.
//   theta   the gradient path or the tensor in use changed: { source, path }
//   dragend a drag ended (its undo step recorded when the cage moved)
//   history-full  the history held `historyLimit` steps and let the oldest go: { limit }
//   error   an edit was refused and undone: { message, error }
//
// Quad models (a QuadMultiresMesh, or a mesh { positions, quads }: lib/quad.mjs) edit the same way
// with the catmull-clark scheme and the bilinear-patch volume: model.quads holds the quads,
// model.faces the triangles they are drawn with (each quad split in two), the cage's edges are the
// level-e quads' sides. What the quad editor lacks (the limit surface; painted regions
// and parts until it has them) is refused with a message; `freeSetModes` says which free sets work.
import { DEFAULT_SCHEME, chooseGradientPath } from '../api.mjs';
import { History } from './history.mjs';
import { edgesOf, quadEdgesOf, trianglesOfQuads } from './edges.mjs';

/** The scheme of quad models (Catmull-Clark, docs/catmull-clark.md). */
export const QUAD_SCHEME = 'catmull-clark';
// Levels of details from which the cage polynomial beats a pass over the fine mesh (as lib/api.mjs).
const COARSE_CAGE_LEVELS = 3;

/**
 * Free-set modes: the cage minus the held handles, all the cage, a painted region (a list of cage
 * vertices), or parts (cage minus held, each part keeping its own volume).
 */
export const FREE_SET_MODES = Object.freeze(['minus-held', 'all', 'painted', 'parts']);
export const MAX_PARTS = 8;

const emptyParts = () => Array.from({ length: MAX_PARTS }, () => []);

/**
 * The gradient path a session picks for a triangle model's editor at `level` (gradientChoice): the
 * web app's editor worker makes big models' editors with the same choice. options: { level, scheme,
 * alpha, beta, surface ('mesh' | 'limit'), path (the session's: 'auto' | 'matrix-free') }.
 */
export function triangleGradientChoice(mr, { surface = 'mesh', path = 'auto', ...options }) {
  // A mesh theta is no use for the limit surface's volume (its own theta is not computed here).
  if (surface === 'limit') return { path: 'matrix-free', estimate: null, reason: "not used: the limit surface's volume runs matrix-free" };
  // a coarse cage needs no estimate of theta^e (a second or more on a big mesh)
  if (path === 'auto' && chooseGradientPath(mr, options).path === 'polynomial') return { path: 'polynomial', estimate: null };
  const choice = chooseGradientPath(mr, { ...options, thetaInBackground: true });
  return path === 'auto' && choice.path === 'tensor' ? { ...choice, path: 'polynomial' } : choice;
}

export class EditingSession extends EventTarget {
  /** The model: { name, mr, info, fingerprint, faces (triangles), quads (quad models) or null, depths }, or null. */
  model = null;
  /** The mrvol VolumeEditor, or null. */
  editor = null;
  cageSize = 0;
  /** Caller's vertex of each cage vertex (cage order), and its inverse (a Map). */
  cageVertices = null;
  cageIndex = null;
  history;
  /** { mode, painted: caller's cage vertices, parts: MAX_PARTS lists of them }; replaced, never mutated. */
  freeSet = { mode: 'minus-held', painted: [], parts: emptyParts() };
  /** Part numbers (1..MAX_PARTS) of the editor's parts, and their reference volumes. */
  parts = [];
  partReferences = null;
  /** Where the tensor in use came from ('computed', 'cache', ...), or null (matrix-free). */
  thetaSource = null;
  /** Whose volume is kept ('mesh' or 'limit': the Loop limit surface), and whether the centre of mass is kept too. */
  surface = 'mesh';
  keepCentroid = false;
  lastReport = null;
  lastStepMs = null;
  #mrvol;
  #ownsMesh = false;
  #drag = null;
  #heldAll = null;
  #thetas = new Map(); // `${scheme}/${level}` -> { theta, source }, this model's
  #volume = null;      // the volume of the current shape, once known (null: ask the core)
  #centroid = null;    // its centre of mass likewise (a pass over the fine mesh)
  #freeSetModes = FREE_SET_MODES;

  /**
   * @param {object} mrvol the API object (createMrvol)
   * @param {object} [options] { level, scheme, alpha, beta, preserve, tolerance, historyLimit, path }; path
   *   'matrix-free' (default: until a tensor is handed over) or 'auto': the cage polynomial built from
   *   the fine mesh wherever chooseGradientPath would take it or theta^e (the same steps, without
   *   computing theta^e or handing it over), else matrix-free; no tensor is wanted then.
   */
  constructor(mrvol, { level = 0, scheme = DEFAULT_SCHEME.scheme, alpha = DEFAULT_SCHEME.alpha, beta = DEFAULT_SCHEME.beta,
    preserve = true, tolerance = 1e-6, historyLimit = 200, path = 'matrix-free' } = {}) {
    super();
    this.#mrvol = mrvol;
    this.level = level;
    this.scheme = scheme;
    this.alpha = alpha;
    this.beta = beta;
    this.preserve = preserve;
    this.tolerance = tolerance;
    this.path = path;
    this.history = new History(historyLimit, { onDrop: () => this.#emit('history-full', { limit: historyLimit }) });
  }

  get mrvol() { return this.#mrvol; }
  get dragging() { return this.#drag !== null; }
  /** { scheme, alpha, beta }: what the analysis and theta depend on besides the mesh and level. */
  get schemeOptions() { return { scheme: this.scheme, alpha: this.alpha, beta: this.beta }; }
  /** Whether the model is a quad mesh (catmull-clark scheme, bilinear-patch volume). */
  get quad() { return Boolean(this.model?.quads); }
  /** The free-set modes the current editor takes (FREE_SET_MODES for triangle models). */
  get freeSetModes() { return this.#freeSetModes; }
  /** Whether the centre of mass can be kept (both kinds of model) and the limit surface's volume (triangles). */
  get canKeepCentroid() { return typeof this.editor?.keepCentroid === 'function'; }
  get canKeepLimit() { return Boolean(this.model) && !this.quad; }

  #emit(type, detail = {}) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }

  /**
   * Opens a model and makes it current (the previous one is freed). `source` is a mesh
   * ({ positions, faces }, opened here and owned by the session) or a MultiresMesh the caller opened
   * (the caller keeps it unless `own`: the session then deletes it with the model, or at once when
   * it does not open). Throws MrvolError when it does not open; the current model stays then, as it
   * was (its editor, tensors, level and scheme).
   * options: { name, restore: { positions, reference } (a stored shape of this mesh), own }
   */
  open(source, { name = 'mesh', restore = null, own = false } = {}) {
    const opened = typeof source?.createEditor !== 'function';
    const mr = opened ? this.#mrvol.openMesh(source) : source;
    let model;
    try {
      const info = mr.info();
      const quads = mr.scheme === QUAD_SCHEME ? mr.quads() : null;
      model = { name, mr, info, fingerprint: mr.fingerprint(), faces: quads ? trianglesOfQuads(quads) : mr.faces(), quads, depths: mr.depths() };
    } catch (e) {
      if (opened) mr.delete();
      throw e;
    }
    // The new model is tried with the old one still open: if its editor cannot be made, the old one
    // stays current, as it was (its editor, tensors and settings).
    this.cancelDrag();
    const before = { model: this.model, editor: this.editor, ownsMesh: this.#ownsMesh, thetas: this.#thetas,
                     level: this.level, scheme: this.scheme, surface: this.surface, keepCentroid: this.keepCentroid };
    this.model = model;
    this.editor = null;
    this.#thetas = new Map();
    this.#ownsMesh = opened || own;
    // a level analysis reaches (a quad mesh on a cube's base stops at 1)
    this.level = Math.max(this.lowestLevel, Math.min(this.level, model.info.levels));
    // A quad model has one scheme; a triangle model opened after one goes back to the default.
    if (model.quads) {
      this.scheme = QUAD_SCHEME;
      this.surface = 'mesh';
      this.keepCentroid = false;
    } else if (this.scheme === QUAD_SCHEME) {
      this.scheme = DEFAULT_SCHEME.scheme;
    }
    let reference = null;
    if (restore?.positions?.length === 3 * model.info.vertices) {
      mr.setPositions(restore.positions);
      if (Number.isFinite(restore.reference)) reference = restore.reference;
    }
    // model first (views replace the mesh), then the new cage.
    if (this.surface === 'limit') this.keepCentroid = false;
    try {
      try {
        this.#buildEditor(reference, { announce: false });
      } catch (error) {
        // a stored 'limit' setting on a mesh without a limit volume (an open one): the mesh's volume
        if (this.surface !== 'limit') throw error;
        this.surface = 'mesh';
        this.#buildEditor(null, { announce: false });
      }
    } catch (error) {
      this.model = before.model;
      this.editor = before.editor;
      this.#thetas = before.thetas;
      this.#ownsMesh = before.ownsMesh;
      Object.assign(this, { level: before.level, scheme: before.scheme, surface: before.surface, keepCentroid: before.keepCentroid });
      if (opened || own) mr.delete(); // handed over (own): not the caller's to free any more
      throw error;
    }
    // the model before, closed now
    for (const { theta } of before.thetas.values()) theta?.delete();
    before.editor?.delete();
    if (before.model && before.ownsMesh) before.model.mr.delete();
    this.history.clear(); // a new model, a new history
    this.#emit('model', { model });
    this.#announceEditor();
    this.#emit('change', { reason: 'model' });
    return model;
  }

  /** The lowest level e the model's analysis reaches (0 but for a quad mesh on a cube's base: 1). */
  get lowestLevel() { return this.model?.mr.lowestLevel ?? 0; }

  #closeModel() {
    this.cancelDrag();
    for (const { theta } of this.#thetas.values()) theta?.delete();
    this.#thetas.clear();
    this.editor?.delete();
    this.editor = null;
    this.#shapeChanged();
    if (this.model && this.#ownsMesh) this.model.mr.delete();
    this.model = null;
    this.thetaSource = null;
  }

  /** Level e of the cage; the editor is rebuilt from the current shape, reference volume kept. */
  setLevel(level) {
    if (!Number.isInteger(level)) throw new this.#mrvol.MrvolError(`level must be an integer, got ${level}`);
    if (this.model && (level < this.lowestLevel || level > this.model.info.levels))
      throw new this.#mrvol.MrvolError(`level ${level} is outside ${this.lowestLevel}..${this.model.info.levels}` +
        (level < this.lowestLevel ? ` (this mesh's analysis stops at level ${this.lowestLevel}: its base is a cube, whose first split is not invertible)` : ''));
    this.#changeCage({ level, scheme: this.scheme });
  }

  /** The wavelet scheme (loop, butterfly, linear); the editor is rebuilt as for setLevel. */
  setScheme(scheme) {
    if (this.model && (scheme === QUAD_SCHEME) !== this.quad)
      throw new this.#mrvol.MrvolError(this.quad
        ? `a quad mesh uses the ${QUAD_SCHEME} scheme, not ${scheme} (loop, butterfly and linear are for triangle meshes)`
        : `the ${QUAD_SCHEME} scheme is for quad meshes; this is a triangle mesh (loop, butterfly or linear)`);
    this.#changeCage({ level: this.level, scheme });
  }

  /**
   * Level and scheme changed as setLevel / setScheme do (one undo step unless `record` is false),
   * with the editor made elsewhere: `mr` is this model's mesh opened in another instance of the
   * module, at the current shape, whose first createEditor at `after` ({ level, scheme }) is made
   * already (lib/api.mjs adoptTransferred; the web app makes big models' editors in a worker). The
   * session owns `mr` from now on; the mesh before goes with its editor and tensors. The reference
   * volume, free set and history stay. `after` may also change the surface as setSurface does
   * ({ surface, keepCentroid, reference }: one 'surface' undo step; the new surface's volume now is
   * its reference unless `reference` is given, as when undoing). `reason` ('undo', 'redo'): the
   * change event said when the caller took a history step back or forth for this. `theta`
   * ({ source, info }): the editor was made with theta^e there (its tensor path needs no tensor here).
   */
  adoptRebuilt(mr, after, { record = true, reason = null, theta = null } = {}) {
    if (!this.editor) throw new this.#mrvol.MrvolError('no model is open');
    if (mr.vertexCount !== undefined && mr.vertexCount !== this.model.info.vertices)
      throw new this.#mrvol.MrvolError(`the mesh handed over has ${mr.vertexCount} vertices, this model ${this.model.info.vertices}`);
    this.cancelDrag();
    const before = { level: this.level, scheme: this.scheme };
    const surfaceBefore = this.#surfaceState();
    const surface = after.surface ?? this.surface;
    const changesSurface = surface !== this.surface || (after.keepCentroid !== undefined && after.keepCentroid !== this.keepCentroid);
    let reference = (this.editor.surface?.() ?? 'mesh') === surface ? this.editor.referenceVolume() : null;
    if (Number.isFinite(after.reference)) reference = after.reference;
    const old = this.model.mr, owned = this.#ownsMesh;
    for (const { theta } of this.#thetas.values()) theta?.delete();
    this.#thetas.clear();
    this.editor.delete();
    this.editor = null;
    if (owned) old.delete();
    this.model = { ...this.model, mr };
    this.#ownsMesh = true;
    this.level = after.level;
    this.scheme = after.scheme;
    this.surface = surface;
    if (after.keepCentroid !== undefined) this.keepCentroid = after.keepCentroid;
    if (surface === 'limit') this.keepCentroid = false;
    // the editor came with theta^e handed to it where it was made: its slot says so (no tensor here)
    if (theta) this.#thetas.set(this.#thetaSlot(), { theta: null, source: theta.source, info: theta.info });
    this.#buildEditor(reference);
    if (record && changesSurface) this.history.push(surfaceBefore, this.#surfaceState(), 'surface');
    else if (record && (before.level !== after.level || before.scheme !== after.scheme))
      this.history.push(before, { level: after.level, scheme: after.scheme }, 'editor');
    if (reason) this.#emit('change', { reason });
  }

  /** Level and scheme together; a rebuilt editor is one undo step. */
  #changeCage(after, { record = true } = {}) {
    const before = { level: this.level, scheme: this.scheme };
    this.level = after.level;
    this.scheme = after.scheme;
    if (!this.editor) return;
    try {
      this.#buildEditor();
    } catch (error) {
      // the editor before stays (#buildEditor makes the new one first), and so do its level and scheme
      this.level = before.level;
      this.scheme = before.scheme;
      throw error;
    }
    if (record && (before.level !== after.level || before.scheme !== after.scheme)) this.history.push(before, after, 'editor');
  }

  /** Turns preservation on or off (one undo step). */
  setPreserve(on) {
    on = Boolean(on);
    if (on === this.preserve) return;
    this.history.push(this.preserve, on, 'preserve');
    this.preserve = on;
    this.#emit('change', { reason: 'preserve' });
  }

  /**
   * The surface whose volume is kept: 'mesh' or 'limit' (closed meshes; the centre of mass is then
   * not kept). The editor is rebuilt and its reference becomes that surface's volume now. Throws
   * MrvolError (the session unchanged) when the mesh has no limit volume.
   */
  setSurface(surface) {
    if (surface !== 'mesh' && surface !== 'limit') throw new this.#mrvol.MrvolError(`surface must be 'mesh' or 'limit', got ${surface}`);
    if (surface === 'limit' && this.quad)
      throw new this.#mrvol.MrvolError('the limit surface is that of Loop triangle meshes: a quad mesh keeps its bilinear-patch volume');
    if (surface === this.surface || !this.editor) {
      this.surface = surface;
      if (surface === 'limit') this.keepCentroid = false;
      return;
    }
    const before = this.#surfaceState();
    this.surface = surface;
    if (surface === 'limit') this.keepCentroid = false;
    try {
      this.#buildEditor();
    } catch (error) {
      // the editor before stays (#buildEditor makes the new one first)
      this.surface = before.surface;
      this.keepCentroid = before.keepCentroid;
      throw error;
    }
    this.history.push(before, this.#surfaceState(), 'surface');
  }

  /** What a surface change changes: the surface, whether the centre of mass is kept, the reference volume. */
  #surfaceState() {
    return { surface: this.surface, keepCentroid: this.keepCentroid, reference: this.editor.referenceVolume() };
  }

  /**
   * Keeps the centre of mass where it is now (with the volume), or stops; mesh surface only. One undo
   * step when it changes.
   */
  setKeepCentroid(on) {
    on = Boolean(on);
    if (on && this.surface === 'limit')
      throw new this.#mrvol.MrvolError('the centre of mass is kept for the mesh surface only: switch the surface to mesh first');
    if (on && this.editor && !this.canKeepCentroid)
      throw new this.#mrvol.MrvolError('this editor keeps the volume only, not the centre of mass');
    if (on === this.keepCentroid) return;
    if (this.editor) this.history.push(this.keepCentroid, on, 'keep');
    this.keepCentroid = on;
    if (this.canKeepCentroid) this.editor.keepCentroid(on);
    this.#emit('change', { reason: 'keep' });
  }

  #shapeChanged() {
    this.#volume = null;
    this.#centroid = null;
  }

  /**
   * The mesh solid's centre of mass now (asked once per shape and kept: a pass over the fine mesh),
   * and the one kept (the current one when it is not kept).
   */
  centroid() {
    if (!this.canKeepCentroid) return null;
    this.#centroid ??= this.editor.centroid();
    return this.#centroid.slice();
  }
  referenceCentroid() { return this.canKeepCentroid ? this.editor.referenceCentroid() : null; }

  /**
   * Brings the volume back to the reference with every handle free to move (the minimal
   * correction of the whole cage): one undo step. Returns the core's report, or null when refused.
   */
  restoreReferenceVolume() {
    if (!this.editor || this.#drag) return null;
    const before = this.editor.cagePositions();
    const report = this.#step(before.slice(), new Uint8Array(this.cageSize), globalThis.performance.now(), { preserve: true });
    if (!report) return null;
    const after = this.editor.cagePositions();
    if (after.some((v, i) => v !== before[i])) this.history.push(before, after, 'drag');
    return report;
  }

  /** Rebuilds the editor at the current level and scheme from the current shape (keeps the reference). */
  #buildEditor(reference = null, { announce = true } = {}) {
    const { mr } = this.model;
    this.cancelDrag();
    if (this.editor) {
      mr.setPositions(this.editor.positions());
      // Another surface has another volume: its reference is its volume now.
      if ((this.editor.surface?.() ?? 'mesh') === this.surface) reference ??= this.editor.referenceVolume();
    }
    // 'matrix-free': until theta^e arrives (a theta source decides); 'auto': the cage polynomial
    // where the cage is coarse (no tensor needed), else matrix-free until theta^e arrives.
    const path = this.path === 'auto' ? this.gradientChoice().path : 'matrix-free';
    // created matrix-free, then the polynomial: the same editor, measured faster than createEditor's own path
    // keep: as an editor made in a worker was (lib/api.mjs hands it over for the same options)
    const keep = this.keepCentroid && !this.quad ? ['volume', 'centroid'] : undefined;
    // made before the editor before is let go: if this one cannot be made, that one stays
    const editor = mr.createEditor({ level: this.level, ...this.schemeOptions, path: 'matrix-free', surface: this.surface, keep });
    try {
      if (path === 'polynomial' && typeof editor.usePolynomial === 'function') editor.usePolynomial();
      if (reference !== null) editor.setReferenceVolume(reference);
      if (this.keepCentroid && typeof editor.keepCentroid === 'function') editor.keepCentroid(true);
    } catch (error) {
      editor.delete();
      throw error;
    }
    this.editor?.delete();
    this.editor = editor;
    this.#freeSetModes = this.quad ? quadFreeSetModes(editor) : FREE_SET_MODES;
    this.#shapeChanged();
    this.cageSize = editor.cageSize;
    this.cageVertices = editor.cageVertices();
    this.cageIndex = new Map(Array.from(this.cageVertices, (v, i) => [v, i]));
    this.#heldAll = new Uint8Array(editor.cageSize).fill(1);
    this.lastReport = null;
    this.lastStepMs = null;
    this.thetaSource = null;
    const stored = this.#thetas.get(this.#thetaSlot());
    if (stored && (stored.theta ? this.#tryTheta(stored.theta) : this.editor.path() === 'tensor')) this.thetaSource = stored.source;
    this.setFreeSet(this.freeSet, { quiet: true });
    if (!announce) return;
    this.#announceEditor();
    this.#emit('change', { reason: 'editor' });
  }

  #announceEditor() {
    this.#emit('editor', { level: this.level, scheme: this.scheme });
    this.#emit('theta', { source: this.thetaSource, path: this.editor.path() });
  }

  /** The level-e cage's edges, pairs of cage indices (a quad cage: the quads' sides). */
  cageEdges() {
    const { mr, quads } = this.model;
    return quads ? quadEdgesOf(mr.levelQuads(this.level), this.cageIndex) : edgesOf(mr.levelFaces(this.level), this.cageIndex);
  }

  /** The level-e cage's faces in cage indices: { corners: 3 | 4, faces: Uint32Array }. */
  cageFaces() {
    const { mr, quads } = this.model;
    const faces = quads ? mr.levelQuads(this.level) : mr.levelFaces(this.level);
    return { corners: quads ? 4 : 3, faces: Uint32Array.from(faces, (v) => this.cageIndex.get(v)) };
  }

  // ---- free set and parts -------------------------------------------------------------------------

  /**
   * The free set: { mode (FREE_SET_MODES), painted, parts } (caller's cage vertices; vertices not in
   * this cage are dropped, a vertex is in one part at most). Parts keep their volumes from now on.
   * An unknown mode falls back to 'minus-held'.
   */
  setFreeSet({ mode = this.freeSet.mode, painted = this.freeSet.painted, parts = this.freeSet.parts } = {}, { quiet = false } = {}) {
    const inCage = (v) => Number.isInteger(v) && this.cageIndex?.has(v);
    const seen = new Set();
    this.freeSet = {
      mode: this.#freeSetModes.includes(mode) ? mode : 'minus-held',
      painted: Array.isArray(painted) ? [...new Set(painted.filter(inCage))] : [],
      parts: Array.from({ length: MAX_PARTS }, (_, p) => {
        const list = Array.isArray(parts?.[p]) ? parts[p] : [];
        return list.filter((v) => inCage(v) && !seen.has(v) && seen.add(v));
      }),
    };
    const editor = this.editor;
    if (!editor) return;
    const { mode: m, painted: region } = this.freeSet;
    const active = m === 'parts'
      ? this.freeSet.parts.map((vertices, p) => ({ number: p + 1, vertices })).filter((part) => part.vertices.length > 0) : [];
    try {
      editor.setFreeSet({ cage: m === 'painted' ? region : m === 'all' ? 'all' : 'minus-held' });
      if (typeof editor.setParts === 'function') editor.setParts(active.map((part) => part.vertices));
      this.parts = active.map((part) => part.number);
      this.partReferences = active.length ? Array.from(editor.partVolumes()) : null;
    } catch (error) {
      this.parts = [];
      this.partReferences = null;
      this.#emit('error', { message: `The free set could not be set: ${error.message}`, error });
    }
    if (!quiet) this.#emit('change', { reason: 'free-set' });
  }

  /** Part volumes now (the editor's order, as `parts`), or null without parts. */
  partVolumes() {
    return this.editor && this.parts.length ? Array.from(this.editor.partVolumes()) : null;
  }

  // ---- editing --------------------------------------------------------------------------------------

  /** Starts a drag of these handles (cage indices); they are held where the drag puts them. */
  beginDrag(handles) {
    if (!this.editor) return;
    this.cancelDrag();
    const held = new Uint8Array(this.cageSize);
    for (const h of handles) {
      if (!Number.isInteger(h) || h < 0 || h >= this.cageSize)
        throw new this.#mrvol.MrvolError(`handle ${h} is not a cage index (0..${this.cageSize - 1})`);
      held[h] = 1;
    }
    this.#drag = { handles: [...handles], held, before: this.editor.cagePositions() };
  }

  /**
   * One drag step: the dragged handles at their start plus `delta` ([dx, dy, dz]), the volume
   * restored (when preserving). Returns the core's report; null when the edit was refused (the
   * drag is cancelled, the cage goes back, an `error` event says why).
   */
  dragBy(delta) {
    const drag = this.#drag;
    if (!drag) return null;
    const started = globalThis.performance.now();
    const target = this.editor.cagePositions();
    for (const h of drag.handles)
      for (let k = 0; k < 3; k++) target[3 * h + k] = drag.before[3 * h + k] + delta[k];
    const report = this.#step(target, drag.held, started);
    // Refused (e.g. a boundary vertex of an open mesh, which stays fixed): the cage goes back.
    if (!report) this.cancelDrag();
    return report;
  }

  /**
   * Moves the whole cage to `target` (Float64Array, 3 per handle, cage order), the `held` handles
   * (flags, cage order) staying where it puts them, the volume restored when preserving: one step
   * (animations drive the cage this way). The report, or null when refused (an `error` event).
   */
  setCage(target, held) {
    if (this.#drag) this.cancelDrag();
    return this.#step(target, held, globalThis.performance.now());
  }

  #step(target, held, started, { preserve = this.preserve } = {}) {
    let report;
    try {
      report = this.editor.deformCage(target, held, { tolerance: this.tolerance, preserve });
    } catch (error) {
      this.#shapeChanged();
      this.#emit('error', { message: `This edit is not possible: ${error.message}`, error });
      return null;
    }
    this.#shapeChanged(); // asked once per step (the report's volumeResult may come from the cage polynomial)
    // ...but a drag's readouts take the step's own (volumeNow)
    if (this.#drag && this.parts.length === 0 && Number.isFinite(report.volumeResult)) this.#drag.volume = report.volumeResult;
    this.lastReport = report;
    this.lastStepMs = globalThis.performance.now() - started;
    this.#emit('step', { report, ms: this.lastStepMs });
    this.#emit('change', { reason: 'step' });
    return report;
  }

  /** Ends the drag: one undo step when the cage moved. */
  endDrag() {
    const drag = this.#drag;
    this.#drag = null;
    if (!drag) return;
    const after = this.editor.cagePositions();
    if (after.some((v, i) => v !== drag.before[i])) this.history.push(drag.before, after);
    this.#emit('dragend', {});
  }

  /** Abandons the drag: the cage goes back to where it started. */
  cancelDrag() {
    const drag = this.#drag;
    this.#drag = null;
    if (drag) this.#restoreCage(drag.before, 'cancel');
  }

  /** A whole drag at once: handles moved by delta (one undo step). Returns the report or null. */
  moveHandles(handles, delta) {
    this.beginDrag(handles);
    const report = this.dragBy(delta);
    this.endDrag();
    return report;
  }

  undo() {
    if (this.#drag || !this.editor) return false;
    const step = this.history.undo();
    if (step) this.#apply(step, step.before, 'undo');
    return Boolean(step);
  }

  redo() {
    if (this.#drag || !this.editor) return false;
    const step = this.history.redo();
    if (step) this.#apply(step, step.after, 'redo');
    return Boolean(step);
  }

  /** Puts back one side (`state`) of a history step. */
  #apply(step, state, reason) {
    if (step.label === 'editor') {
      this.#changeCage(state, { record: false });
      this.#emit('change', { reason });
    } else if (step.label === 'reference') {
      this.editor.setReferenceVolume(state);
      if (this.parts.length) this.setFreeSet(this.freeSet, { quiet: true });
      this.#emit('change', { reason });
    } else if (step.label === 'preserve') {
      this.preserve = state;
      this.#emit('change', { reason });
    } else if (step.label === 'keep') {
      this.keepCentroid = state;
      this.editor.keepCentroid(state);
      this.#emit('change', { reason });
    } else if (step.label === 'surface') {
      // the surface's own reference volume comes back with it
      this.surface = state.surface;
      this.keepCentroid = state.keepCentroid;
      this.#buildEditor(state.reference);
      this.#emit('change', { reason });
    } else {
      this.#restoreCage(state, reason);
    }
  }

  /** Puts the cage where a snapshot had it (details unchanged: the shape comes back). */
  #restoreCage(cage, reason) {
    this.editor.deformCage(cage, this.#heldAll, { preserve: false });
    this.#shapeChanged();
    this.lastReport = null;
    this.#emit('change', { reason });
  }

  /** The reference volume (default: the volume now); parts take theirs now too. */
  setReferenceVolume(volume = this.volume()) {
    const before = this.editor.referenceVolume();
    this.editor.setReferenceVolume(volume);
    if (volume !== before) this.history.push(before, volume, 'reference');
    if (this.parts.length) this.setFreeSet(this.freeSet, { quiet: true });
    this.#emit('change', { reason: 'reference' });
  }

  /** The volume now: the core's (a pass over the fine mesh), asked once per shape and kept. */
  volume() {
    if (!this.editor) return null;
    this.#volume ??= this.editor.volume();
    return this.#volume;
  }
  /**
   * The volume now, for readouts: during a drag, the last step's own (the correction's value, equal
   * to the mesh's to round-off: on the polynomial path the cage cubic's), which spares a pass over
   * the fine mesh at every step (46 ms at 655k vertices); else volume(). A `dragend` listener asks
   * volume() once the drag is over.
   */
  volumeNow() {
    return this.#drag?.volume ?? this.volume();
  }
  referenceVolume() { return this.editor?.referenceVolume() ?? null; }
  /** Fine positions (caller's order) and cage positions (cage order), copies. */
  positions() { return this.editor.positions(); }
  cagePositions() { return this.editor.cagePositions(); }
  /** The level-l approximation of the current shape, or of `positions` (MultiresMesh.approximation). */
  approximation(level, positions = this.editor.positions()) {
    return this.model.mr.approximation(positions, { level, ...this.schemeOptions });
  }

  // ---- the volume tensor ----------------------------------------------------------------------------

  #thetaSlot() { return `${this.scheme}/${this.alpha}/${this.beta}/${this.level}`; }

  #tryTheta(theta) {
    try {
      this.editor.useTheta(theta);
      return true;
    } catch {
      return false;
    }
  }

  /**
   * The gradient path the rule picks for the current level (chooseGradientPath, theta^e computed in
   * the background): 'tensor' when theta^e fits (with path 'auto': 'polynomial' instead), else
   * 'polynomial' on a coarse cage, else 'matrix-free'; { path, estimate, reason (when not the estimate) }.
   */
  gradientChoice() {
    // Quads: theta^e is not computed in the background (the app's worker builds triangle tensors);
    // the cage polynomial where the quad editor has it and the cage is coarse, else matrix-free.
    if (this.quad && this.surface !== 'limit') {
      const polynomial = !this.editor || typeof this.editor.usePolynomial === 'function';
      const coarse = polynomial && this.path === 'auto' && this.model.info.levels - this.level >= COARSE_CAGE_LEVELS;
      return coarse ? { path: 'polynomial', estimate: null }
        : { path: 'matrix-free', estimate: null, reason: 'not used: a quad mesh edits matrix-free (the bilinear-patch volume of the fine quads)' };
    }
    // asked more than once per editor (the editor's build, the theta source): theta^e's estimate is a
    // pass over the hierarchy (0.7 s at 655k vertices, level 6), kept per model, level, scheme, surface, path
    if (this.#choices.model !== this.model.fingerprint) this.#choices = { model: this.model.fingerprint, map: new Map() };
    const key = `${this.#thetaSlot()}/${this.surface}/${this.path}`;
    if (!this.#choices.map.has(key))
      this.#choices.map.set(key, triangleGradientChoice(this.model.mr, { level: this.level, ...this.schemeOptions, surface: this.surface, path: this.path }));
    return { ...this.#choices.map.get(key) };
  }
  #choices = { model: null, map: new Map() };

  /**
   * The tensor kept for the current level and scheme, or null: { theta, source }, or { theta: null,
   * source, info } when it was handed to an editor made elsewhere (adoptRebuilt).
   */
  storedTheta() { return this.#thetas.get(this.#thetaSlot()) ?? null; }

  /**
   * Hands theta^e to the editor (the session owns it from now on, until the model changes).
   * Returns { ok, reason }; a refused tensor is not kept (the caller deletes it).
   */
  useTheta(theta, source = 'computed') {
    try {
      this.editor.useTheta(theta);
    } catch (error) {
      return { ok: false, reason: error.message };
    }
    const slot = this.#thetaSlot();
    const old = this.#thetas.get(slot);
    if (old && old.theta !== theta) old.theta?.delete();
    this.#thetas.set(slot, { theta, source });
    this.thetaSource = source;
    this.#emit('theta', { source, path: this.editor.path() });
    return { ok: true };
  }

  /** Drops the tensor of the current level and scheme; the editor runs matrix-free (with path 'auto': its choice). */
  forgetTheta() {
    const slot = this.#thetaSlot();
    if (this.path === 'auto' && this.gradientChoice().path === 'polynomial' && typeof this.editor?.usePolynomial === 'function')
      this.editor.usePolynomial();
    else this.editor?.useMatrixFree();
    this.#thetas.get(slot)?.theta?.delete();
    this.#thetas.delete(slot);
    this.thetaSource = null;
    this.#emit('theta', { source: null, path: this.editor?.path() ?? 'matrix-free' });
  }

  /** Computes theta^e here (synchronously) and uses it. */
  computeTheta() {
    const theta = this.model.mr.computeTheta({ level: this.level, ...this.schemeOptions });
    const used = this.useTheta(theta, 'computed');
    if (!used.ok) theta.delete();
    return used;
  }

  /** Frees the editor, the tensors and (when the session opened it) the mesh. */
  dispose() {
    this.#closeModel();
  }
}

/**
 * The free sets a quad editor takes: the cage minus the held handles and all of it; a painted list
 * when lib/quad.mjs's editor takes vertex lists (tried with an empty list, which changes nothing).
 */
function quadFreeSetModes(editor) {
  const modes = ['minus-held', 'all'];
  try {
    editor.setFreeSet({ cage: [] });
    modes.push('painted');
  } catch { /* the cage minus held and all only */ }
  editor.setFreeSet({ cage: 'minus-held' });
  // parts: lib/quad.mjs's setParts refuses any part for now (quads keep one global volume)
  return Object.freeze(modes);
}
