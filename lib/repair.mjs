// The input stage of remeshing (lib/remesh.mjs): welding and the optional repair of a scan that is
// almost a closed 2-manifold (orientation made consistent and outward, duplicate, non-manifold and
// folded faces dropped, holes closed, optional smoothing); the remesher's validation after it
// names what the repair could not fix. No three.js here: plain arrays and the mrvol API.
import { connectivity } from './connectivity.mjs';
import { boundingDiagonal, hypot3, triangleNormal } from './geometry.mjs';

// ---- input: weld, components, validation ---------------------------------------------------------

/**
 * What is wrong with { positions: Float64Array, faces: Uint32Array } as a mesh to weld, repair or
 * remesh (the first problem found, in words), or null: typed arrays of 3 numbers per vertex and 3
 * indices per face, every index a vertex, every coordinate a finite number (an index past the end
 * read as vertex 0, out of bounds, and made a mesh of the wrong shape without a word).
 */
export function meshProblem(mesh) {
  if (!mesh || !(mesh.positions instanceof Float64Array) || !(mesh.faces instanceof Uint32Array))
    return 'expected a mesh { positions: Float64Array, faces: Uint32Array }';
  const { positions, faces } = mesh;
  if (positions.length % 3 !== 0) return `positions must hold 3 numbers per vertex, got ${positions.length}`;
  if (faces.length % 3 !== 0) return `faces must hold 3 vertex indices per face, got ${faces.length}`;
  const n = positions.length / 3;
  for (let i = 0; i < faces.length; i++)
    if (faces[i] >= n) return `face ${(i / 3) | 0} refers to vertex ${faces[i]} but the mesh has ${n} vertices`;
  for (let i = 0; i < positions.length; i++)
    if (!Number.isFinite(positions[i])) return `vertex ${(i / 3) | 0} has a coordinate that is not a finite number (${positions[i]})`;
  return null;
}

/**
 * Merges vertices with identical coordinates (after rounding to 1e-9 of the bounding-box
 * diagonal), drops faces that become degenerate and vertices no face uses. Throws RangeError for
 * a mesh meshProblem() finds wrong.
 * @returns {{ positions: Float64Array, faces: Uint32Array, merged: number, droppedFaces: number, unusedVertices: number }}
 *   unusedVertices: positions no kept face uses (dropped)
 */
export function weld(mesh) {
  const problem = meshProblem(mesh);
  if (problem) throw new RangeError(`weld: ${problem}`);
  const { positions, faces } = mesh;
  const n = positions.length / 3;
  const quantum = (boundingDiagonal(positions) || 1) * 1e-9;
  // Rounded coordinates hashed to a number; equal hashes compared coordinate by coordinate
  // (chains through `nextSame`), which strings as keys took several times as long for.
  const q = new Float64Array(3 * n);
  for (let i = 0; i < 3 * n; i++) q[i] = Math.round(positions[i] / quantum);
  // The chains' heads by hash: open addressing over typed arrays (a Map of 400k+ numbers took a
  // second on the 871k dragon), at most half full.
  let bits = 1;
  while (1 << bits < 2 * n) bits++;
  const slots = 1 << bits, mask = slots - 1, hashes = new Uint32Array(slots), heads = new Int32Array(slots).fill(-1);
  const nextSame = new Int32Array(n).fill(-1), remap = new Uint32Array(n);
  let unique = 0;
  for (let i = 0; i < n; i++) {
    const h = (Math.imul(q[3 * i] % 1e9 | 0, 73856093) ^ Math.imul(q[3 * i + 1] % 1e9 | 0, 19349663) ^ Math.imul(q[3 * i + 2] % 1e9 | 0, 83492791)) >>> 0;
    let s = Math.imul(h, 0x9e3779b1) >>> (32 - bits);
    while (heads[s] >= 0 && hashes[s] !== h) s = (s + 1) & mask;
    let found = -1;
    for (let c = heads[s]; c >= 0; c = nextSame[c])
      if (q[3 * c] === q[3 * i] && q[3 * c + 1] === q[3 * i + 1] && q[3 * c + 2] === q[3 * i + 2]) { found = c; break; }
    if (found >= 0) {
      remap[i] = remap[found];
      continue;
    }
    // i represents a new position: first in its hash chain.
    nextSame[i] = heads[s];
    hashes[s] = h, heads[s] = i;
    remap[i] = unique++;
  }
  const kept = new Uint32Array(faces.length);
  let keptLength = 0, droppedFaces = 0;
  for (let f = 0; f < faces.length; f += 3) {
    const a = remap[faces[f]], b = remap[faces[f + 1]], c = remap[faces[f + 2]];
    if (a === b || b === c || c === a) droppedFaces++;
    else kept[keptLength++] = a, kept[keptLength++] = b, kept[keptLength++] = c;
  }
  // Compact: vertices in order of first use by a face.
  const order = new Int32Array(unique).fill(-1);
  const firstOf = new Uint32Array(unique);
  for (let i = n - 1; i >= 0; i--) firstOf[remap[i]] = i;
  let used = 0;
  const outFaces = new Uint32Array(keptLength);
  for (let i = 0; i < keptLength; i++) {
    if (order[kept[i]] < 0) order[kept[i]] = used++;
    outFaces[i] = order[kept[i]];
  }
  const outPositions = new Float64Array(3 * used);
  for (let u = 0; u < unique; u++)
    if (order[u] >= 0) for (let k = 0; k < 3; k++) outPositions[3 * order[u] + k] = positions[3 * firstOf[u] + k];
  return { positions: outPositions, faces: outFaces, merged: n - unique, droppedFaces, unusedVertices: unique - used };
}

