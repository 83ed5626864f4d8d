// Pointer geometry for dragging handles, shared by the mrvol/three component and the web editor's
// drag controls: handles projected to the screen, the nearest one under the pointer, and a drag on
// the plane through the grabbed handle facing the camera. No DOM events here.
import * as THREE from 'three';

const scratch = new THREE.Vector3();

/**
 * Handle positions (flat, 3 per handle, world) on the screen of a `width` x `height` CSS-pixel
 * element: out = [x0, y0, x1, y1, ...]; the depth of each (NDC z) in `depths` when given.
 */
export function projectPoints(positions, camera, width, height, out = new Float64Array(2 * (positions.length / 3)), depths = null) {
  camera.updateMatrixWorld();
  for (let i = 0, n = positions.length / 3; i < n; i++) {
    scratch.fromArray(positions, 3 * i).project(camera);
    out[2 * i] = (scratch.x + 1) / 2 * width;
    out[2 * i + 1] = (1 - scratch.y) / 2 * height;
    if (depths) depths[i] = scratch.z;
  }
  return out;
}

/**
 * The handle nearest to (x, y) on the screen within `radius` pixels, or -1: projected handles
 * `screen` and their `depths` (projectPoints); between handles about as near, the one in front.
 */
export function nearestOnScreen(screen, depths, x, y, radius) {
  let best = -1, bestD = Infinity, bestZ = Infinity;
  for (let i = 0, n = depths.length; i < n; i++) {
    const z = depths[i];
    if (z < -1 || z > 1) continue; // behind the camera or clipped
    const dx = screen[2 * i] - x, dy = screen[2 * i + 1] - y;
    const d = dx * dx + dy * dy;
    if (d > radius * radius) continue;
    if (best < 0 || d < bestD - 1 || (Math.abs(d - bestD) <= 1 && z < bestZ)) {
      best = i;
      bestD = d;
      bestZ = z;
    }
  }
  return best;
}

/** The ray from the camera through (x, y), CSS pixels of a `width` x `height` element. */
export function rayThrough(camera, x, y, width, height, ray = new THREE.Ray()) {
  const ndcX = x / width * 2 - 1, ndcY = 1 - y / height * 2;
  camera.updateMatrixWorld();
  ray.origin.setFromMatrixPosition(camera.matrixWorld);
  ray.direction.set(ndcX, ndcY, 0.5).unproject(camera).sub(ray.origin).normalize();
  if (camera.isOrthographicCamera) {
    // Parallel rays: from the near plane at (x, y), along the view direction.
    ray.origin.set(ndcX, ndcY, -1).unproject(camera);
    camera.getWorldDirection(ray.direction);
  }
  return ray;
}

/**
 * A drag on the plane through a grabbed point facing the camera: start() where the pointer ray
 * meets it, delta() the displacement since then ([dx, dy, dz], or null when the ray misses it).
 */
export class DragPlane {
  #plane = new THREE.Plane();
  #origin = new THREE.Vector3();
  #hit = new THREE.Vector3();

  /** false when the ray does not meet the plane (then no drag). */
  start(camera, ray, point) {
    const normal = camera.getWorldDirection(new THREE.Vector3());
    this.#plane.setFromNormalAndCoplanarPoint(normal, point);
    return ray.intersectPlane(this.#plane, this.#origin) !== null;
  }

  delta(ray) {
    if (!ray.intersectPlane(this.#plane, this.#hit)) return null;
    return [this.#hit.x - this.#origin.x, this.#hit.y - this.#origin.y, this.#hit.z - this.#origin.z];
  }
}
