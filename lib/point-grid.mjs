// A uniform grid over points for the remesher's neighbour queries (the drag's and the nudge's input
// samples near a patch, the emphasis weights around far vertices). Cells are numbered exactly from
// the points' lowest cell (one number, one cell). A query box that spans more cells than there are
// cells holding points walks those instead: a fit far from its input makes the reach of a query
// wide (thousands of empty cells a query at 0.5% of the diagonal a cell).
import { hypot3 } from './geometry.mjs';

/**
 * The grid of `points` (flat xyz) in cubic cells of side `cell`: `cellsNear(x, y, z, r)` the lists
 * of point indices of the cells meeting the box of half-side r; `within(x, y, z, r)` the points
 * within distance r; `inBox(x, y, z, r)` those within the box of half-side r.
 */
export function pointGrid(points, cell) {
  const n = points.length / 3, lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < n; i++)
    for (let k = 0; k < 3; k++) {
      const c = Math.floor(points[3 * i + k] / cell);
      if (c < lo[k]) lo[k] = c;
      if (c > hi[k]) hi[k] = c;
    }
  const nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1;
  const key = (a, b, c) => (a - lo[0]) + nx * ((b - lo[1]) + ny * (c - lo[2]));
  const cells = new Map();
  // The cells holding points, with their coordinates: [a, b, c, list] each.
  const held = [];
  for (let i = 0; i < n; i++) {
    const a = Math.floor(points[3 * i] / cell), b = Math.floor(points[3 * i + 1] / cell), c = Math.floor(points[3 * i + 2] / cell);
    const k = key(a, b, c);
    let list = cells.get(k);
    if (!list) cells.set(k, (list = [])), held.push([a, b, c, list]);
    list.push(i);
  }
  const range = (x, r, k) => [Math.max(lo[k], Math.floor((x - r) / cell)), Math.min(hi[k], Math.floor((x + r) / cell))];
  const grid = {
    cellsNear(x, y, z, r) {
      const out = [];
      if (n === 0) return out;
      const [a0, a1] = range(x, r, 0), [b0, b1] = range(y, r, 1), [c0, c1] = range(z, r, 2);
      if (a1 < a0 || b1 < b0 || c1 < c0) return out;
      if ((a1 - a0 + 1) * (b1 - b0 + 1) * (c1 - c0 + 1) > held.length) {
        for (const [a, b, c, list] of held) if (a >= a0 && a <= a1 && b >= b0 && b <= b1 && c >= c0 && c <= c1) out.push(list);
        return out;
      }
      for (let a = a0; a <= a1; a++)
        for (let b = b0; b <= b1; b++)
          for (let c = c0; c <= c1; c++) {
            const list = cells.get(key(a, b, c));
            if (list) out.push(list);
          }
      return out;
    },
    within(x, y, z, r) {
      const out = [];
      for (const list of grid.cellsNear(x, y, z, r))
        for (const i of list) {
          if (hypot3(points[3 * i] - x, points[3 * i + 1] - y, points[3 * i + 2] - z) <= r) out.push(i);
        }
      return out;
    },
    inBox(x, y, z, r) {
      const out = [];
      for (const list of grid.cellsNear(x, y, z, r))
        for (const i of list)
          if (Math.abs(points[3 * i] - x) <= r && Math.abs(points[3 * i + 1] - y) <= r && Math.abs(points[3 * i + 2] - z) <= r) out.push(i);
      return out;
    },
  };
  return grid;
}