/** The mesh with the vertices no face uses dropped, the others in order of first use (as weld() orders them). */
function withoutUnusedVertices(positions, faces) {
  const order = new Int32Array(positions.length / 3).fill(-1), out = new Uint32Array(faces.length);
  let used = 0;
  for (let i = 0; i < faces.length; i++) {
    if (order[faces[i]] < 0) order[faces[i]] = used++;
    out[i] = order[faces[i]];
  }
  const kept = new Float64Array(3 * used);
  for (let v = 0; v < order.length; v++) if (order[v] >= 0) for (let k = 0; k < 3; k++) kept[3 * order[v] + k] = positions[3 * v + k];
  return { positions: kept, faces: out, order };
}

function keepLargestComponent(mesh) {
  const { ofFace, count } = connectivity(mesh.faces, mesh.positions.length / 3).components;
  const sizes = new Uint32Array(count);
  for (const c of ofFace) sizes[c]++;
  let best = 0;
  for (let c = 1; c < count; c++) if (sizes[c] > sizes[best]) best = c;
  const faces = [];
  for (let f = 0; f < ofFace.length; f++) if (ofFace[f] === best) faces.push(mesh.faces[3 * f], mesh.faces[3 * f + 1], mesh.faces[3 * f + 2]);
  return { mesh: weld({ positions: mesh.positions, faces: Uint32Array.from(faces) }), dropped: count - 1 };
}

// ---- repair (optional): a closed 2-manifold from a scan that is almost one -----------------------

/**
 * Faces of `faces` (flat array) sharing three vertices: opposite orientations cancel in pairs (a
 * fin, two-sided and without volume, as crude decimation leaves them); of the rest one face stays.
 * @returns {{ keep: Uint8Array, finFaces: number, duplicateFaces: number }}
 */
function cancelDuplicates(faces) {
  const faceCount = faces.length / 3;
  // Faces grouped by their sorted vertex triple in an open-addressing table (typed arrays: a
  // string key per face took most of a large scan's repair): each group is named by its first face.
  let size = 1;
  while (size < 2 * faceCount) size *= 2;
  const slots = new Int32Array(size).fill(-1), sorted = new Uint32Array(faces.length);
  const plus = new Uint32Array(faceCount), minus = new Uint32Array(faceCount);
  const firstPlus = new Int32Array(faceCount).fill(-1), firstMinus = new Int32Array(faceCount).fill(-1);
  for (let f = 0; f < faceCount; f++) {
    const a = faces[3 * f], b = faces[3 * f + 1], c = faces[3 * f + 2];
    const lo = Math.min(a, b, c), hi = Math.max(a, b, c), mid = a + b + c - lo - hi;
    sorted[3 * f] = lo, sorted[3 * f + 1] = mid, sorted[3 * f + 2] = hi;
    // Same cyclic order as the sorted triple: one orientation; otherwise the other.
    const even = (a === lo && b === mid) || (b === lo && c === mid) || (c === lo && a === mid);
    let h = (Math.imul(lo, 73856093) ^ Math.imul(mid, 19349663) ^ Math.imul(hi, 83492791)) & (size - 1);
    let group;
    for (;; h = (h + 1) & (size - 1)) {
      const g = slots[h];
      if (g < 0) {
        slots[h] = group = f;
        break;
      }
      if (sorted[3 * g] === lo && sorted[3 * g + 1] === mid && sorted[3 * g + 2] === hi) {
        group = g;
        break;
      }
    }
    if (even) {
      if (plus[group]++ === 0) firstPlus[group] = f;
    } else if (minus[group]++ === 0) {
      firstMinus[group] = f;
    }
  }
  const keep = new Uint8Array(faceCount);
  let finFaces = 0, duplicateFaces = 0;
  for (let g = 0; g < faceCount; g++) {
    const p = plus[g], m = minus[g];
    if (p + m === 0) continue;
    const pairs = Math.min(p, m), rest = p > m ? p : m;
    finFaces += 2 * pairs;
    if (rest > pairs) {
      keep[p > m ? firstPlus[g] : firstMinus[g]] = 1;
      duplicateFaces += rest - pairs - 1;
    }
  }
  return { keep, finFaces, duplicateFaces };
}

