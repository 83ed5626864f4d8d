// The last step of remesh() for a fit still a little above its Hausdorff goal: the few sample
// points that make the distance (a tip the fit grazes, a face bridging a fold) are brought within
// it by moving the corners of the result triangle they are measured against, off the input
// surface if need be (a vertex within `tolerance` of the input is as good as one on it for the
// two-sided measure), each move kept only where it flips nothing and makes no nearby sample farther.
import { Triangle, Vector3 } from 'three';
import { connectivity } from './connectivity.mjs';
import { hypot3 } from './geometry.mjs';
import { centroidsOnSurface, flippedFaces, Surface } from './remesh.mjs';

// Far samples tried per round, the farthest first.
const MAX_TRIES = 2000;
// Rounds that also bring samples between aim and the goal in (a margin); the later ones run only
// while a sample is beyond the goal (dragon-871k's spikes took 6: 0.551% -> 0.449%).
const MARGIN_ROUNDS = 3;

// The measure's points inside a face (remesh's oneSidedHausdorff): centroid and three interior points.
const BARY = [[1 / 3, 1 / 3, 1 / 3], [2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]];

/** The measure's sample points of a mesh: its vertices, then four points per face (flat xyz). */
function samplePoints({ positions: p, faces }) {
  const n = p.length / 3, out = new Float64Array(p.length + 12 * faces.length / 3);
  out.set(p);
  for (let f = 0; f < faces.length / 3; f++) for (let s = 0; s < 4; s++) faceSample(out, p, faces, n, f, s);
  return out;
}

/** How many sample points samplePoints() makes of a mesh. */
function sampleCount({ positions, faces }) {
  return positions.length / 3 + 4 * faces.length / 3;
}

/** Writes sample s of face f (of a mesh of n vertices) into the samples `out`. */
function faceSample(out, p, faces, n, f, s) {
  for (let k = 0; k < 3; k++)
    out[3 * (n + 4 * f + s) + k] = BARY[s][0] * p[3 * faces[3 * f] + k] + BARY[s][1] * p[3 * faces[3 * f + 1] + k] + BARY[s][2] * p[3 * faces[3 * f + 2] + k];
}

/**
 * The result's samples and their closest points on the input, of the result as it is now: those
 * of the last call (`last`, or null) with only the vertices moved since and their faces' samples
 * asked again (the same points get the same answers). Returns { samples, closest, at: the
 * positions they are of }.
 */
function resultSamplesOnInput(surface, positions, faces, around, last) {
  if (!last) {
    const samples = samplePoints({ positions, faces });
    return { samples, closest: surface.closestMany(samples), at: positions.slice() };
  }
  const { samples, closest, at } = last, n = positions.length / 3;
  const changed = [], faceChanged = new Uint8Array(faces.length / 3);
  for (let v = 0; v < n; v++) {
    if (positions[3 * v] === at[3 * v] && positions[3 * v + 1] === at[3 * v + 1] && positions[3 * v + 2] === at[3 * v + 2]) continue;
    for (let k = 0; k < 3; k++) samples[3 * v + k] = positions[3 * v + k];
    changed.push(v);
    for (let e = around.offsets[v]; e < around.offsets[v + 1]; e++) faceChanged[around.list[e]] = 1;
  }
  for (let f = 0; f < faceChanged.length; f++)
    if (faceChanged[f]) for (let s = 0; s < 4; s++) faceSample(samples, positions, faces, n, f, s), changed.push(n + 4 * f + s);
  const points = new Float64Array(3 * changed.length);
  changed.forEach((i, q) => points.set(samples.subarray(3 * i, 3 * i + 3), 3 * q));
  const answers = surface.closestMany(points);
  changed.forEach((i, q) => {
    closest.points.set(answers.points.subarray(3 * q, 3 * q + 3), 3 * i);
    closest.distances[i] = answers.distances[q], closest.triangles[i] = answers.triangles[q];
  });
  at.set(positions);
  return last;
}

