// Connectivity of a triangle mesh given as a flat face array (3 vertex indices per face): what the
// remesher and the repair stage ask of it (faces around a vertex, neighbours, the face across an
// edge, faces of an edge, connected components), each built when first asked for and kept with
// the faces array (the pipeline never edits one in place).

/** Key of the directed edge a -> b (vertex indices below 2^32). */
export const edgeKey = (a, b) => a * 0x100000000 + b;

const cache = new WeakMap();

/**
 * The connectivity of `faces` over `vertexCount` vertices, shared by every caller that asks for
 * the same faces array and vertex count.
 * @param {Uint32Array} faces
 * @param {number} vertexCount
 * @returns {MeshConnectivity}
 */
export function connectivity(faces, vertexCount) {
  let c = cache.get(faces);
  if (!c || c.vertexCount !== vertexCount) cache.set(faces, (c = new MeshConnectivity(faces, vertexCount)));
  return c;
}

class MeshConnectivity {
  #vertexFaces = null;
  #neighbours = null;
  #twins = null;
  #edgeFaces = null;
  #components = null;

  constructor(faces, vertexCount) {
    this.faces = faces;
    this.vertexCount = vertexCount;
  }

  /** Faces around each vertex as CSR ({ offsets, list }), in increasing face order. */
  get vertexFaces() {
    if (this.#vertexFaces) return this.#vertexFaces;
    const { faces, vertexCount } = this;
    const offsets = new Uint32Array(vertexCount + 1);
    for (let i = 0; i < faces.length; i++) offsets[faces[i] + 1]++;
    for (let v = 0; v < vertexCount; v++) offsets[v + 1] += offsets[v];
    const fill = offsets.slice(0, vertexCount), list = new Uint32Array(faces.length);
    for (let i = 0; i < faces.length; i++) list[fill[faces[i]]++] = (i / 3) | 0;
    return (this.#vertexFaces = { offsets, list });
  }

  /**
   * Neighbours of each vertex as CSR ({ offsets, list }), each vertex's in the order the faces
   * first name them (as a Set would keep them).
   */
  get neighbours() {
    if (this.#neighbours) return this.#neighbours;
    const { faces, vertexCount } = this;
    const start = new Uint32Array(vertexCount + 1);
    for (let i = 0; i < faces.length; i++) start[faces[i] + 1] += 2;
    for (let v = 0; v < vertexCount; v++) start[v + 1] += start[v];
    const size = new Uint32Array(vertexCount), room = new Uint32Array(start[vertexCount]);
    const add = (a, b) => {
      const s = start[a], n = size[a];
      for (let e = s; e < s + n; e++) if (room[e] === b) return;
      room[s + n] = b;
      size[a] = n + 1;
    };
    for (let f = 0; f < faces.length; f += 3)
      for (let j = 0; j < 3; j++) {
        const a = faces[f + j], b = faces[f + (j + 1) % 3];
        add(a, b);
        add(b, a);
      }
    const offsets = new Uint32Array(vertexCount + 1);
    for (let i = 0; i < vertexCount; i++) offsets[i + 1] = offsets[i] + size[i];
    const list = new Uint32Array(offsets[vertexCount]);
    for (let i = 0; i < vertexCount; i++) list.set(room.subarray(start[i], start[i] + size[i]), offsets[i]);
    return (this.#neighbours = { offsets, list });
  }

  /**
   * For each face f and corner j, the face holding the directed edge faces[3f + (j+1)%3] ->
   * faces[3f + j] (the twin of f's edge from corner j), or -1 (a boundary edge); the last such
   * face if several.
   */
  get twins() {
    if (this.#twins) return this.#twins;
    const { faces, vertexCount } = this;
    const n = faces.length;
    // The half-edges leaving each vertex (CSR, in increasing half-edge order, so increasing face)
    // with their far ends: the twin of a -> b is the last b -> a among b's few.
    const offsets = new Uint32Array(vertexCount + 1);
    for (let h = 0; h < n; h++) offsets[faces[h] + 1]++;
    for (let v = 0; v < vertexCount; v++) offsets[v + 1] += offsets[v];
    const fill = offsets.slice(0, vertexCount), far = new Uint32Array(n), face = new Uint32Array(n);
    for (let f = 0, h = 0; h < n; f++)
      for (let j = 0; j < 3; j++, h++) {
        const e = fill[faces[h]]++;
        far[e] = faces[3 * f + (j + 1) % 3];
        face[e] = f;
      }
    const twins = new Int32Array(n).fill(-1);
    for (let f = 0, h = 0; h < n; f++)
      for (let j = 0; j < 3; j++, h++) {
        const a = faces[h], b = faces[3 * f + (j + 1) % 3];
        for (let e = offsets[b + 1] - 1; e >= offsets[b]; e--) if (far[e] === a) { twins[h] = face[e]; break; }
      }
    return (this.#twins = twins);
  }

  /**
   * Faces around each undirected edge, grouped (counting sort by the smaller end, then the larger):
   * { count, a (smaller end), b (larger end), offsets (count + 1), list (face indices, increasing
   * within an edge) }.
   */
  get edgeFaces() {
    if (this.#edgeFaces) return this.#edgeFaces;
    const { faces, vertexCount } = this;
    const n = faces.length;
    // Each half-edge's smaller and larger end, once.
    const lows = new Uint32Array(n), highs = new Uint32Array(n);
    for (let f = 0; f < n; f += 3)
      for (let j = 0; j < 3; j++) {
        const x = faces[f + j], y = faces[f + (j + 1) % 3];
        lows[f + j] = x < y ? x : y;
        highs[f + j] = x < y ? y : x;
      }
    const start = new Uint32Array(vertexCount + 1);
    for (let h = 0; h < n; h++) start[lows[h] + 1]++;
    for (let v = 0; v < vertexCount; v++) start[v + 1] += start[v];
    const fill = start.slice(0, vertexCount), bucket = new Uint32Array(n);
    for (let h = 0; h < n; h++) bucket[fill[lows[h]]++] = h;
    const a = new Uint32Array(n), b = new Uint32Array(n), offsets = new Uint32Array(n + 1), list = new Uint32Array(n);
    const taken = new Uint8Array(n);
    let count = 0, at = 0;
    for (let v = 0; v < vertexCount; v++)
      for (let i = start[v]; i < start[v + 1]; i++) {
        const h = bucket[i];
        if (taken[h]) continue;
        const w = highs[h];
        a[count] = v, b[count] = w, offsets[count] = at;
        // Half-edges of this bucket with the same other end, in increasing order (faces increase).
        for (let j = i; j < start[v + 1]; j++) {
          const g = bucket[j];
          if (!taken[g] && highs[g] === w) taken[g] = 1, list[at++] = (g / 3) | 0;
        }
        count++;
      }
    offsets[count] = at;
    return (this.#edgeFaces = { count, a: a.subarray(0, count), b: b.subarray(0, count), offsets: offsets.subarray(0, count + 1), list });
  }

  /**
   * Connected components of the faces (sharing a vertex): { ofFace (component of each face,
   * numbered in order of first face), count }.
   */
  get components() {
    if (this.#components) return this.#components;
    const { faces, vertexCount } = this;
    const parent = new Int32Array(vertexCount).map((_, i) => i);
    const find = (x) => {
      while (parent[x] !== x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (let f = 0; f < faces.length; f += 3) {
      const a = find(faces[f]), b = find(faces[f + 1]), c = find(faces[f + 2]);
      parent[b] = a;
      parent[find(c)] = a;
    }
    const label = new Map();
    const ofFace = new Uint32Array(faces.length / 3);
    for (let f = 0; f < ofFace.length; f++) {
      const r = find(faces[3 * f]);
      if (!label.has(r)) label.set(r, label.size);
      ofFace[f] = label.get(r);
    }
    return (this.#components = { ofFace, count: label.size });
  }
}