/**
 * Faces that make the mesh non-manifold: all faces of an edge shared by more than two faces or
 * walked twice in the same direction, and at a vertex whose faces form several fans, the faces of
 * all fans but the largest. Returns a mask of the faces to drop and their count. `since` (or null:
 * the whole mesh is checked): the mesh is one that had no such face with faces removed around the
 * vertices of `since.touched` (a mask) and faces appended from index `since.appendedFrom` on. A
 * removal makes no edge bad, and leaves one fan at a vertex it does not touch: only the appended
 * faces' edges are checked, and the fans at the touched vertices, at the appended faces' corners
 * and at those of the faces of bad edges (the same faces as checking the whole mesh).
 */
export function nonManifoldFaces(faces, vertexCount, since = null) {
  const faceCount = faces.length / 3, drop = new Uint8Array(faceCount);
  const around = connectivity(faces, vertexCount).vertexFaces;
  // The face's vertex after `a` (its direction along the edge a-b).
  const after = (f, a) => { for (let j = 0; j < 3; j++) if (faces[3 * f + j] === a) return faces[3 * f + (j + 1) % 3]; };
  // An edge is bad if more than two faces share it, or two walk it the same way.
  const badEdge = (size, a, f0, f1) => size > 2 || (size === 2 && after(f0, a) === after(f1, a));
  if (!since) {
    const edges = connectivity(faces, vertexCount).edgeFaces, { offsets, list } = edges;
    for (let e = 0; e < edges.count; e++)
      if (badEdge(offsets[e + 1] - offsets[e], edges.a[e], list[offsets[e]], list[offsets[e] + 1]))
        for (let i = offsets[e]; i < offsets[e + 1]; i++) drop[list[i]] = 1;
  } else {
    // The appended faces' edges: their faces are those around the smaller end that hold the larger.
    const holding = [];
    for (let g = since.appendedFrom; g < faceCount; g++)
      for (let j = 0; j < 3; j++) {
        const x = faces[3 * g + j], y = faces[3 * g + (j + 1) % 3], a = x < y ? x : y, b = x < y ? y : x;
        holding.length = 0;
        for (let e = around.offsets[a]; e < around.offsets[a + 1]; e++) {
          const f = around.list[e];
          if (faces[3 * f] === b || faces[3 * f + 1] === b || faces[3 * f + 2] === b) holding.push(f);
        }
        if (badEdge(holding.length, a, holding[0], holding[1])) for (const f of holding) drop[f] = 1;
      }
  }
  // The vertices whose fans are looked at (null: all).
  let only = null;
  if (since) {
    only = Uint8Array.from(since.touched);
    for (let g = since.appendedFrom; g < faceCount; g++) for (let j = 0; j < 3; j++) only[faces[3 * g + j]] = 1;
    for (let f = 0; f < faceCount; f++) if (drop[f]) for (let j = 0; j < 3; j++) only[faces[3 * f + j]] = 1;
  }
  // Fans: the kept faces around a vertex, joined across the edges at it that two of them share
  // (union-find over the few faces of one vertex).
  // The faces kept by the edge step (the fans of every vertex are taken from them).
  const afterEdges = drop.slice();
  let most = 0;
  for (let v = 0; v < vertexCount; v++) most = Math.max(most, around.offsets[v + 1] - around.offsets[v]);
  const local = new Uint32Array(most), parent = new Uint32Array(most);
  const find = (i) => { while (parent[i] !== i) i = parent[i] = parent[parent[i]]; return i; };
  // The first local face at each other vertex (-1: none yet; reset after each vertex).
  const firstAt = new Int32Array(vertexCount).fill(-1);
  for (let v = 0; v < vertexCount; v++) {
    if (only && !only[v]) continue;
    let size = 0;
    for (let e = around.offsets[v]; e < around.offsets[v + 1]; e++) if (!afterEdges[around.list[e]]) local[size++] = around.list[e];
    if (size < 2) continue;
    for (let i = 0; i < size; i++) parent[i] = i;
    // Faces i and j share an edge at v if they share another vertex: each joins the first face
    // at each of its other vertices.
    for (let i = 0; i < size; i++)
      for (let x = 0; x < 3; x++) {
        const w = faces[3 * local[i] + x];
        if (w === v) continue;
        if (firstAt[w] < 0) firstAt[w] = i;
        else parent[find(i)] = find(firstAt[w]);
      }
    for (let i = 0; i < size; i++) for (let x = 0; x < 3; x++) firstAt[faces[3 * local[i] + x]] = -1;
    // One fan (the usual case): nothing to drop.
    const root = find(0);
    let one = true;
    for (let i = 1; i < size && one; i++) one = find(i) === root;
    if (one) continue;
    const sizes = new Map();
    for (let i = 0; i < size; i++) sizes.set(find(i), (sizes.get(find(i)) ?? 0) + 1);
    const largest = [...sizes].reduce((x, y) => (y[1] > x[1] ? y : x))[0];
    for (let i = 0; i < size; i++) if (find(i) !== largest) drop[local[i]] = 1;
  }
  let count = 0;
  for (let f = 0; f < drop.length; f++) count += drop[f];
  return { drop, count };
}