/** Barycentric weights of q on triangle (a, b, c) of p, clamped to the triangle (q is its closest point). */
function weightsOn(p, a, b, c, qx, qy, qz) {
  const u = [p[3 * b] - p[3 * a], p[3 * b + 1] - p[3 * a + 1], p[3 * b + 2] - p[3 * a + 2]];
  const v = [p[3 * c] - p[3 * a], p[3 * c + 1] - p[3 * a + 1], p[3 * c + 2] - p[3 * a + 2]];
  const w = [qx - p[3 * a], qy - p[3 * a + 1], qz - p[3 * a + 2]];
  const dot = (x, y) => x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
  const d00 = dot(u, u), d01 = dot(u, v), d11 = dot(v, v), d20 = dot(w, u), d21 = dot(w, v), den = d00 * d11 - d01 * d01;
  if (!(den > 0)) return [1 / 3, 1 / 3, 1 / 3];
  const s = Math.max(0, (d11 * d20 - d01 * d21) / den), t = Math.max(0, (d00 * d21 - d01 * d20) / den), sum = Math.max(1, s + t);
  return [1 - (s + t) / sum, s / sum, t / sum];
}

/**
 * Moves vertices of the result (`positions`, changed in place; `faces`) so that the two-sided
 * sampled distance to `surface` (the input) falls within `goal` of the diagonal: for each sample
 * beyond `aim` (an input point far from the result, or a result point far from the input; the
 * farthest first; those between aim and goal too, for a margin), the corners of its result triangle move along the gap by the least squares
 * share that brings the sample to `aim` (all of it, half of it, or just within the goal). A move is
 * kept if it turns no triangle around it over, leaves every sample of those triangles within
 * max(its distance before, `tolerance`) of the input, and every input sample near it within
 * max(its distance before, `tolerance`) of the result ("turned over": flippedFaces with `against`,
 * the cosine to the input's normal below which a triangle counts as flipped). A move refused is
 * tried again together with the far samples that share a corner with it (jointMove), then, for an
 * input sample, as one vertex near it moved alone toward it (singleCandidates). Vertices with
 * `fixed` set stay. Moves of one round do not share a triangle; `rounds` rounds (fewer once a round
 * keeps none, and past MARGIN_ROUNDS only while a sample is beyond the goal). Returns { kept: how
 * many moves were kept, measured: the two-sided sampled distances of the result as it ends ({ toInput,
 * fromInput }, as remesh's measure takes them), or null where the last round's moves were not
 * measured again or a side has more than `maxSamples` samples (the measure strides those) }.
 */
