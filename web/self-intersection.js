// Whether the surface intersects itself: a BVH of the fine triangles (three-mesh-bvh) cast against
// itself, triangle pairs that share a vertex skipped (they touch by construction). Run after each
// edit (not during drags), in a worker (SelfIntersectionChecker); meshes over MAX_FACES triangles are
// not checked (null).
import * as THREE from 'three';
import { MeshBVH } from 'three-mesh-bvh';

const MAX_FACES = 200_000;
const identity = new THREE.Matrix4();

/**
 * positions: Float64Array (3 per vertex), faces: Uint32Array (3 per triangle). Returns
 * { intersects: boolean, pair: [i, j] (caller's face indices) | null, ms } or null when not checked.
 */
export function findSelfIntersection(positions, faces) {
  const faceCount = faces.length / 3;
  if (faceCount > MAX_FACES) return null;
  const started = performance.now();
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(Float32Array.from(positions), 3));
  // the BVH reorders the index; a face id attribute is not needed: the original face of a reordered
  // triangle is found by its vertices only when reported
  geometry.setIndex(new THREE.BufferAttribute(Uint32Array.from(faces), 1));
  const bvh = new MeshBVH(geometry);
  const index = geometry.index.array;
  let pair = null;
  bvh.bvhcast(bvh, identity, {
    intersectsTriangles(t1, t2, i1, i2) {
      if (i1 >= i2) return false;
      const a = 3 * i1, b = 3 * i2;
      for (let p = 0; p < 3; p++)
        for (let q = 0; q < 3; q++) if (index[a + p] === index[b + q]) return false;
      if (!t1.intersectsTriangle(t2)) return false;
      pair = [originalFace(faces, index, a), originalFace(faces, index, b)];
      return true;
    },
  });
  geometry.dispose();
  return { intersects: pair !== null, pair, ms: performance.now() - started };
}

function originalFace(faces, index, offset) {
  const key = [index[offset], index[offset + 1], index[offset + 2]].sort((x, y) => x - y).join(',');
  for (let f = 0; f < faces.length; f += 3)
    if ([faces[f], faces[f + 1], faces[f + 2]].sort((x, y) => x - y).join(',') === key) return f / 3;
  return -1;
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