/**
 * Closes the boundary loops of at most `maxHoleEdges` edges (a triangle for three edges, else a
 * fan around a new vertex at the loop's centroid). Needs manifold vertices (one boundary loop
 * through each boundary vertex at most). Returns the new mesh and what it did. `touched` (a vertex
 * mask, or null): the mesh was closed, then faces went around those vertices only: a boundary
 * edge has both ends there (the same loops, found without the whole mesh's twins).
 */
export function fillHoles(mesh, maxHoleEdges, touched = null) {
  const { positions, faces } = mesh;
  const next = new Map();  // boundary half-edge of the hole, b -> a for a face edge a -> b without twin
  for (const h of boundaryHalfEdges(faces, positions.length / 3, touched)) {
    const f = (h / 3) | 0, j = h % 3;
    next.set(faces[3 * f + (j + 1) % 3], faces[h]);
  }
  // What the fills add (the mesh's own arrays are copied once at the end: copied into plain arrays
  // up front, a large scan's millions of numbers took seconds per pass).
  const addedPositions = [], addedFaces = [], vertexCount = positions.length / 3;
  let holesFilled = 0, holeEdges = 0, holesLeft = 0, largestLeft = 0;
  const seen = new Set();
  for (const start of next.keys()) {
    if (seen.has(start)) continue;
    const loop = [];
    for (let v = start; !seen.has(v); v = next.get(v)) seen.add(v), loop.push(v);
    if (loop.length > maxHoleEdges) {
      holesLeft++;
      largestLeft = Math.max(largestLeft, loop.length);
      continue;
    }
    holesFilled++;
    holeEdges += loop.length;
    if (loop.length === 3) {
      addedFaces.push(loop[0], loop[1], loop[2]);
      continue;
    }
    const c = vertexCount + addedPositions.length / 3;
    for (let k = 0; k < 3; k++) addedPositions.push(loop.reduce((s, v) => s + positions[3 * v + k], 0) / loop.length);
    for (let i = 0; i < loop.length; i++) addedFaces.push(loop[i], loop[(i + 1) % loop.length], c);
  }
  const outPositions = new Float64Array(positions.length + addedPositions.length), outFaces = new Uint32Array(faces.length + addedFaces.length);
  outPositions.set(positions), outPositions.set(addedPositions, positions.length);
  outFaces.set(faces), outFaces.set(addedFaces, faces.length);
  return { mesh: { positions: outPositions, faces: outFaces }, holesFilled, holeEdges, holesLeft, largestLeft };
}

/**
 * The half-edges (3f + j: face f's edge from corner j) whose twin is missing, in increasing order.
 * `touched`: as fillHoles' (only half-edges with both ends there are looked at), or null: all.
 */
function boundaryHalfEdges(faces, vertexCount, touched) {
  const out = [];
  if (!touched) {
    const twins = connectivity(faces, vertexCount).twins;
    for (let h = 0; h < twins.length; h++) if (twins[h] < 0) out.push(h);
    return out;
  }
  const around = connectivity(faces, vertexCount).vertexFaces;
  for (let a = 0; a < touched.length; a++) {
    if (!touched[a]) continue;
    for (let e = around.offsets[a]; e < around.offsets[a + 1]; e++) {
      const f = around.list[e];
      for (let j = 0; j < 3; j++) {
        if (faces[3 * f + j] !== a) continue;
        const b = faces[3 * f + (j + 1) % 3];
        if (touched[b] && twinFace(faces, around, a, b) < 0) out.push(3 * f + j);
      }
    }
  }
  return out.sort((x, y) => x - y);
}