export function nudgeToGoal(surface, positions, faces, fixed, { goal, aim, tolerance, rounds = 6, against = 0, maxSamples = Infinity, start = null }) {
  const diagonal = surface.diagonal, limit = goal * diagonal, target = aim * diagonal, allowed = tolerance * diagonal, slack = 1e-9 * diagonal;
  const vertexCount = positions.length / 3;
  const { vertexFaces: around, twins } = connectivity(faces, vertexCount);
  const inputSamples = start?.inputSamples ?? samplePoints(surface.mesh);
  // The checks' queries on the input, asked again only for faces that moved (see the two functions).
  const centroidsOn = centroidsOnSurface(surface, faces.length / 3), patchDistances = patchDistancesOn(surface, faces.length / 3);
  let kept = 0, onInput = start?.onInput ?? null, measured = null;
  // The samples' largest distances, where both sides are all of the measure's samples.
  const measurable = sampleCount(surface.mesh) <= maxSamples && sampleCount({ positions, faces }) <= maxSamples;
  const measuredNow = (fromInput) => (measurable ? { toInput: largest(onInput.closest.distances), fromInput: largest(fromInput.distances) } : null);
  let fromInput = start?.fromInput ?? null;
  for (let round = 0; round < rounds; round++) {
    fromInput = inputSamplesOnResult(inputSamples, positions, faces, around, fromInput);
    // The input samples by the corners of their closest triangle: those a move can uncover.
    const samplesAt = samplesByCorner(fromInput.corners, vertexCount);
    onInput = resultSamplesOnInput(surface, positions, faces, around, onInput);
    const { samples: resultSamples, closest: toInput } = onInput;
    // Far samples: [distance, side (0 input, 1 result), sample]. Input side: the result triangle
    // is the closest one; result side: the sample's own face (or, for a vertex, the vertex alone).
    const far = [];
    for (let i = 0; i < fromInput.distances.length; i++) if (fromInput.distances[i] > target) far.push([fromInput.distances[i], 0, i]);
    for (let i = 0; i < toInput.distances.length; i++) if (toInput.distances[i] > target) far.push([toInput.distances[i], 1, i]);
    // Where the loop ends, the result is as these queries found it.
    measured = measuredNow(fromInput);
    if (far.length === 0) break;
    // Past the first rounds, only while a sample is beyond the goal (not for the margin alone).
    if (round >= MARGIN_ROUNDS && !far.some(([d]) => d > limit)) break;
    far.sort((x, y) => y[0] - x[0] || x[1] - y[1] || x[2] - y[2]);
    // The farthest first; on a fit far beyond the goal (many far samples) no more than these a round.
    far.length = Math.min(far.length, MAX_TRIES);
    // Each far sample's move: the corners of its triangle, their weights at the sample, the gap.
    const moves = far.map(([, side, i]) => {
      if (side === 0) {
        const q = fromInput.points.subarray(3 * i, 3 * i + 3);
        const corners = [fromInput.corners[3 * i], fromInput.corners[3 * i + 1], fromInput.corners[3 * i + 2]];
        return { corners, weights: weightsOn(positions, corners[0], corners[1], corners[2], q[0], q[1], q[2]),
                 gap: [0, 1, 2].map((k) => inputSamples[3 * i + k] - q[k]) };
      }
      const n = vertexCount, gap = [0, 1, 2].map((k) => toInput.points[3 * i + k] - resultSamples[3 * i + k]);
      if (i < n) return { corners: [i], weights: [1], gap };
      const f = Math.floor((i - n) / 4);
      return { corners: [faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]], weights: BARY[(i - n) % 4], gap };
    });
    // The far samples whose move moves a vertex (for the joint moves below).
    const farAt = new Map();
    moves.forEach(({ corners }, e) => {
      for (const v of corners) farAt.has(v) ? farAt.get(v).push(e) : farAt.set(v, [e]);
    });
    const used = new Uint8Array(vertexCount);
    // Tries the corners' moves (`step(part)`: per corner its displacement) at each part; keeps the
    // first that passes the checks. Returns the corners of the triangles moved, or null.
    const tryMove = (corners, step, parts) => {
      // The triangles around the moved corners, and their corners (used by this move).
      const faceSet = new Set();
      for (const v of corners) for (let e = around.offsets[v]; e < around.offsets[v + 1]; e++) faceSet.add(around.list[e]);
      const patch = [...faceSet].sort((a, b) => a - b);
      const patchCorners = new Set();
      for (const f of patch) for (let j = 0; j < 3; j++) patchCorners.add(faces[3 * f + j]);
      // A sample the patch leaves may be closest to a triangle next to it: those are asked too.
      const aroundSet = new Set(patch);
      for (const v of patchCorners) for (let e = around.offsets[v]; e < around.offsets[v + 1]; e++) aroundSet.add(around.list[e]);
      const checked = [...aroundSet].sort((a, b) => a - b);
      const flippedBefore = new Set(flippedFaces({ positions, faces }, surface, patch, against, twins, centroidsOn(positions, faces, patch)));
      const ownBefore = patchDistances(positions, faces, patch);
      const saved = corners.map((v) => positions.slice(3 * v, 3 * v + 3));
      for (const part of parts) {
        const displacements = step(part);
        corners.forEach((v, j) => {
          const dv = displacements[j];
          for (let k = 0; k < 3; k++) positions[3 * v + k] = saved[j][k] + dv[k];
        });
        const good = flippedFaces({ positions, faces }, surface, patch, against, twins, centroidsOn(positions, faces, patch)).every((f) => flippedBefore.has(f)) &&
          patchDistances(positions, faces, patch).every((d, q) => d <= Math.max(ownBefore[q], allowed) + slack) &&
          nearSamplesKept(inputSamples, samplesAt, fromInput, checked, corners, positions, faces, allowed + slack);
        if (good) return patchCorners;
        corners.forEach((v, j) => positions.set(saved[j], 3 * v));
      }
      return null;
    };
    let movedThisRound = 0;
    for (const [e, [d, side]] of far.entries()) {
      const { corners, weights, gap } = moves[e];
      const movable = corners.map((v) => !fixed[v]);
      const norm = weights.reduce((s, w, j) => s + (movable[j] ? w * w : 0), 0);
      if (!(norm > 0) || corners.some((v) => used[v])) continue;
      // The whole way to `aim`, half of it, or (from beyond the goal) just within it.
      const share = (d - target) / d / norm;
      const parts = d > limit ? [1, 0.5, Math.min(0.5, (d - 0.98 * limit) / (d - target))] : [1, 0.5];
      let moved = tryMove(corners, (part) => corners.map((v, j) => gap.map((g) => (movable[j] ? part * share * weights[j] * g : 0))), parts);
      // Refused (a far sample next to it got farther: two sides of a rim the result cuts): the
      // samples whose moves share a corner with it, moved together (the least moves that bring each to `aim`).
      if (!moved) {
        const joint = jointMove(e, far, moves, farAt, fixed, used, target);
        if (joint) moved = tryMove(joint.corners, (part) => joint.displacements.map((dv) => dv.map((x) => part * x)), [1, 0.5]);
      }
      // Still refused, an input sample (a thin spike's tip the result cuts below: moving the whole
      // triangle tilts one of its faces over): one vertex near it moved alone, part of the way
      // toward it (dragon-871k's last far tip: the third corner, a fifth of the way, 0.515% -> 0.485%).
      if (!moved && side === 0) {
        const i = far[e][2], sample = inputSamples.subarray(3 * i, 3 * i + 3);
        for (const v of singleCandidates(corners, around, faces, positions, sample, fixed, used)) {
          const toward = [0, 1, 2].map((k) => sample[k] - positions[3 * v + k]);
          moved = tryMove([v], (part) => [toward.map((x) => part * x)], SINGLE_PARTS);
          if (moved) break;
        }
      }
      if (!moved) continue;
      for (const v of moved) used[v] = 1;
      movedThisRound++;
    }
    kept += movedThisRound;
    if (movedThisRound === 0) break;
    measured = null;
  }
  // The last round's moves, measured (only the samples they can have changed are asked again).
  if (measurable && !measured && kept > 0 && onInput) {
    fromInput = inputSamplesOnResult(inputSamples, positions, faces, around, fromInput);
    onInput = resultSamplesOnInput(surface, positions, faces, around, onInput);
    measured = measuredNow(fromInput);
  }
  return { kept, measured };
}

