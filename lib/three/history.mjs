// Undo/redo of the editing session (lib/three/session.mjs). A step is { before, after, label }: a drag
// ('drag': Float64Array cage positions; the details never change while editing, so the cage alone
// gives the shape back), a level or scheme change ('editor': { level, scheme }), a reference volume
// ('reference': numbers), a preservation toggle ('preserve': booleans), a keep-balance toggle ('keep':
// booleans) or a surface change ('surface': { surface, keepCentroid, reference }).
// It keeps the last `limit` steps; the oldest is let go as a new one comes, and `onDrop` is told so
// (the step let go), since an undo that stops short of where the user started is work lost.
export class History {
  #undo = [];
  #redo = [];
  #onDrop;
  constructor(limit = 200, { onDrop = null } = {}) {
    this.limit = limit;
    this.#onDrop = onDrop;
  }
  /** Records one finished edit (see above for what before/after are per label). */
  push(before, after, label = 'drag') {
    this.#undo.push({ before, after, label });
    this.#redo.length = 0;
    if (this.#undo.length > this.limit) this.#onDrop?.(this.#undo.shift());
  }
  /** The step to undo (its `before` is the cage to go back to), or null. */
  undo() {
    const step = this.#undo.pop();
    if (!step) return null;
    this.#redo.push(step);
    return step;
  }
  /** The step to redo (its `after` is the cage to go to), or null. */
  redo() {
    const step = this.#redo.pop();
    if (!step) return null;
    this.#undo.push(step);
    return step;
  }
  /** The step undo() or redo() would return next, left in place; or null. */
  peekUndo() { return this.#undo.at(-1) ?? null; }
  peekRedo() { return this.#redo.at(-1) ?? null; }
  /** The recorded steps, oldest first, for storing: { undo: [...], redo: [...] } (copies of the lists). */
  steps() {
    return { undo: [...this.#undo], redo: [...this.#redo] };
  }
  /** Replaces the history with stored steps (from steps()); steps that are not { before, after, label } are skipped. */
  load({ undo = [], redo = [] } = {}) {
    const valid = (step) => step && 'before' in step && 'after' in step && typeof step.label === 'string';
    this.#undo = undo.filter(valid).slice(-this.limit);
    this.#redo = redo.filter(valid);
  }
  clear() {
    this.#undo.length = 0;
    this.#redo.length = 0;
  }
  get canUndo() { return this.#undo.length > 0; }
  get canRedo() { return this.#redo.length > 0; }
  get size() { return { undo: this.#undo.length, redo: this.#redo.length }; }
}