/** The last face (by index) holding the directed edge b -> a, the twin of a -> b (as connectivity's twins), or -1. */
function twinFace(faces, around, a, b) {
  for (let e = around.offsets[b + 1] - 1; e >= around.offsets[b]; e--) {
    const g = around.list[e];
    for (let j = 0; j < 3; j++) if (faces[3 * g + j] === b && faces[3 * g + (j + 1) % 3] === a) return g;
  }
  return -1;
}

/** The unit normal of face f into out[at..at+2] (0 for a degenerate face). */
function unitFaceNormal(p, faces, f, out, at) {
  const n = triangleNormal(p, faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]);
  const l = hypot3(n[0], n[1], n[2]) || 1;
  for (let k = 0; k < 3; k++) out[at + k] = n[k] / l;
}

/**
 * Folded faces: faces whose normal points against those of at least two of their three edge
 * neighbours (more than 120 degrees apart) that agree with each other (less than 90 degrees
 * apart: a face turned over on a smooth surface, as crude decimation and hole filling leave them;
 * not the apex face of a sharp corner, such as a tetrahedron's, whose neighbours face three ways). A
 * mask of those faces and their neighbours (a hole that refills as a fan), and its count.
 * `since` ({ touched: a vertex mask, appendedFrom }, or null: every face is checked): the mesh is
 * one whose folded faces were all cut out, with faces removed around the touched vertices and
 * faces appended from index appendedFrom on; a face's neighbours changed only across an edge with
 * both ends among those vertices and the appended faces' corners, and only those faces are checked.
 * `sharpCorners`: a sharp corner's apex face counts as folded too (against two neighbours whatever
 * they face), as for a simplifier's output (see repair).
 */
export function foldedFaces(mesh, since = null, { sharpCorners = false } = {}) {
  const { positions: p, faces } = mesh;
  const faceCount = faces.length / 3, vertexCount = p.length / 3;
  const drop = new Uint8Array(faceCount);
  let count = 0;
  if (!since) {
    const normals = new Float64Array(faces.length);
    for (let f = 0; f < faceCount; f++) unitFaceNormal(p, faces, f, normals, 3 * f);
    const twins = connectivity(faces, vertexCount).twins, againstFaces = [0, 0, 0];
    for (let f = 0; f < faceCount; f++) {
      // (No array per face: on a large scan those were most of this step.)
      let against = 0, agree = false;
      for (let j = 0; j < 3; j++) {
        const g = twins[3 * f + j];
        if (!(g >= 0 && normals[3 * f] * normals[3 * g] + normals[3 * f + 1] * normals[3 * g + 1] + normals[3 * f + 2] * normals[3 * g + 2] < -0.5)) continue;
        // Agreeing with an earlier neighbour against the face (each pair once).
        for (let i = 0; i < against && !agree; i++) {
          const h = againstFaces[i];
          agree = normals[3 * h] * normals[3 * g] + normals[3 * h + 1] * normals[3 * g + 1] + normals[3 * h + 2] * normals[3 * g + 2] > 0;
        }
        againstFaces[against++] = g;
      }
      if (against < 2 || !(agree || sharpCorners)) continue;
      count++;
      drop[f] = 1;
      for (let j = 0; j < 3; j++) if (twins[3 * f + j] >= 0) drop[twins[3 * f + j]] = 1;
    }
    return { drop, count };
  }
  const changed = new Uint8Array(vertexCount);
  changed.set(since.touched.subarray(0, Math.min(since.touched.length, vertexCount)));
  for (let i = 3 * since.appendedFrom; i < faces.length; i++) changed[faces[i]] = 1;
  const around = connectivity(faces, vertexCount).vertexFaces;
  // The faces with an edge between two changed vertices, in increasing order.
  const look = new Uint8Array(faceCount), candidates = [];
  for (let v = 0; v < vertexCount; v++) {
    if (!changed[v]) continue;
    for (let e = around.offsets[v]; e < around.offsets[v + 1]; e++) {
      const f = around.list[e];
      if (look[f]) continue;
      const a = changed[faces[3 * f]], b = changed[faces[3 * f + 1]], c = changed[faces[3 * f + 2]];
      if (a + b + c >= 2) look[f] = 1, candidates.push(f);
    }
  }
  const own = new Float64Array(3), other = new Float64Array(3), againstNormals = new Float64Array(9), twins = [0, 0, 0];
  for (const f of candidates) {
    unitFaceNormal(p, faces, f, own, 0);
    let against = 0, agree = false;
    for (let j = 0; j < 3; j++) {
      const g = (twins[j] = twinFace(faces, around, faces[3 * f + j], faces[3 * f + (j + 1) % 3]));
      if (g < 0) continue;
      unitFaceNormal(p, faces, g, other, 0);
      if (!(own[0] * other[0] + own[1] * other[1] + own[2] * other[2] < -0.5)) continue;
      for (let i = 0; i < against && !agree; i++)
        agree = againstNormals[3 * i] * other[0] + againstNormals[3 * i + 1] * other[1] + againstNormals[3 * i + 2] * other[2] > 0;
      againstNormals.set(other, 3 * against++);
    }
    if (against < 2 || !(agree || sharpCorners)) continue;
    count++;
    drop[f] = 1;
    for (let j = 0; j < 3; j++) if (twins[j] >= 0) drop[twins[j]] = 1;
  }
  return { drop, count };
}

