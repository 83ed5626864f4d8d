// One Catmull-Clark level's lifting steps (QuadMultiresMesh.liftingSteps: targets, offsets, sources,
// weights in the caller's vertex order) applied phase by phase in JS, for the teaching views: the
// first k steps of synthesis, the last k undone in reverse order (analysis), or the last k
// transposed in reverse order (the masks applied outwards, docs/catmull-clark.md section 3). Every
// step reads only other vertices than it writes (docs/catmull-clark.md section 2), so the rows run
// in place in any order.

/**
 * @param {Array<object>} steps the level's steps, in synthesis order
 * @param {Float64Array} x 3 per vertex, caller's order (not changed: a copy is returned)
 * @param {'synthesize' | 'analyze' | 'transpose'} direction
 * @param {number} count how many phases (0..steps.length)
 * @returns {Float64Array}
 */
export function applyQuadSteps(steps, x, direction, count = steps.length) {
  const out = Float64Array.from(x);
  const k = Math.max(0, Math.min(steps.length, count));
  const chosen = direction === 'synthesize' ? steps.slice(0, k) : steps.slice(steps.length - k).reverse();
  for (const step of chosen) {
    const { targets, offsets, sources, weights } = step;
    for (let r = 0; r < targets.length; r++) {
      const t = 3 * targets[r];
      if (step.scaling) {
        const factor = direction === 'analyze' ? 1 / weights[r] : weights[r];
        for (let c = 0; c < 3; c++) out[t + c] *= factor;
        continue;
      }
      for (let q = offsets[r]; q < offsets[r + 1]; q++) {
        const s = 3 * sources[q], w = weights[q];
        for (let c = 0; c < 3; c++) {
          if (direction === 'transpose') out[s + c] += w * out[t + c];  // outwards: the target pushes to its sources
          else if (direction === 'analyze') out[t + c] -= w * out[s + c];
          else out[t + c] += w * out[s + c];
        }
      }
    }
  }
  return out;
}
