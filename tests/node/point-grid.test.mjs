// lib/point-grid.mjs: the grid's answers are the brute-force ones, for small and wide query boxes
// (a wide box walks the cells that hold points instead of the box's cells).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { pointGrid } from '../../lib/point-grid.mjs';
import { hypot3 } from '../../lib/geometry.mjs';

/** A deterministic pseudo-random generator in [0, 1). */
function random(seed) {
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 4294967296);
}

test('within and inBox list exactly the points a brute-force scan finds, at every reach', () => {
  const rnd = random(7), n = 3000, points = new Float64Array(3 * n);
  // Points on a sphere's surface (cells mostly empty inside), some duplicated, some on cell borders.
  for (let i = 0; i < n; i++) {
    const u = 2 * rnd() - 1, t = 2 * Math.PI * rnd(), s = Math.sqrt(1 - u * u);
    points.set([s * Math.cos(t), s * Math.sin(t), u], 3 * i);
  }
  points.set(points.subarray(0, 30), 3 * 100);
  points.set([0.25, -0.5, 0.75], 3 * 200);
  const grid = pointGrid(points, 0.05);
  let wide = 0;
  for (let q = 0; q < 200; q++) {
    const x = 2.4 * rnd() - 1.2, y = 2.4 * rnd() - 1.2, z = 2.4 * rnd() - 1.2, r = q % 4 === 0 ? 1.5 * rnd() : 0.2 * rnd();
    if (r > 0.5) wide++;
    const near = [], box = [];
    for (let i = 0; i < n; i++) {
      if (hypot3(points[3 * i] - x, points[3 * i + 1] - y, points[3 * i + 2] - z) <= r) near.push(i);
      if (Math.abs(points[3 * i] - x) <= r && Math.abs(points[3 * i + 1] - y) <= r && Math.abs(points[3 * i + 2] - z) <= r) box.push(i);
    }
    assert.deepEqual(grid.within(x, y, z, r).sort((a, b) => a - b), near, `query ${q}`);
    assert.deepEqual(grid.inBox(x, y, z, r).sort((a, b) => a - b), box, `query ${q}`);
    // Each cell named once; its points are its run of grid.order, in increasing index.
    const cells = grid.cellsNear(x, y, z, r);
    assert.equal(new Set(cells).size, cells.length);
    const listed = cells.flatMap((q) => [...grid.order.subarray(grid.start[q], grid.start[q + 1])]);
    assert.ok(listed.every((i, j) => j === 0 || cells.length > 1 || listed[j - 1] < i));
    for (const i of near) assert.ok(listed.includes(i), `query ${q}: point ${i} is in a listed cell`);
  }
  assert.ok(wide > 10, `${wide} wide queries`);
  assert.deepEqual(pointGrid(new Float64Array(0), 1).within(0, 0, 0, 10), []);
});

test('within: points at the reach within rounding, and scales whose squares underflow or overflow, as hypot3 decides', () => {
  const rnd = random(21);
  for (const scale of [1, 1e-160, 1e160, 3.7e-5, 6.1e4]) {
    const n = 2000, points = new Float64Array(3 * n), centre = [0.1 * scale, -0.2 * scale, 0.3 * scale], r = 0.5 * scale;
    for (let i = 0; i < n; i++) {
      // Directions at random, at the reach times 1 +- a few ulps (both sides of it), and some well inside or out.
      const u = 2 * rnd() - 1, t = 2 * Math.PI * rnd(), s = Math.sqrt(1 - u * u);
      const d = i % 3 === 0 ? r * (0.5 + rnd()) : r * (1 + (rnd() - 0.5) * 4e-16);
      points.set([centre[0] + d * s * Math.cos(t), centre[1] + d * s * Math.sin(t), centre[2] + d * u], 3 * i);
    }
    const grid = pointGrid(points, 0.1 * scale), near = [];
    for (let i = 0; i < n; i++) if (hypot3(points[3 * i] - centre[0], points[3 * i + 1] - centre[1], points[3 * i + 2] - centre[2]) <= r) near.push(i);
    assert.deepEqual(grid.within(centre[0], centre[1], centre[2], r).sort((a, b) => a - b), near, `scale ${scale}`);
    assert.ok(near.length > 100 && near.length < n - 100, `scale ${scale}: ${near.length} of ${n} within`);
  }
});