/**
 * Consistent orientation: faces are walked across the edges that exactly two faces
 * share, and a neighbour that walks the shared edge in the same direction is reversed (a patch
 * saved with flipped faces). A non-orientable surface keeps its conflicts (for the non-manifold
 * step to drop, and counted). Returns the faces, how many were reversed and the conflicts.
 */
function orientConsistently(faces, vertexCount) {
  const out = Uint32Array.from(faces);
  const edges = connectivity(faces, vertexCount).edgeFaces;
  const faceCount = faces.length / 3, seen = new Uint8Array(faceCount);
  // Faces across the edges that exactly two faces share (CSR).
  const degree = new Uint32Array(faceCount + 1);
  for (let e = 0; e < edges.count; e++)
    if (edges.offsets[e + 1] - edges.offsets[e] === 2) degree[edges.list[edges.offsets[e]] + 1]++, degree[edges.list[edges.offsets[e] + 1] + 1]++;
  for (let f = 0; f < faceCount; f++) degree[f + 1] += degree[f];
  const fill = degree.slice(0, faceCount), across = new Uint32Array(degree[faceCount]), edgeOf = new Uint32Array(degree[faceCount]);
  for (let e = 0; e < edges.count; e++) {
    if (edges.offsets[e + 1] - edges.offsets[e] !== 2) continue;
    const f = edges.list[edges.offsets[e]], g = edges.list[edges.offsets[e] + 1];
    edgeOf[fill[f]] = e, across[fill[f]++] = g;
    edgeOf[fill[g]] = e, across[fill[g]++] = f;
  }
  // Whether face f (as it is now in `out`) walks the edge e from its smaller end to its larger.
  const forward = (f, e) => {
    for (let j = 0; j < 3; j++) if (out[3 * f + j] === edges.a[e]) return out[3 * f + (j + 1) % 3] === edges.b[e];
    return false;
  };
  let reversed = 0;
  const stack = [];
  // The walk keeps its seed's orientation; orientOutwards() then turns inside-out components.
  for (let seed = 0; seed < faceCount; seed++) {
    if (seen[seed]) continue;
    seen[seed] = 1;
    stack.push(seed);
    while (stack.length) {
      const f = stack.pop();
      for (let i = degree[f]; i < degree[f + 1]; i++) {
        const g = across[i];
        if (seen[g]) continue;
        seen[g] = 1;
        if (forward(f, edgeOf[i]) === forward(g, edgeOf[i])) {
          const t = out[3 * g + 1];
          out[3 * g + 1] = out[3 * g + 2], out[3 * g + 2] = t;
          reversed++;
        }
        stack.push(g);
      }
    }
  }
  // Edges still walked twice the same way: the surface is one-sided there (a Klein bottle).
  let conflicts = 0;
  for (let e = 0; e < edges.count; e++)
    if (edges.offsets[e + 1] - edges.offsets[e] === 2 && forward(edges.list[edges.offsets[e]], e) === forward(edges.list[edges.offsets[e] + 1], e)) conflicts++;
  return { faces: out, reversed, conflicts };
}

/** Signed volume of the faces of each component (divergence theorem). */
function componentVolumes(mesh) {
  const { ofFace, count } = connectivity(mesh.faces, mesh.positions.length / 3).components;
  const volumes = new Float64Array(count), p = mesh.positions, f = mesh.faces;
  for (let t = 0; t < ofFace.length; t++) {
    const a = 3 * f[3 * t], b = 3 * f[3 * t + 1], c = 3 * f[3 * t + 2];
    volumes[ofFace[t]] += (p[a] * (p[b + 1] * p[c + 2] - p[b + 2] * p[c + 1]) - p[a + 1] * (p[b] * p[c + 2] - p[b + 2] * p[c]) +
                           p[a + 2] * (p[b] * p[c + 1] - p[b + 1] * p[c])) / 6;
  }
  return { volumes, ofFace };
}

