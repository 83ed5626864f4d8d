// Module worker for the self-intersection check (self-intersection.js): on the dragon the BVH and its
// cast took 0.2 s of the page's thread (0.5-1.7 s wall on a loaded machine) after every edit and
// right as a big θ was handed over (issue 13: no long computation on the main thread).
// Message in:  { id, positions: Float64Array, faces?: Uint32Array (only when the model changed) }
// Message out: { id, found } (findSelfIntersection's result, or null when not checked), or { id, error }
import { findSelfIntersection } from './self-intersection.js';

let faces = null;

self.onmessage = ({ data: { id, positions, faces: newFaces } }) => {
  try {
    if (newFaces) faces = newFaces;
    self.postMessage({ id, found: findSelfIntersection(positions, faces) });
  } catch (e) {
    self.postMessage({ id, error: e?.message ?? String(e) });
  }
};
