// Whether the surface intersects itself (lib/self-intersection.mjs, stopped at the first pair within a piece). Run after each
// edit (not during drags), in a worker (SelfIntersectionChecker); meshes over MAX_FACES triangles are
// not checked (null).
import { selfIntersections } from '../lib/self-intersection.mjs';

export const MAX_FACES = 200_000;

/**
 * positions: Float64Array (3 per vertex), faces: Uint32Array (3 per triangle). Returns
 * { intersects: boolean, pair: [i, j] (caller's face indices) | null, piecesOverlap: [i, j] | null, ms }
 * or null when not checked. intersects: a piece crosses itself (its volume counts the overlap with
 * opposite signs); piecesOverlap: two closed pieces pass through each other (a teapot's spout into its
 * body, as many files have them: each piece's volume is right, their overlap is counted in both).
 */
export function findSelfIntersection(positions, faces) {
  if (faces.length / 3 > MAX_FACES) return null;
  const started = performance.now();
  const { firstWithin, firstBetween } = selfIntersections(positions, faces, { limitWithin: 1 });
  return { intersects: firstWithin !== null, pair: firstWithin, piecesOverlap: firstBetween, ms: performance.now() - started };
}

/**
 * The check in a worker (self-intersection-worker.js), the page's thread free meanwhile: check(positions,
 * faces) resolves to findSelfIntersection's result, or to undefined when a later check replaced it.
 * The faces are sent again only when they are another array (another model).
 */
export class SelfIntersectionChecker {
  #worker = null;
  #faces = null;
  #latest = 0;
  #waiting = new Map(); // id -> resolve

  check(positions, faces) {
    // Not checked: no copy of the positions made, nothing sent (a copy of 655k vertices took 15-54 ms).
    if (faces.length / 3 > MAX_FACES) return Promise.resolve(null);
    if (!this.#worker) {
      this.#worker = new Worker(new URL('./self-intersection-worker.js', import.meta.url), { type: 'module', name: 'mrvol-self-intersection' });
      this.#worker.onmessage = ({ data }) => {
        const resolve = this.#waiting.get(data.id);
        this.#waiting.delete(data.id);
        if (data.error) console.warn(`the self-intersection check failed: ${data.error}`);
        resolve?.(data.id === this.#latest && !data.error ? data.found : undefined);
      };
      this.#faces = null;
    }
    const id = ++this.#latest;
    const message = { id, positions };
    if (faces !== this.#faces) message.faces = faces.slice(); // the page keeps its own
    this.#faces = faces;
    // an array of its own is moved, not copied (never a view of the core's memory)
    this.#worker.postMessage(message, positions.byteLength === positions.buffer.byteLength ? [positions.buffer] : []);
    return new Promise((resolve) => this.#waiting.set(id, resolve));
  }
}