/** Components of negative volume (inside out) reversed. Returns how many. */
function orientOutwards(mesh) {
  const { volumes, ofFace } = componentVolumes(mesh);
  let count = 0;
  for (const v of volumes) if (v < 0) count++;
  if (count === 0) return 0;
  const f = mesh.faces;
  for (let t = 0; t < ofFace.length; t++)
    if (volumes[ofFace[t]] < 0) {
      const x = f[3 * t + 1];
      f[3 * t + 1] = f[3 * t + 2], f[3 * t + 2] = x;
    }
  return count;
}

/**
 * Taubin's lambda|mu smoothing (lambda 0.5, mu -0.53, uniform weights), `iterations` pairs, in
 * place: evens out the crumples of a crudely decimated scan with little shrinking.
 */
function taubinSmooth(mesh, iterations) {
  const p = mesh.positions, { offsets, list } = connectivity(mesh.faces, p.length / 3).neighbours;
  const q = new Float64Array(p.length);
  for (let it = 0; it < 2 * iterations; it++) {
    const step = it % 2 ? -0.53 : 0.5;
    q.set(p);
    for (let v = 0; v < p.length / 3; v++) {
      const count = offsets[v + 1] - offsets[v];
      if (count === 0) continue;
      for (let k = 0; k < 3; k++) {
        let sum = 0;
        for (let e = offsets[v]; e < offsets[v + 1]; e++) sum += q[3 * list[e] + k];
        p[3 * v + k] = q[3 * v + k] + step * (sum / count - q[3 * v + k]);
      }
    }
  }
}

/**
 * The repair stage (`remesh --repair`), for scans that are almost a closed 2-manifold: weld by
 * position (weld()), then drop duplicate faces (opposite pairs cancel: fins), the faces of
 * non-manifold edges and vertices (repeated until none is left), optionally every component but
 * the largest, close the holes of at most `maxHoleEdges` edges, cut out folded faces and fill
 * again, and optionally smooth (`smooth` Taubin iterations). What is left wrong (a larger
 * hole, several components) is for the validation after it to name. `sharpCorners`: the apex
 * faces of sharp corners are cut out as folds too (foldedFaces), for a simplifier's output (the
 * remesher's bases and proxies), where such an apex is as often a fold as a corner and its refill
 * costs the fit nothing.
 * @returns {{ mesh: { positions: Float64Array, faces: Uint32Array }, report: object }}
 */
