// A uniform grid over points for the remesher's neighbour queries (the drag's and the nudge's input
// samples near a patch, the emphasis weights around far vertices). The cells that hold points are
// numbered in the order their first point comes, and found through a hash table of their integer
// coordinates in typed arrays (no Map: a query box of a few hundred cells is a few hundred probes);
// each cell's points are a run of `order`, in increasing index. A query box that spans more cells
// than there are cells holding points walks those instead: a fit far from its input makes the reach
// of a query wide (thousands of empty cells a query at 0.5% of the diagonal a cell).
import { hypot3 } from './geometry.mjs';

// Cells along an axis at most (their coordinates are 32-bit integers).
const MAX_CELLS = 2 ** 30;

/**
 * The grid of `points` (flat xyz) in cubic cells of side `cell`: `cellsNear(x, y, z, r)` the cells
 * meeting the box of half-side r (numbers: cell q's points are order[start[q]] to
 * order[start[q + 1] - 1]); `within(x, y, z, r)` the points within distance r; `inBox(x, y, z, r)`
 * those within the box of half-side r. A cell's points come in increasing index, the cells in
 * increasing (x, y, z) of the box, or in the order of their first point for a wide box.
 */
export function pointGrid(points, cell) {
  const n = points.length / 3;
  // The points' lowest and highest cells: each point's cell is taken relative to the lowest
  // (non-negative integers, at most MAX_CELLS a side).
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < 3 * n; i++) {
    const c = Math.floor(points[i] / cell), k = i % 3;
    if (c < lo[k]) lo[k] = c;
    if (c > hi[k]) hi[k] = c;
  }
  for (let k = 0; k < 3 && n > 0; k++)
    if (!(hi[k] - lo[k] < MAX_CELLS)) throw new RangeError(`pointGrid: ${hi[k] - lo[k] + 1} cells of ${cell} along an axis (at most ${MAX_CELLS})`);
  // Open addressing: slot -> cell number (-1: empty); the cells' coordinates and point counts
  // beside, grown as cells come (a scan's millions of samples lie in a few hundred thousand cells).
  let size = 16;
  while (size < 2 * n) size *= 2;
  const mask = size - 1, slots = new Int32Array(size).fill(-1);
  let cellA = new Int32Array(1024), cellB = new Int32Array(1024), cellC = new Int32Array(1024), count = new Uint32Array(1024);
  const grown = (a, length) => {
    const b = new a.constructor(2 * length);
    b.set(a);
    return b;
  };
  const hash = (a, b, c) => (Math.imul(a, 0x9e3779b1) ^ Math.imul(b, 0x85ebca77) ^ Math.imul(c, 0xc2b2ae3d)) >>> 0;
  const find = (a, b, c) => {
    for (let s = hash(a, b, c) & mask; ; s = (s + 1) & mask) {
      const q = slots[s];
      if (q < 0 || (cellA[q] === a && cellB[q] === b && cellC[q] === c)) return s;
    }
  };
  let held = 0;
  const cellOf = new Int32Array(n);
  for (let i = 0; i < n; i++) {
    const a = Math.floor(points[3 * i] / cell) - lo[0], b = Math.floor(points[3 * i + 1] / cell) - lo[1], c = Math.floor(points[3 * i + 2] / cell) - lo[2];
    const s = find(a, b, c);
    if (slots[s] < 0) {
      if (held === cellA.length) cellA = grown(cellA, held), cellB = grown(cellB, held), cellC = grown(cellC, held), count = grown(count, held);
      slots[s] = held, cellA[held] = a, cellB[held] = b, cellC[held] = c, held++;
    }
    cellOf[i] = slots[s];
    count[slots[s]]++;
  }
  const start = new Uint32Array(held + 1);
  for (let q = 0; q < held; q++) start[q + 1] = start[q] + count[q];
  const order = new Uint32Array(n), next = start.slice(0, held);
  for (let i = 0; i < n; i++) order[next[cellOf[i]]++] = i;

  // The cells meeting the box of half-side r about (x, y, z), passed to visit(q) in turn.
  const eachCellNear = (x, y, z, r, visit) => {
    if (n === 0) return;
    const a0 = Math.max(0, Math.floor((x - r) / cell) - lo[0]), a1 = Math.min(hi[0], Math.floor((x + r) / cell)) - lo[0];
    const b0 = Math.max(0, Math.floor((y - r) / cell) - lo[1]), b1 = Math.min(hi[1], Math.floor((y + r) / cell)) - lo[1];
    const c0 = Math.max(0, Math.floor((z - r) / cell) - lo[2]), c1 = Math.min(hi[2], Math.floor((z + r) / cell)) - lo[2];
    if (a1 < a0 || b1 < b0 || c1 < c0) return;
    if ((a1 - a0 + 1) * (b1 - b0 + 1) * (c1 - c0 + 1) > held) {
      for (let q = 0; q < held; q++)
        if (cellA[q] >= a0 && cellA[q] <= a1 && cellB[q] >= b0 && cellB[q] <= b1 && cellC[q] >= c0 && cellC[q] <= c1) visit(q);
      return;
    }
    for (let a = a0; a <= a1; a++)
      for (let b = b0; b <= b1; b++)
        for (let c = c0; c <= c1; c++) {
          const q = slots[find(a, b, c)];
          if (q >= 0) visit(q);
        }
  };
  const grid = {
    order,
    start,
    cellsNear(x, y, z, r) {
      const out = [];
      eachCellNear(x, y, z, r, (q) => out.push(q));
      return out;
    },
    within(x, y, z, r) {
      const out = [];
      // The squared distance settles all but the points at r within rounding; those are decided
      // by hypot3 (the distance as the remesher measures it) as before.
      // (Radii whose square would underflow or overflow: hypot3 alone.)
      const plain = !(r * r > 1e-250 && r * r < 1e250);
      const inside = plain ? -1 : r * r * (1 - 1e-9), outside = plain ? Infinity : r * r * (1 + 1e-9);
      eachCellNear(x, y, z, r, (q) => {
        for (let j = start[q]; j < start[q + 1]; j++) {
          const i = order[j], dx = points[3 * i] - x, dy = points[3 * i + 1] - y, dz = points[3 * i + 2] - z;
          const squared = dx * dx + dy * dy + dz * dz;
          if (plain ? hypot3(dx, dy, dz) <= r : squared <= inside || (squared < outside && hypot3(dx, dy, dz) <= r)) out.push(i);
        }
      });
      return out;
    },
    inBox(x, y, z, r) {
      const out = [];
      eachCellNear(x, y, z, r, (q) => {
        for (let j = start[q]; j < start[q + 1]; j++) {
          const i = order[j];
          if (Math.abs(points[3 * i] - x) <= r && Math.abs(points[3 * i + 1] - y) <= r && Math.abs(points[3 * i + 2] - z) <= r) out.push(i);
        }
      });
      return out;
    },
  };
  return grid;
}