/**
 * The two-sided sampled distances of a result (`positions`, `faces`) from `surface` (the input), as
 * remesh's measure takes them ({ toInput, fromInput }, or null if a side has more than `maxSamples`
 * samples: the measure strides those), with the queries that found them: nudgeToGoal's `start`
 * for this result (its first round asks nothing again). Its arrays are the nudge's to change.
 */
export function measureForNudge(surface, positions, faces, maxSamples) {
  if (sampleCount(surface.mesh) > maxSamples || sampleCount({ positions, faces }) > maxSamples) return null;
  const inputSamples = samplePoints(surface.mesh);
  const { vertexFaces: around } = connectivity(faces, positions.length / 3);
  const fromInput = inputSamplesOnResult(inputSamples, positions, faces, around, null);
  const onInput = resultSamplesOnInput(surface, positions, faces, around, null);
  return { toInput: largest(onInput.closest.distances), fromInput: largest(fromInput.distances), start: { inputSamples, fromInput, onInput } };
}

/**
 * The input's samples' closest points on the result as it is now: { points, distances, corners (of
 * each one's closest result triangle, 3 per sample), at: the positions they are of }. With the last
 * call's answers (`last`, or null), only the samples whose closest triangle moved since, or that
 * are within their distance of the box of a moved triangle, are asked again: the others' closest
 * triangle is the same (ties aside: a new tree can break them otherwise).
 */
