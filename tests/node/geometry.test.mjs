// The shared geometry helpers (lib/geometry.mjs): hypot3 must give Math.hypot's answer bit for bit
// (the remesher's results, hashed in the benches, may not change when one replaces the other).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { hypot3 } from '../../lib/geometry.mjs';

/** Deterministic numbers over many magnitudes, signs, zeros and subnormals (xorshift32). */
function numbers(count, seed = 12345) {
  let s = seed;
  const next = () => ((s ^= s << 13), (s ^= s >>> 17), (s ^= s << 5), (s >>> 0) / 2 ** 32);
  const out = [];
  for (let i = 0; i < count; i++) {
    const kind = next();
    if (kind < 0.03) out.push(kind < 0.015 ? 0 : -0);
    else if (kind < 0.05) out.push((next() - 0.5) * 1e-310);
    else out.push((next() - 0.5) * 10 ** Math.floor(next() * 80 - 40));
  }
  return out;
}

test('hypot3 equals Math.hypot bit for bit on a million triples of mixed magnitudes', () => {
  const n = numbers(3e6);
  let differing = 0, first = null;
  for (let i = 0; i < n.length; i += 3) {
    const expected = Math.hypot(n[i], n[i + 1], n[i + 2]), got = hypot3(n[i], n[i + 1], n[i + 2]);
    if (!Object.is(expected, got)) {
      differing++;
      first ??= [n[i], n[i + 1], n[i + 2], expected, got];
    }
  }
  assert.equal(differing, 0, `first difference: ${first}`);
});

test('hypot3 follows Math.hypot on infinities, NaN, zeros and the extremes', () => {
  const cases = [[0, 0, 0], [-0, -0, -0], [Infinity, NaN, 1], [NaN, -Infinity, 0], [NaN, 1, 2], [1, 2, NaN],
    [1e308, 1e308, 1e308], [5e-324, 0, 5e-324], [3, 4, 0], [-3, 0, 4], [1, 1, 1], [1e-200, 1e200, 1]];
  for (const [x, y, z] of cases) assert.ok(Object.is(hypot3(x, y, z), Math.hypot(x, y, z)), `${x}, ${y}, ${z}`);
});
