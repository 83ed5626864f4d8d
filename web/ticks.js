// Round chart ticks (1, 2, 5 x 10^k): the editor's volume chart and the teaching views' charts.

/**
 * Round axis ticks covering [lo, hi]: a step of 1, 2 or 5 x 10^k giving about `count` intervals,
 * ticks at its multiples (the first at or below lo, the last at or above hi), and a label format
 * with just the decimals the step needs.
 */
export function niceTicks(lo, hi, count = 5) {
  if (!(hi > lo)) hi = lo + (Math.abs(lo) || 1) * 1e-6;
  const raw = (hi - lo) / count;
  const power = Math.floor(Math.log10(raw));
  const base = 10 ** power;
  const mantissa = [1, 2, 5, 10].find((m) => m * base >= raw * 0.999);
  const step = mantissa * base;
  const exponent = mantissa === 10 ? power + 1 : power;
  const first = Math.floor(lo / step + 1e-9), last = Math.ceil(hi / step - 1e-9);
  const decimals = Math.max(0, -exponent);
  // Multiples of the step, rounded to its decimals (no 0.30000000000000004).
  const ticks = [];
  for (let t = first; t <= last; t++) ticks.push(Number((t * step).toFixed(decimals)));
  // Plain decimals while they stay short (1.0000005 rather than 1.0000005e+0); else scientific with
  // the digits down to the step's (each label distinct: 9.999995e-1, 1.0000005e+0).
  const largest = Math.max(...ticks.map(Math.abs));
  const scientific = decimals > 9 || largest >= 1e7 || (largest > 0 && largest < 1e-4);
  const digits = (v) => Math.max(0, Math.floor(Math.log10(Math.max(Math.abs(v), step)) + 1e-9) - exponent);
  const format = (v) => (scientific ? v.toExponential(Math.min(20, digits(v))) : v.toFixed(decimals));
  return { step, mantissa: mantissa === 10 ? 1 : mantissa, exponent, ticks, format };
}