function inputSamplesOnResult(samples, positions, faces, around, last) {
  const n = samples.length / 3;
  let asked = null;
  if (last) {
    const { at, distances, corners } = last;
    const moved = new Uint8Array(positions.length / 3), faceMoved = new Uint8Array(faces.length / 3);
    let any = false;
    for (let v = 0; v < moved.length; v++) {
      if (positions[3 * v] === at[3 * v] && positions[3 * v + 1] === at[3 * v + 1] && positions[3 * v + 2] === at[3 * v + 2]) continue;
      moved[v] = 1, any = true;
      for (let e = around.offsets[v]; e < around.offsets[v + 1]; e++) faceMoved[around.list[e]] = 1;
    }
    if (!any) return last;
    const ask = new Uint8Array(n);
    for (let i = 0; i < n; i++) if (moved[corners[3 * i]] || moved[corners[3 * i + 1]] || moved[corners[3 * i + 2]]) ask[i] = 1;
    movedNear(samples, distances, positions, faces, faceMoved, ask);
    asked = [];
    for (let i = 0; i < n; i++) if (ask[i]) asked.push(i);
  }
  const result = new Surface({ positions, faces }, { normals: false });
  const index = result.index;
  let points = samples;
  if (asked) {
    points = new Float64Array(3 * asked.length);
    asked.forEach((i, q) => points.set(samples.subarray(3 * i, 3 * i + 3), 3 * q));
  }
  const answers = points.length > 0 ? result.closestMany(points) : null;
  result.dispose();
  const out = last ?? { points: new Float64Array(3 * n), distances: new Float64Array(n), corners: new Uint32Array(3 * n), at: null };
  const count = points.length / 3;
  for (let q = 0; q < count; q++) {
    const i = asked ? asked[q] : q, t = answers.triangles[q];
    out.points[3 * i] = answers.points[3 * q], out.points[3 * i + 1] = answers.points[3 * q + 1], out.points[3 * i + 2] = answers.points[3 * q + 2];
    out.distances[i] = answers.distances[q];
    out.corners[3 * i] = index[3 * t], out.corners[3 * i + 1] = index[3 * t + 1], out.corners[3 * i + 2] = index[3 * t + 2];
  }
  out.at = positions.slice();
  return out;
}

/**
 * Sets ask[i] for each sample i within its distance (a little slack: a triangle as close as the
 * closest one may be the new answer) of the box of a moved face (faceMoved), among the samples in
 * the cube about that box's centre of half-side its half extent plus the largest distance. Each
 * sample looks up the moved boxes in a grid over them, within its own distance (most are far
 * smaller than the largest, which a coarse fit makes a tenth of the model: a cube per moved face
 * then held most of the samples).
 */
