// The live volume chart beside the readouts: the reference volume and the current one over the last
// CHART_POINTS changes, as an SVG (two polylines scaled to their range, with the range's ends written).
const CHART_POINTS = 240;
const SVG = 'http://www.w3.org/2000/svg';
const W = 280, H = 64;

export class VolumeChart {
  constructor(container) {
    this.current = [];
    this.reference = [];
    this.svg = document.createElementNS(SVG, 'svg');
    this.svg.setAttribute('viewBox', `0 0 ${W} ${H}`);
    this.svg.setAttribute('role', 'img');
    this.svg.dataset.testid = 'volume-chart';
    this.svg.classList.add('volume-chart');
    this.title = document.createElementNS(SVG, 'title');
    this.referenceLine = this.#line('chart-reference');
    this.currentLine = this.#line('chart-current');
    this.top = this.#label(2, 10);
    this.bottom = this.#label(2, H - 3);
    this.svg.append(this.title, this.referenceLine, this.currentLine, this.top, this.bottom);
    container.append(this.svg);
    this.#draw();
  }

  #line(cls) {
    const line = document.createElementNS(SVG, 'polyline');
    line.classList.add(cls);
    line.setAttribute('fill', 'none');
    return line;
  }

  #label(x, y) {
    const text = document.createElementNS(SVG, 'text');
    text.setAttribute('x', String(x));
    text.setAttribute('y', String(y));
    text.classList.add('chart-label');
    return text;
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

  reset() {
    this.current.length = 0;
    this.reference.length = 0;
    this.#draw();
  }

  #draw() {
    const all = [...this.current, ...this.reference];
    const n = this.current.length;
    this.svg.dataset.points = String(n);
    if (n === 0) {
      this.title.textContent = 'Volume chart: no data yet';
      for (const line of [this.referenceLine, this.currentLine]) line.setAttribute('points', '');
      this.top.textContent = this.bottom.textContent = '';
      return;
    }
    let lo = Math.min(...all), hi = Math.max(...all);
    const pad = Math.max((hi - lo) * 0.1, Math.abs(hi) * 1e-9, 1e-12);
    lo -= pad;
    hi += pad;
    const x = (i) => (n === 1 ? W : (i / (n - 1)) * W).toFixed(1);
    const y = (v) => (H - 14 - ((v - lo) / (hi - lo)) * (H - 18) + 12).toFixed(1);
    this.referenceLine.setAttribute('points', this.reference.map((v, i) => `${x(i)},${y(v)}`).join(' '));
    this.currentLine.setAttribute('points', this.current.map((v, i) => `${x(i)},${y(v)}`).join(' '));
    this.top.textContent = hi.toPrecision(6);
    this.bottom.textContent = lo.toPrecision(6);
    this.title.textContent = `Volume over the last ${n} changes: now ${this.current[n - 1].toPrecision(8)}, to keep ${this.reference[n - 1].toPrecision(8)}`;
  }
}
