// Round chart ticks (web/ticks.js): steps of 1, 2 or 5 x 10^k covering the range, and labels that
// read back as the ticks, all distinct, over ranges from 1e-15 of the values to 1e9 wide.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { niceTicks } from '../../web/ticks.js';

const RANGES = [];
for (const centre of [0, 1, -1, 3.622788675, 193.46, 1e-6, 4.2e8])
  for (const width of [1e-15, 1e-9, 2.4e-6, 1e-3, 0.37, 5, 1234, 1e9])
    if (width >= Math.abs(centre) * 1e-15) RANGES.push([centre - width / 2, centre + width / 2]);

test('ticks are multiples of a 1, 2 or 5 x 10^k step and cover the range', () => {
  for (const [lo, hi] of RANGES) {
    const { ticks, step, mantissa } = niceTicks(lo, hi, 5);
    assert.ok([1, 2, 5].includes(mantissa), `${lo}..${hi}: mantissa ${mantissa}`);
    assert.ok(ticks[0] <= lo + 1e-12 * Math.abs(lo) && ticks.at(-1) >= hi - 1e-12 * Math.abs(hi), `${lo}..${hi}: ${ticks}`);
    for (const t of ticks)
      assert.ok(Math.abs(t - Math.round(t / step) * step) <= 1e-6 * step + 8 * Number.EPSILON * Math.abs(t), `${t} is not a multiple of ${step}`);
  }
});

test('labels are distinct and read back as their ticks (a ratio chart near 1 included)', () => {
  for (const [lo, hi] of [...RANGES, [0.9999985, 1.0000015], [1 - 2e-6, 1 + 2e-6]]) {
    const { ticks, step, format } = niceTicks(lo, hi, 6);
    const labels = ticks.map(format);
    assert.equal(new Set(labels).size, labels.length, `${lo}..${hi}: repeated labels ${labels}`);
    labels.forEach((label, i) => assert.ok(Math.abs(Number(label) - ticks[i]) < step * 1e-3, `${label} for ${ticks[i]}`));
    for (const label of labels) assert.ok(label.length <= 24, `${label} is long`);
  }
  assert.deepEqual(niceTicks(0.9999985, 1.0000015, 6).ticks.map(niceTicks(0.9999985, 1.0000015, 6).format).slice(0, 3), ['0.9999985', '0.9999990', '0.9999995']);
});