export function movedNear(samples, distances, positions, faces, faceMoved, ask) {
  const farthest = largest(distances), boxes = [];
  for (let f = 0; f < faceMoved.length; f++) {
    if (!faceMoved[f]) continue;
    const box = new Float64Array(10);  // lo x y z, hi x y z, centre x y z, the cube's half-side
    for (let k = 0; k < 3; k++) {
      const a = positions[3 * faces[3 * f] + k], b = positions[3 * faces[3 * f + 1] + k], c = positions[3 * faces[3 * f + 2] + k];
      box[k] = Math.min(a, b, c), box[3 + k] = Math.max(a, b, c), box[6 + k] = (box[k] + box[3 + k]) / 2;
    }
    box[9] = Math.max(box[3] - box[0], box[4] - box[1], box[5] - box[2]) / 2 + farthest;
    boxes.push(box);
  }
  if (boxes.length === 0) return;
  // Cells as large as the largest box, each box in the cells its extent meets.
  let cell = 0;
  for (const b of boxes) cell = Math.max(cell, b[3] - b[0], b[4] - b[1], b[5] - b[2]);
  cell = cell > 0 ? cell : 1;
  // The cells the boxes meet, numbered within their range (at most 2^17 a side: the cell is the
  // largest box, and the boxes are a fit's faces).
  const span = 2 ** 17, lo = [0, 0, 0], hi = [0, 0, 0];
  const range = () => {
    lo.fill(Infinity), hi.fill(-Infinity);
    for (const b of boxes)
      for (let k = 0; k < 3; k++) lo[k] = Math.min(lo[k], Math.floor(b[k] / cell)), hi[k] = Math.max(hi[k], Math.floor(b[3 + k] / cell));
    return Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  };
  const wide = range();
  if (!(wide < span)) cell *= wide / (span / 2), range();
  const cells = new Map(), key = (a, b, c) => (a - lo[0]) + span * ((b - lo[1]) + span * (c - lo[2]));
  boxes.forEach((b, q) => {
    for (let a = Math.floor(b[0] / cell); a <= Math.floor(b[3] / cell); a++)
      for (let y = Math.floor(b[1] / cell); y <= Math.floor(b[4] / cell); y++)
        for (let z = Math.floor(b[2] / cell); z <= Math.floor(b[5] / cell); z++) {
          const k = key(a, y, z);
          if (!cells.has(k)) cells.set(k, []);
          cells.get(k).push(q);
        }
  });
  const n = samples.length / 3;
  for (let i = 0; i < n; i++) {
    if (ask[i]) continue;
    const reach = distances[i] * (1 + 1e-9) + 1e-12, x = samples[3 * i], y = samples[3 * i + 1], z = samples[3 * i + 2];
    const a0 = Math.max(lo[0], Math.floor((x - reach) / cell)), a1 = Math.min(hi[0], Math.floor((x + reach) / cell));
    const b0 = Math.max(lo[1], Math.floor((y - reach) / cell)), b1 = Math.min(hi[1], Math.floor((y + reach) / cell));
    const c0 = Math.max(lo[2], Math.floor((z - reach) / cell)), c1 = Math.min(hi[2], Math.floor((z + reach) / cell));
    search: for (let a = a0; a <= a1; a++)
      for (let b = b0; b <= b1; b++)
        for (let c = c0; c <= c1; c++) {
          const list = cells.get(key(a, b, c));
          if (!list) continue;
          for (const q of list) {
            const box = boxes[q];
            // In the cube about the box's centre (as a point grid's inBox asked it before), and within reach of the box.
            let inCube = true, squared = 0;
            for (let k = 0; k < 3; k++) {
              const v = samples[3 * i + k], gap = v < box[k] ? box[k] - v : v > box[3 + k] ? v - box[3 + k] : 0;
              if (!(Math.abs(v - box[6 + k]) <= box[9])) inCube = false;
              squared += gap * gap;
            }
            if (inCube && Math.sqrt(squared) <= reach) {
              ask[i] = 1;
              break search;
            }
          }
        }
  }
}

/** The largest of `values` (0 if none). */
function largest(values) {
  let m = 0;
  for (let i = 0; i < values.length; i++) if (values[i] > m) m = values[i];
  return m;
}

// A vertex moved alone toward a far input sample: the nearest of the sample's triangle's corners
// and their neighbours, at most this many, each the share of the way in SINGLE_PARTS (the largest first).
const SINGLE_CANDIDATES = 4, SINGLE_PARTS = [0.5, 0.3, 0.2, 0.1];

/** The vertices (not `fixed`, not `used`) of the triangle `corners` and around them nearest `sample`, the nearest first. */
function singleCandidates(corners, around, faces, positions, sample, fixed, used) {
  const near = new Set(corners);
  for (const v of corners)
    for (let e = around.offsets[v]; e < around.offsets[v + 1]; e++)
      for (let j = 0; j < 3; j++) near.add(faces[3 * around.list[e] + j]);
  return [...near].filter((v) => !fixed[v] && !used[v])
    .map((v) => [hypot3(positions[3 * v] - sample[0], positions[3 * v + 1] - sample[1], positions[3 * v + 2] - sample[2]), v])
    .sort((a, b) => a[0] - b[0] || a[1] - b[1]).slice(0, SINGLE_CANDIDATES).map(([, v]) => v);
}

