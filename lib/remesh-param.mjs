// The base -> input map of a MAPS parametrisation (Lee et al. 1998) made by collapseToTarget(...,
// { track: true }) (lib/remesh-collapse.mjs): every input vertex has weights over the base
// vertices of one base triangle. A point of the base (weights over one triangle's corners) is
// located among the input triangles held by that triangle, drawn in its chart (the triangle as an
// equilateral one, its three edge neighbours unfolded around it), and mapped to the point of the
// input triangle with the same barycentrics.
import { barycentric2 } from './remesh-collapse.mjs';

export class BaseParametrisation {
  /**
   * @param {{ positions: Float64Array, faces: Uint32Array }} base the collapsed mesh
   * @param {{ positions: Float64Array, faces: Uint32Array }} input the mesh it was collapsed from
   * @param {{ ids: number[], weights: number[], face?: number }[]} parameters per input vertex
   */
  constructor(base, input, parameters) {
    this.base = base, this.input = input, this.parameters = parameters;
    const baseFaces = base.faces.length / 3;
    this.facesAround = Array.from({ length: base.positions.length / 3 }, () => []);
    this.across = new Map();  // directed edge "a b" -> the corner facing it in its face
    for (let t = 0; t < baseFaces; t++)
      for (let j = 0; j < 3; j++) {
        const a = base.faces[3 * t + j], b = base.faces[3 * t + (j + 1) % 3], c = base.faces[3 * t + (j + 2) % 3];
        this.facesAround[a].push(t);
        this.across.set(`${a} ${b}`, c);
      }
    // Input triangles by the base triangles their vertices lie in.
    this.held = Array.from({ length: baseFaces }, () => []);
    const homes = (q) => (parameters[q].face !== undefined ? [parameters[q].face] : this.facesAround[parameters[q].ids[0]]);
    for (let f = 0; f < input.faces.length / 3; f++) {
      const ts = new Set();
      for (let j = 0; j < 3; j++) for (const t of homes(input.faces[3 * f + j])) ts.add(t);
      for (const t of ts) this.held[t].push(f);
    }
    this.charts = new Map();
  }

  /** Base triangle t's chart: its corners and the corners facing its edges in the neighbours, in 2D. */
  chart(t) {
    let c = this.charts.get(t);
    if (c) return c;
    const { faces } = this.base, corner = [[0, 0], [1, 0], [0.5, Math.sqrt(3) / 2]];
    const at = new Map();
    for (let j = 0; j < 3; j++) at.set(faces[3 * t + j], corner[j]);
    for (let j = 0; j < 3; j++) {
      const a = faces[3 * t + j], b = faces[3 * t + (j + 1) % 3], o = corner[(j + 2) % 3];
      const d = this.across.get(`${b} ${a}`);
      if (d === undefined || at.has(d)) continue;
      // o reflected across the line a-b.
      const pa = corner[j], pb = corner[(j + 1) % 3];
      const ex = pb[0] - pa[0], ey = pb[1] - pa[1], l2 = ex * ex + ey * ey;
      const s = ((o[0] - pa[0]) * ex + (o[1] - pa[1]) * ey) / l2;
      const fx = pa[0] + s * ex, fy = pa[1] + s * ey;
      at.set(d, [2 * fx - o[0], 2 * fy - o[1]]);
    }
    // The held input triangles drawn in the chart (those with a vertex beyond it are left out).
    const drawn = [];
    const place = (q) => {
      const { ids, weights } = this.parameters[q];
      let x = 0, y = 0;
      for (let k = 0; k < ids.length; k++) {
        if (weights[k] === 0) continue;
        const pt = at.get(ids[k]);
        if (!pt) return null;
        x += weights[k] * pt[0], y += weights[k] * pt[1];
      }
      return [x, y];
    };
    for (const f of this.held[t]) {
      const v = [0, 1, 2].map((j) => this.input.faces[3 * f + j]);
      const pts = v.map(place);
      if (pts.every(Boolean)) drawn.push({ v, pts });
    }
    c = { at, drawn };
    this.charts.set(t, c);
    return c;
  }

  /**
   * The input point of the base point with `weights` over base vertices `ids` (all corners of one
   * base triangle), into `out` (3 numbers); false if no base triangle holds them all.
   */
  map(ids, weights, out) {
    const support = ids.filter((_, k) => weights[k] > 0);
    const t = this.facesAround[support[0]].find((s) => support.every((id) => this.base.faces.slice(3 * s, 3 * s + 3).includes(id)));
    if (t === undefined) return false;
    const { at, drawn } = this.chart(t);
    let x = 0, y = 0;
    for (let k = 0; k < ids.length; k++) {
      const pt = at.get(ids[k]);
      x += weights[k] * pt[0], y += weights[k] * pt[1];
    }
    let best = null, bestMin = -Infinity;
    for (const d of drawn) {
      const b = barycentric2([x, y], d.pts);
      if (!b) continue;
      const m = Math.min(b[0], b[1], b[2]);
      if (m > bestMin) bestMin = m, best = { v: d.v, b };
    }
    if (!best) return false;
    const b = best.b.map((w) => Math.max(0, w)), s = b[0] + b[1] + b[2] || 1, p = this.input.positions;
    for (let k = 0; k < 3; k++) out[k] = (b[0] * p[3 * best.v[0] + k] + b[1] * p[3 * best.v[1] + k] + b[2] * p[3 * best.v[2] + k]) / s;
    return true;
  }
}