export function repair(input, { keepLargest = false, maxHoleEdges = 100, smooth = 0, sharpCorners = false } = {}) {
  const problem = meshProblem(input);
  if (problem) throw new RangeError(`repair: ${problem}`);
  const welded = weld(input);
  const report = { weldedVertices: welded.merged, unusedVertices: welded.unusedVertices, degenerateFaces: welded.droppedFaces, duplicateFaces: 0, finFaces: 0,
                   nonManifoldFaces: 0, droppedComponents: 0, holesFilled: 0, holeEdges: 0, holesLeft: 0 };
  let mesh = welded;
  // The mesh stays welded as faces go: only the vertices no face uses are dropped. Returns a mask
  // of the dropped faces' corners still used (new numbering), or null if nothing was dropped.
  // The vertices the removals touched since the last fill left the mesh closed (in the numbering
  // as it goes), or null: then the next fill and fold check look only there (see the passes).
  let sinceFill = null;
  const keepFaces = (keep) => {
    let count = 0;
    for (let f = 0; f < keep.length; f++) count += keep[f] ? 1 : 0;
    if (count === keep.length) return null;
    const faces = new Uint32Array(3 * count);
    for (let f = 0, i = 0; f < keep.length; f++) if (keep[f]) for (let j = 0; j < 3; j++) faces[i++] = mesh.faces[3 * f + j];
    const old = mesh.faces, kept = withoutUnusedVertices(mesh.positions, faces);
    mesh = { positions: kept.positions, faces: kept.faces };
    const touched = new Uint8Array(mesh.positions.length / 3);
    for (let f = 0; f < keep.length; f++)
      if (!keep[f]) for (let j = 0; j < 3; j++) if (kept.order[old[3 * f + j]] >= 0) touched[kept.order[old[3 * f + j]]] = 1;
    if (sinceFill) {
      const carried = touched.slice();
      for (let v = 0; v < sinceFill.length; v++) if (sinceFill[v] && kept.order[v] >= 0) carried[kept.order[v]] = 1;
      sinceFill = carried;
    }
    return touched;
  };
  // Non-manifold faces dropped until none is left (after the first call, only where faces went).
  // `since`: what changed since the mesh was last left with none (nonManifoldFaces), or null.
  // Returns whether none is left.
  const dropNonManifold = (since = null) => {
    for (let round = 0; round < 16; round++) {
      const { drop, count } = nonManifoldFaces(mesh.faces, mesh.positions.length / 3, since);
      if (count === 0) return true;
      report.nonManifoldFaces += count;
      since = { touched: keepFaces(drop.map((d) => 1 - d)), appendedFrom: mesh.faces.length / 3 };
    }
    return false;
  };
  const duplicates = cancelDuplicates(mesh.faces);
  report.finFaces = duplicates.finFaces;
  report.duplicateFaces = duplicates.duplicateFaces;
  keepFaces(duplicates.keep);
  const oriented = orientConsistently(mesh.faces, mesh.positions.length / 3);
  mesh = { positions: mesh.positions, faces: oriented.faces };
  report.reorientedFaces = oriented.reversed;
  report.oneSidedEdges = oriented.conflicts;
  report.foldedFaces = 0;
  // Folds left by the input or by a fill are cut out with their neighbours and filled again. After
  // the first pass, what the fill appended and the folds' removal touched is all that changed
  // since the non-manifold faces were dropped (if that ran to the end): only that is checked.
  // Likewise a fill of a mesh without non-manifold faces that closes every hole leaves it closed,
  // and the folds it had are cut out: the next holes and folds can only be where faces went since
  // (sinceFill) or were appended.
  let changed = null;
  for (let pass = 0; pass < 6; pass++) {
    const clean = dropNonManifold(changed), local = sinceFill;
    if (pass === 0 && keepLargest && mesh.faces.length > 0) {
      const largest = keepLargestComponent(mesh);
      mesh = largest.mesh;
      report.droppedComponents = largest.dropped;
    }
    const filled = fillHoles(mesh, maxHoleEdges, local);
    report.holesFilled += filled.holesFilled;
    report.holeEdges += filled.holeEdges;
    report.holesLeft = filled.holesLeft;
    report.largestHoleLeft = filled.largestLeft;
    const appendedAt = mesh.faces.length / 3;
    mesh = filled.mesh;
    const folds = foldedFaces(mesh, local ? { touched: local, appendedFrom: appendedAt } : null, { sharpCorners });
    if (folds.count === 0 || filled.holesLeft > 0 || pass === 5) break;
    report.foldedFaces += folds.count;
    sinceFill = clean ? new Uint8Array(mesh.positions.length / 3) : null;
    const keep = folds.drop.map((d) => 1 - d), touched = keepFaces(keep);
    // The appended faces stay last, in order: they start after the kept faces that were there before.
    let appendedFrom = 0;
    for (let f = 0; f < appendedAt; f++) appendedFrom += keep[f];
    changed = clean ? { touched, appendedFrom } : null;
  }
  // A fill can repeat a face that is still there (a 3-edge hole closed by the face across it):
  // such pairs cancel, and what they leave is cleaned and filled once more.
  const again = cancelDuplicates(mesh.faces);
  if (again.finFaces + again.duplicateFaces > 0) {
    report.finFaces += again.finFaces;
    report.duplicateFaces += again.duplicateFaces;
    keepFaces(again.keep);
    dropNonManifold();
    const filled = fillHoles(mesh, maxHoleEdges);
    report.holesFilled += filled.holesFilled;
    report.holeEdges += filled.holeEdges;
    report.holesLeft = filled.holesLeft;
    mesh = filled.mesh;
  }
  report.reversedComponents = orientOutwards(mesh);
  report.smoothIterations = smooth;
  if (smooth > 0) {
    // What the smoothing did, for the remesher's report (its distances are to the smoothed surface).
    const before = mesh.positions.slice(), volumeBefore = componentVolumes(mesh).volumes.reduce((a, b) => a + b, 0);
    taubinSmooth(mesh, smooth);
    let moved = 0;
    for (let v = 0; v < before.length; v += 3)
      moved = Math.max(moved, hypot3(mesh.positions[v] - before[v], mesh.positions[v + 1] - before[v + 1], mesh.positions[v + 2] - before[v + 2]));
    report.smoothing = { volumeBefore, volumeAfter: componentVolumes(mesh).volumes.reduce((a, b) => a + b, 0),
                         largestMove: moved / (boundingDiagonal(before) || 1) };
  }
  return { mesh, report };
}