// Far samples moved together with one whose own move was refused, at most.
const JOINT_SAMPLES = 4;

/**
 * The joint move of far sample `e` and the farthest others (up to JOINT_SAMPLES in all) whose moves
 * share a corner with it: the least displacement of their corners (not `fixed`, not `used`) that
 * brings each sample to `target` along its gap, to first order (minimum norm solution of one
 * equation per sample). null if no other sample shares a corner or the equations are degenerate.
 */
function jointMove(e, far, moves, farAt, fixed, used, target) {
  const chosen = [e];
  const candidates = new Set();
  for (const v of moves[e].corners) for (const o of farAt.get(v) ?? []) if (o !== e) candidates.add(o);
  for (const o of [...candidates].sort((a, b) => a - b)) {
    if (chosen.length >= JOINT_SAMPLES) break;
    if (!moves[o].corners.some((v) => used[v])) chosen.push(o);
  }
  if (chosen.length < 2) return null;
  const corners = [...new Set(chosen.flatMap((o) => moves[o].corners))].filter((v) => !fixed[v]);
  const column = new Map(corners.map((v, j) => [v, j]));
  // One row per sample: the first-order change of its distance per corner displacement.
  const rows = chosen.map((o) => {
    const { corners: cs, weights, gap } = moves[o], d = far[o][0], row = new Float64Array(3 * corners.length);
    for (const [j, v] of cs.entries()) {
      if (!column.has(v)) continue;
      for (let k = 0; k < 3; k++) row[3 * column.get(v) + k] = (weights[j] * gap[k]) / d;
    }
    return { row, need: d - target };
  });
  // (A A^T) lambda = need, displacement = A^T lambda; Gaussian elimination with partial pivoting.
  const n = rows.length, g = rows.map((a) => rows.map((b) => a.row.reduce((s, x, i) => s + x * b.row[i], 0)));
  const rhs = rows.map((r) => r.need), scale = Math.max(...g.map((r, i) => r[i]));
  if (!(scale > 0)) return null;
  for (let c = 0; c < n; c++) {
    let pivot = c;
    for (let r = c + 1; r < n; r++) if (Math.abs(g[r][c]) > Math.abs(g[pivot][c])) pivot = r;
    if (Math.abs(g[pivot][c]) < 1e-9 * scale) return null;
    [g[c], g[pivot]] = [g[pivot], g[c]];
    [rhs[c], rhs[pivot]] = [rhs[pivot], rhs[c]];
    for (let r = c + 1; r < n; r++) {
      const f = g[r][c] / g[c][c];
      for (let k = c; k < n; k++) g[r][k] -= f * g[c][k];
      rhs[r] -= f * rhs[c];
    }
  }
  const lambda = new Float64Array(n);
  for (let c = n - 1; c >= 0; c--) {
    let s = rhs[c];
    for (let k = c + 1; k < n; k++) s -= g[c][k] * lambda[k];
    lambda[c] = s / g[c][c];
  }
  const displacements = corners.map((v, j) => [0, 1, 2].map((k) => rows.reduce((s, r, q) => s + r.row[3 * j + k] * lambda[q], 0)));
  return { corners, displacements };
}

/**
 * patchDistances(p, faces, patch): for each face of `patch`, the largest distance from its
 * measure's samples (corners and four inner points) to the surface, asked in one batch for the
 * faces whose corners moved since they were last asked (a move tried and undone leaves its patch
 * as it was, and the next move's patch overlaps it).
 */
