// The input's points' closest points on a fit whose vertices move round after round (its faces
// fixed): the fit's snap and pull (lib/remesh.mjs) ask it every round, and only where the answer can
// matter to them, a point farther than `limit`. A point's closest triangle that has not moved since
// it was asked is still that far from it, so the point is no farther than it was: one within
// `limit` then is within it now and is not asked again (its entry is then an upper bound). The
// others are asked on the fit as it is, the same answers as asking every point (the same tree).
import { Surface } from './remesh.mjs';

export class InputOnResult {
  /** `input`: the points (Float64Array, 3 each); `limit`: the distance within which a point needs no answer. */
  constructor(input, limit) {
    this.input = input;
    this.limit = limit;
    const n = input.length / 3;
    /** Per point: the distance (exact beyond `limit`, else an upper bound), the closest point (3), the corners of its triangle (3). */
    this.distances = new Float64Array(n);
    this.points = new Float64Array(3 * n);
    this.corners = new Uint32Array(3 * n);
    // The fit's positions when the entries were last brought up to date (null: never).
    this.at = null;
  }

  /**
   * Brings the entries up to the fit (`positions`, `faces`: the same faces at every call);
   * `surface`: the fit's Surface as it is, if the caller has one (else one is made here).
   */
  update(positions, faces, surface = null) {
    const { input, distances, points, corners, limit } = this, n = distances.length;
    let asked = null;
    if (this.at) {
      const at = this.at, moved = new Uint8Array(positions.length / 3);
      let any = false;
      for (let v = 0; v < moved.length; v++)
        if (positions[3 * v] !== at[3 * v] || positions[3 * v + 1] !== at[3 * v + 1] || positions[3 * v + 2] !== at[3 * v + 2]) moved[v] = 1, any = true;
      // Nothing moved: every entry is as it was asked.
      if (!any) return this;
      asked = [];
      for (let i = 0; i < n; i++)
        if (distances[i] > limit || moved[corners[3 * i]] || moved[corners[3 * i + 1]] || moved[corners[3 * i + 2]]) asked.push(i);
    }
    this.at = positions.slice();
    if (asked && asked.length === 0) return this;
    let query = input;
    if (asked) {
      query = new Float64Array(3 * asked.length);
      for (let q = 0; q < asked.length; q++) {
        const i = asked[q];
        query[3 * q] = input[3 * i], query[3 * q + 1] = input[3 * i + 1], query[3 * q + 2] = input[3 * i + 2];
      }
    }
    const result = surface ?? new Surface({ positions, faces }, { normals: false });
    const answers = result.closestMany(query), index = result.index;
    if (!surface) result.dispose();
    const count = query.length / 3;
    for (let q = 0; q < count; q++) {
      const i = asked ? asked[q] : q, t = answers.triangles[q];
      distances[i] = answers.distances[q];
      points[3 * i] = answers.points[3 * q], points[3 * i + 1] = answers.points[3 * q + 1], points[3 * i + 2] = answers.points[3 * q + 2];
      corners[3 * i] = index[3 * t], corners[3 * i + 1] = index[3 * t + 1], corners[3 * i + 2] = index[3 * t + 2];
    }
    return this;
  }
}
