// Handle dots sized to how dense the cage looks on the screen: a cage of 600 handles seen whole on
// a phone would overlap into a blob at a fixed 13 px. The size follows the median on-screen length
// of the cage's edges (a sample of them), clamped: zoomed in, the dots grow back to their full size.
// Pure functions (no three.js, no DOM): the CageObject calls them when the view or the cage changed.

/** 'auto' handle size: k times the median edge length on the screen, within [min, max] CSS px. */
export const AUTO_HANDLE_SIZE = Object.freeze({ k: 0.55, min: 6, max: 13 });

/** At most this many edges are projected to measure the spacing (evenly spread over the list). */
export const SPACING_SAMPLES = 256;

/**
 * The handle dot size (CSS px) for a median on-screen edge length `spacing` (CSS px):
 * clamp(k * spacing, min, max), in quarter pixels; max when the spacing is unknown (no edge seen).
 */
export function handleSizeForSpacing(spacing, { k = AUTO_HANDLE_SIZE.k, min = AUTO_HANDLE_SIZE.min, max = AUTO_HANDLE_SIZE.max } = {}) {
  if (!(spacing > 0) || !Number.isFinite(spacing)) return max;
  return Math.min(max, Math.max(min, Math.round(4 * k * spacing) / 4));
}

/**
 * The median on-screen length (CSS px) of the edges (pairs of indices into `positions`, flat, 3 per
 * point) under `matrix` (16 numbers, column-major: projection * view * model), on a `width` x
 * `height` CSS-pixel view. Edges with an end behind the camera or clipped in depth are left out; at
 * most `samples` edges are looked at. NaN when none is seen.
 */
export function medianEdgeSpacing(positions, edges, matrix, width, height, samples = SPACING_SAMPLES) {
  const count = Math.floor(edges.length / 2);
  const stride = Math.max(1, Math.ceil(count / samples));
  const lengths = new Float64Array(Math.ceil(count / stride));
  const m = matrix;
  let n = 0;
  const a = [0, 0], b = [0, 0];
  const project = (i, out) => {
    const x = positions[3 * i], y = positions[3 * i + 1], z = positions[3 * i + 2];
    const w = m[3] * x + m[7] * y + m[11] * z + m[15];
    if (!(w > 0)) return false;
    const depth = (m[2] * x + m[6] * y + m[10] * z + m[14]) / w;
    if (depth < -1 || depth > 1) return false;
    out[0] = (m[0] * x + m[4] * y + m[8] * z + m[12]) / w * width / 2;
    out[1] = (m[1] * x + m[5] * y + m[9] * z + m[13]) / w * height / 2;
    return true;
  };
  for (let e = 0; e < count; e += stride) {
    if (!project(edges[2 * e], a) || !project(edges[2 * e + 1], b)) continue;
    lengths[n++] = Math.hypot(a[0] - b[0], a[1] - b[1]);
  }
  if (n === 0) return NaN;
  const seen = lengths.subarray(0, n).sort();
  return n % 2 ? seen[(n - 1) / 2] : (seen[n / 2 - 1] + seen[n / 2]) / 2;
}
