// Draws the editor's surface from its float32 buffers in WASM memory (editor.positionsView() and
// normalsView(): written in place by the core, normals included, only what an edit changed), into
// the mesh's BufferAttributes: only the vertices the core rewrote are copied (a few hundred after
// a small edit, all after a move of the whole cage) and only those uploaded (addUpdateRange). The
// attributes keep arrays of their own rather than views of WASM memory: a view is detached whenever
// the memory grows, and three.js may read an attribute again at any time (a context restore,
// framing). Nothing is allocated per frame beyond a few small views.
import { BufferAttribute } from 'three';

/** Copies the rewritten vertices [first, first + count) of `view` into the attribute and marks them. */
function copyVertices(attribute, view, first, count) {
  if (count <= 0) return;
  attribute.array.set(view.subarray(3 * first, 3 * (first + count)), 3 * first);
  attribute.addUpdateRange(3 * first, 3 * count);
  attribute.needsUpdate = true;
}

export class SurfaceUpload {
  // What each attribute holds: the editor and geometry it was filled for and the surface version.
  #positions = { editor: null, attribute: null, version: -1 };
  #normals = { editor: null, attribute: null, version: -1 };
  /** Vertices copied by the last draw that copied anything, per attribute (for the tests). */
  lastCopied = { positions: 0, normals: 0 };

  /**
   * Brings the geometry's position (and, with `normals`, normal) attribute in step with the editor.
   * Returns whether anything was copied (lastCopied says how much).
   */
  draw(geometry, editor, { normals = true } = {}) {
    // normalsView first: it brings the positions up to date as well; positionsView then only
    // returns the view (a later call may grow WASM memory and detach an earlier view: take both
    // before reading either, and the normals again if they were detached meanwhile).
    let normalView = normals ? editor.normalsView() : null;
    const positionView = editor.positionsView();
    if (normalView && normalView.length === 0) normalView = editor.normalsView();
    const version = editor.surfaceVersion;
    const ranges = editor.updatedRanges();
    const copiedBefore = { ...this.lastCopied };
    this.lastCopied.normals = 0;
    this.lastCopied.positions = this.#fill(this.#positions, geometry.getAttribute('position'), editor, positionView, version, ranges.positions);
    let copied = this.lastCopied.positions > 0;
    if (normalView) {
      let attribute = geometry.getAttribute('normal');
      if (!attribute || attribute.count !== positionView.length / 3) {
        attribute = new BufferAttribute(new Float32Array(positionView.length), 3);
        geometry.setAttribute('normal', attribute);
      }
      this.lastCopied.normals = this.#fill(this.#normals, attribute, editor, normalView, version, ranges.normals);
      copied ||= this.lastCopied.normals > 0;
    }
    if (!copied) this.lastCopied = copiedBefore;
    return copied;
  }

  /**
   * Takes the geometry's position attribute as holding the editor's surface as it is (filled from
   * the same positions, as float32: a model just opened): the editor's buffers are brought up to
   * date (built on their first use), nothing is copied or marked for upload; the next draw copies
   * only what an edit rewrote.
   */
  takeInStep(geometry, editor) {
    editor.positionsView();
    Object.assign(this.#positions, { editor, attribute: geometry.getAttribute('position'), version: editor.surfaceVersion });
  }

  // One attribute: nothing when it holds this version; the rewritten range when it holds the one
  // before; everything otherwise (another editor or geometry, or versions it missed).
  // Returns how many vertices it copied.
  #fill(state, attribute, editor, view, version, range) {
    const same = state.editor === editor && state.attribute === attribute;
    if (same && state.version === version) return 0;
    attribute.clearUpdateRanges();
    const { first, count } = same && state.version === version - 1 ? range : { first: 0, count: view.length / 3 };
    copyVertices(attribute, view, first, count);
    Object.assign(state, { editor, attribute, version });
    return count;
  }
}
