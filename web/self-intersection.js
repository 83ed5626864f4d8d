// Whether the surface intersects itself (lib/self-intersection.mjs, stopped at the first pair). Run after each
// edit (not during drags), in a worker (SelfIntersectionChecker); meshes over MAX_FACES triangles are
// not checked (null).
import { selfIntersections } from '../lib/self-intersection.mjs';

const MAX_FACES = 200_000;

/**
 * positions: Float64Array (3 per vertex), faces: Uint32Array (3 per triangle). Returns
 * { intersects: boolean, pair: [i, j] (caller's face indices) | null, ms } or null when not checked.
 */
export function findSelfIntersection(positions, faces) {
  if (faces.length / 3 > MAX_FACES) return null;
  const started = performance.now();
  const { first } = selfIntersections(positions, faces, { limit: 1 });
  return { intersects: first !== null, pair: first, ms: performance.now() - started };
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
