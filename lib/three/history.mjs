// Undo/redo of cage edits. One drag is one step: the cage positions before and after it (the
// details never change while editing, so the cage alone gives the shape back).
export class History {
  #undo = [];
  #redo = [];
  constructor(limit = 200) {
    this.limit = limit;
  }
  /** Records one finished edit. before/after: Float64Array cage positions. */
  push(before, after, label = 'drag') {
    this.#undo.push({ before, after, label });
    if (this.#undo.length > this.limit) this.#undo.shift();
    this.#redo.length = 0;
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
  clear() {
    this.#undo.length = 0;
    this.#redo.length = 0;
  }
  get canUndo() { return this.#undo.length > 0; }
  get canRedo() { return this.#redo.length > 0; }
  get size() { return { undo: this.#undo.length, redo: this.#redo.length }; }
}
