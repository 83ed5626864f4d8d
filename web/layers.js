// The optional layers over the editor's mesh: the level-l approximation of the current shape
// (MultiresMesh.approximation, computed by the core) and the detail vectors from it to the fine
// positions. Recomputed after every drag step while that is cheap, else once the drag ends.
import { showLayers } from './readouts.js';

// The layers follow every drag step while an update costs less than this (the median of the last
// few: one slow update, a pause of the page, does not stop them for the rest of the drag).
const LAYER_BUDGET_MS = 4;
const RECENT = 5;

export class Layers {
  level = null;
  updates = 0;
  lastMs = null;
  deferred = false;
  #dirty = false;
  #recent = [];

  /** settings: { showApprox, approxLevel, showDetails } (read at each update). */
  constructor(session, viewer, settings, onMeasured = () => {}) {
    this.session = session;
    this.viewer = viewer;
    this.settings = settings;
    this.onMeasured = onMeasured;
  }

  get shown() { return this.settings.showApprox || this.settings.showDetails; }

  /** Recomputes the shown layers from the current shape. */
  update() {
    this.#dirty = false;
    const session = this.session;
    if (!session.editor || !this.shown) {
      this.#show();
      return;
    }
    const started = performance.now();
    const l = Math.max(0, Math.min(session.model.info.levels, Math.round(this.settings.approxLevel)));
    const fine = session.positions();
    const approx = session.approximation(l, fine);
    if (this.settings.showApprox) this.viewer.updateApprox(approx);
    if (this.settings.showDetails) this.viewer.updateDetails(approx, fine);
    const ms = performance.now() - started;
    this.level = l;
    this.updates++;
    this.lastMs = ms;
    this.#recent.push(ms);
    if (this.#recent.length > RECENT) this.#recent.shift();
    this.onMeasured(ms);
    this.#show();
  }

  /** After a drag step: now while cheap, else marked for the end of the drag. */
  afterStep() {
    if (!this.shown) return;
    const sorted = [...this.#recent].sort((a, b) => a - b);
    this.deferred = sorted.length > 0 && sorted[Math.floor(sorted.length / 2)] > LAYER_BUDGET_MS;
    if (this.deferred) this.#dirty = true;
    else this.update();
  }

  /** The drag ended: the deferred update, if one is due. */
  afterDrag() {
    if (this.#dirty) this.update();
  }

  #show() {
    showLayers({ shown: this.shown, level: this.level, lastMs: this.lastMs, deferred: this.deferred });
  }
}