export function patchDistancesOn(surface, faceCount) {
  const at = new Float64Array(9 * faceCount), value = new Float64Array(faceCount), asked = new Uint8Array(faceCount);
  const same = (p, faces, f) => {
    for (let j = 0; j < 3; j++) {
      const v = 3 * faces[3 * f + j], o = 9 * f + 3 * j;
      if (at[o] !== p[v] || at[o + 1] !== p[v + 1] || at[o + 2] !== p[v + 2]) return false;
    }
    return true;
  };
  return (p, faces, patch) => {
    const missing = [];
    for (const f of patch) if (!(asked[f] && same(p, faces, f))) missing.push(f);
    if (missing.length > 0) {
      const points = new Float64Array(21 * missing.length);
      missing.forEach((f, q) => {
        const a = 3 * faces[3 * f], b = 3 * faces[3 * f + 1], c = 3 * faces[3 * f + 2], o = 21 * q;
        for (let k = 0; k < 3; k++) points[o + k] = p[a + k], points[o + 3 + k] = p[b + k], points[o + 6 + k] = p[c + k];
        for (let s = 0; s < 4; s++) for (let k = 0; k < 3; k++) points[o + 9 + 3 * s + k] = BARY[s][0] * p[a + k] + BARY[s][1] * p[b + k] + BARY[s][2] * p[c + k];
      });
      const { distances } = surface.closestMany(points);
      missing.forEach((f, q) => {
        let largest = 0;
        for (let j = 7 * q; j < 7 * q + 7; j++) largest = Math.max(largest, distances[j]);
        value[f] = largest, asked[f] = 1;
        for (let j = 0; j < 3; j++) for (let k = 0; k < 3; k++) at[9 * f + 3 * j + k] = p[3 * faces[3 * f + j] + k];
      });
    }
    return Float64Array.from(patch, (f) => value[f]);
  };
}

/**
 * Whether every input sample is, after a move of the `moved` vertices, within max(its distance
 * before, `allowed`) of the result: its closest triangle before has no moved corner (unchanged, so
 * no farther), or one of the triangles `near` (the moved ones and a ring around them) is that close.
 * Only the samples listed at a moved vertex (samplesByCorner) are asked.
 */
function nearSamplesKept(samples, samplesAt, before, near, moved, p, faces, allowed) {
  const { offsets, list } = samplesAt, seen = new Set();
  for (const v of moved)
    for (let e = offsets[v]; e < offsets[v + 1]; e++) {
      const i = list[e];
      if (seen.has(i)) continue;
      seen.add(i);
      const x = samples[3 * i], y = samples[3 * i + 1], z = samples[3 * i + 2];
      const limit = Math.max(before.distances[i], allowed);
      if (!near.some((f) => pointTriangleDistance(x, y, z, p, faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]) <= limit)) return false;
    }
  return true;
}

/** The samples by vertex: each sample listed at the (distinct) corners of its closest triangle, as { offsets, list }. */
function samplesByCorner(corners, vertexCount) {
  const offsets = new Uint32Array(vertexCount + 1), n = corners.length / 3;
  for (let i = 0; i < n; i++) {
    const a = corners[3 * i], b = corners[3 * i + 1], c = corners[3 * i + 2];
    offsets[a + 1]++;
    if (b !== a) offsets[b + 1]++;
    if (c !== a && c !== b) offsets[c + 1]++;
  }
  for (let v = 0; v < vertexCount; v++) offsets[v + 1] += offsets[v];
  const list = new Uint32Array(offsets[vertexCount]), fill = offsets.slice(0, vertexCount);
  for (let i = 0; i < n; i++) {
    const a = corners[3 * i], b = corners[3 * i + 1], c = corners[3 * i + 2];
    list[fill[a]++] = i;
    if (b !== a) list[fill[b]++] = i;
    if (c !== a && c !== b) list[fill[c]++] = i;
  }
  return { offsets, list };
}

/** Distance from (x, y, z) to triangle (a, b, c) of p (three's closest point on a triangle). */
const triangle = new Triangle(), point = new Vector3(), closest = new Vector3();
function pointTriangleDistance(x, y, z, p, a, b, c) {
  triangle.a.fromArray(p, 3 * a), triangle.b.fromArray(p, 3 * b), triangle.c.fromArray(p, 3 * c);
  return triangle.closestPointToPoint(point.set(x, y, z), closest).distanceTo(point);
}
