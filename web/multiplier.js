// The correction's multiplier λ of one drag step (the paper's formula (6): the free handles move by
// λ times the volume gradient): the handles' move in the step, not counting the held ones, as a
// multiple of the gradient there (least squares), as the demos plot it (learn/demo-common.js).
const MATRIX_FREE_MAX_VERTICES = 100_000; // the matrix-free gradient is a pass over the fine mesh

const hierarchyIndices = new WeakMap(); // model -> cage index -> hierarchy index (matrix-free gradient)

/**
 * λ of the step that moved the cage from `before` (cage positions, cage order) to where it is now,
 * the `held` handles (cage indices) excluded; null when it cannot be had cheaply.
 */
export function stepMultiplier(session, before, held) {
  const editor = session.editor;
  // a quad editor has no gradient readout (lib/quad.mjs): no multiplier then
  if (!editor || typeof editor.gradient !== 'function') return null;
  const after = editor.cagePositions();
  const path = editor.path();
  let gradient, index = null;
  if (path === 'tensor' || path === 'polynomial') {
    gradient = editor.gradient(path); // cage order
  } else {
    if (session.model.info.vertices > MATRIX_FREE_MAX_VERTICES) return null;
    // a quad mesh has no hierarchy order to map the matrix-free gradient with (lib/quad.mjs)
    if (typeof session.model.mr.hierarchyOrder !== 'function') return null;
    gradient = editor.gradient('matrix-free'); // hierarchy order, all vertices
    index = hierarchyIndices.get(session.model);
    if (!index || index.length !== session.cageSize) {
      const position = new Map(Array.from(session.model.mr.hierarchyOrder(), (v, h) => [v, h]));
      index = Uint32Array.from(session.cageVertices, (v) => position.get(v));
      hierarchyIndices.set(session.model, index);
    }
  }
  const heldSet = new Set(held);
  let dg = 0, gg = 0;
  for (let c = 0; c < session.cageSize; c++) {
    if (heldSet.has(c)) continue;
    const g = index ? 3 * index[c] : 3 * c;
    let moved = false;
    for (let k = 0; k < 3; k++) if (after[3 * c + k] !== before[3 * c + k]) moved = true;
    if (!moved) continue; // not free in this step (or no correction)
    for (let k = 0; k < 3; k++) {
      dg += (after[3 * c + k] - before[3 * c + k]) * gradient[g + k];
      gg += gradient[g + k] ** 2;
    }
  }
  return gg > 0 ? dg / gg : 0;
}
