// The live chart beside the readouts, as one SVG of two plots with round ticks (web/ticks.js) and a
// legend: above, the volume now (solid) and the volume to keep (dashed) over the last CHART_POINTS
// changes; below, during a drag, the correction's multiplier λ of each step (the paper's formula
// (6): the free handles move by λ times the volume gradient), from the drag's start.
import { niceTicks } from './ticks.js';

const CHART_POINTS = 240;
const LAMBDA_POINTS = 300;
const SVG = 'http://www.w3.org/2000/svg';
const W = 280;
const LEFT = 70, RIGHT = 4; // LEFT: room for a preserved volume's middle tick written in full (3.622788675)
// Two plots stacked: [top, bottom] of each one's drawing area, legend lines above each.
const VOLUME = { legend: 10, top: 16, bottom: 70 };
const LAMBDA = { legend: 88, top: 94, bottom: 138 };
const H = 144;

function element(name, attributes = {}, cls = null) {
  const e = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, String(v));
  if (cls) e.classList.add(cls);
  return e;
}

/** A plot area: its tick lines and labels (a group redrawn each time), its polylines. */
class Plot {
  constructor(svg, area, series, legendText) {
    this.area = area;
    this.ticks = element('g');
    svg.append(this.ticks);
    this.lines = series.map((cls) => {
      const line = element('polyline', { fill: 'none' }, cls);
      svg.append(line);
      return line;
    });
    let x = LEFT;
    for (const [cls, text] of legendText) {
      svg.append(element('line', { x1: x, y1: area.legend - 3, x2: x + 14, y2: area.legend - 3 }, cls));
      const label = element('text', { x: x + 18, y: area.legend }, 'chart-label');
      label.textContent = text;
      svg.append(label);
      x += 26 + 5.2 * text.length;
    }
    this.tickValues = [];
  }

  /** Draws series (arrays of numbers) over `span` x slots; empty series clear the plot. */
  draw(values, span) {
    this.ticks.replaceChildren();
    const all = values.flat();
    if (all.length === 0) {
      for (const line of this.lines) line.setAttribute('points', '');
      this.tickValues = [];
      return;
    }
    let lo = Math.min(...all), hi = Math.max(...all);
    const pad = Math.max((hi - lo) * 0.05, Math.abs(hi) * 1e-9, 1e-15);
    const axis = niceTicks(lo - pad, hi + pad, 3);
    lo = axis.ticks[0];
    hi = axis.ticks[axis.ticks.length - 1];
    this.tickValues = axis.ticks;
    const { top, bottom } = this.area;
    const y = (v) => (bottom - (bottom - top) * (v - lo) / (hi - lo)).toFixed(1);
    // A range tiny against the values (a preserved volume: 1e-9 of it) would need a dozen digits per
    // label: the middle tick written once, the others as offsets from it (+2e-7).
    const mid = axis.ticks[Math.floor(axis.ticks.length / 2)];
    const offsets = axis.step < Math.abs(mid) * 1e-4;
    const label = (t) => {
      if (!offsets) return axis.format(t);
      if (t === mid) return String(Number(mid.toFixed(Math.max(0, -axis.exponent))));
      const d = Number((t - mid).toPrecision(2));
      return `${d > 0 ? '+' : '−'}${Math.abs(d).toExponential()}`;
    };
    for (const t of axis.ticks) {
      this.ticks.append(element('line', { x1: LEFT, x2: W - RIGHT, y1: y(t), y2: y(t) }, 'chart-grid'));
      const text = element('text', { x: LEFT - 3, y: Number(y(t)) + 3, 'text-anchor': 'end' }, 'chart-label');
      text.textContent = label(t);
      this.ticks.append(text);
    }
    const x = (i) => (LEFT + (W - LEFT - RIGHT) * (span <= 1 ? 1 : i / (span - 1))).toFixed(1);
    this.lines.forEach((line, s) => line.setAttribute('points', values[s].map((v, i) => `${x(i)},${y(v)}`).join(' ')));
  }
}

export class VolumeChart {
  constructor(container) {
    this.current = [];
    this.reference = [];
    this.lambdas = [];
    this.svg = element('svg', { viewBox: `0 0 ${W} ${H}`, role: 'img' }, 'volume-chart');
    this.svg.dataset.testid = 'volume-chart';
    this.title = element('title');
    this.svg.append(this.title);
    this.volumePlot = new Plot(this.svg, VOLUME, ['chart-current', 'chart-reference'], [['chart-current', 'volume now V'], ['chart-reference', 'volume to keep V₀']]);
    this.lambdaPlot = new Plot(this.svg, LAMBDA, ['chart-lambda'], [['chart-lambda', 'multiplier λ per drag step']]);
    this.lambdaEmpty = element('text', { x: LEFT, y: (LAMBDA.top + LAMBDA.bottom) / 2 + 3 }, 'chart-label');
    this.svg.append(this.lambdaEmpty);
    container.append(this.svg);
    this.#draw();
  }

  /** Adds one point (the volume now and the reference); a new model starts over (reset). */
  push(current, reference) {
    if (!Number.isFinite(current) || !Number.isFinite(reference)) return;
    this.current.push(current);
    this.reference.push(reference);
    if (this.current.length > CHART_POINTS) {
      this.current.shift();
      this.reference.shift();
    }
    this.#draw();
  }

  /** A drag starts: its multiplier plot starts empty. */
  startDrag() {
    this.lambdas.length = 0;
    this.#draw();
  }

  /** The multiplier λ of one drag step. */
  pushLambda(lambda) {
    if (!Number.isFinite(lambda)) return;
    this.lambdas.push(lambda);
    if (this.lambdas.length > LAMBDA_POINTS) this.lambdas.shift();
    this.#draw();
  }

  reset() {
    this.current.length = 0;
    this.reference.length = 0;
    this.lambdas.length = 0;
    this.#draw();
  }

  #draw() {
    const n = this.current.length;
    this.svg.dataset.points = String(n);
    this.svg.dataset.lambdas = String(this.lambdas.length);
    this.volumePlot.draw(n ? [this.current, this.reference] : [], CHART_POINTS);
    // a short drag fills the width (at least 20 slots)
    this.lambdaPlot.draw(this.lambdas.length ? [this.lambdas] : [], Math.max(20, this.lambdas.length));
    this.svg.dataset.ticks = JSON.stringify(this.volumePlot.tickValues);
    this.svg.dataset.lambdaTicks = JSON.stringify(this.lambdaPlot.tickValues);
    this.lambdaEmpty.textContent = this.lambdas.length ? '' : 'λ of each drag step shows here';
    this.title.textContent = n === 0 ? 'Volume chart: no data yet'
      : `Volume over the last ${n} changes: now ${this.current[n - 1].toPrecision(8)}, to keep ${this.reference[n - 1].toPrecision(8)}` +
        (this.lambdas.length ? `; multiplier λ of the last drag step ${this.lambdas[this.lambdas.length - 1].toExponential(3)}` : '');
  }
}
