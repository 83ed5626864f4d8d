// Type declarations for mrvol's public JS API: lib/node.mjs (Node entry point) and lib/api.mjs
// (environment-agnostic wrapper around the emscripten module).

/** A triangle mesh as flat typed arrays, in the caller's vertex order. */
export interface Mesh {
  /** 3 doubles per vertex: x0 y0 z0 x1 ... */
  positions: Float64Array;
  /** 3 vertex indices (0-based) per triangle, counter-clockwise seen from outside. */
  faces: Uint32Array;
}

/** The wavelet scheme's name. */
export type SchemeName = 'loop' | 'butterfly' | 'linear';

/** Which wavelet transform to use. Defaults: Loop with alpha = -1.70943, beta = 0.42954. */
export interface SchemeOptions {
  scheme?: SchemeName;
  /** Loop update weight on the incident odd vertices (alpha = beta = 0 is the plain scheme). */
  alpha?: number;
  /** Loop update weight on the link odd vertices. */
  beta?: number;
}

/** A scheme and an analysis level e, 0 <= e <= levels (default 0). */
export interface TransformOptions extends SchemeOptions {
  level?: number;
}

export interface SubdivideOptions extends SchemeOptions {
  /** Number of 1-to-4 splits, 0..12 (default 1). */
  levels?: number;
}

export interface OpenMeshOptions {
  /** At most this many levels are detected (default 16). */
  maxLevels?: number;
}

/** What validate() finds about a valid mesh. */
export interface Topology {
  edges: number;
  boundaryEdges: number;
  components: number;
  closed: boolean;
  /** From the Euler characteristic, for a single closed component. */
  genus: number;
}

/** Facts about a multiresolution mesh. */
export interface MeshInfo {
  vertices: number;
  faces: number;
  levels: number;
  baseVertices: number;
  /** The caller's (0-based) indices of the level-0 vertices, ascending. */
  baseVertexIndices: Uint32Array;
  closed: boolean;
  boundaryEdges: number;
  genus: number;
  components: number;
  /** Signed enclosed volume (for an open mesh: of the cone to its boundary's centroid). */
  volume: number;
}

/** How much of a volume tensor is kept: the rows of the level-e cage vertices, or every entry. */
export type ThetaStorage = 'cage' | 'full';

export interface ThetaOptions extends TransformOptions {
  /** 'cage' (default) keeps what editing needs; 'full' keeps every entry. */
  storage?: ThetaStorage;
  /** Called with the fraction done (0..1); returning false cancels the computation. */
  onProgress?: (fraction: number) => boolean | void;
}

/** The header of a volume tensor: what it was computed for, and its size. */
export interface ThetaInfo {
  formatVersion: number;
  scheme: SchemeName;
  alpha: number;
  beta: number;
  /** Levels n of the mesh it belongs to. */
  levels: number;
  /** The level e of its coefficients. */
  level: number;
  storage: ThetaStorage;
  /** Connectivity fingerprint (16 hex digits) of the mesh it belongs to. */
  fingerprint: string;
  vertices: number;
  /** Non-zero entries of the full tensor, null when unknown. */
  nnzFull: number | null;
  nnzStored: number;
  bytes: number;
}

/** A volume tensor theta^e. Lives in the WebAssembly heap: call delete() when done. */
export interface Theta {
  /** Milliseconds computeTheta() took; null for a tensor read from a file. */
  readonly precomputeMs: number | null;
  info(): ThetaInfo;
  /** The theta file: versioned header, arrays, checksum (a fresh copy). */
  bytes(): Uint8Array;
  /** Frees the tensor; calling it again does nothing. Other methods then throw MrvolError. */
  delete(): void;
}

/** An error reported by mrvol's core, with its message as the core wrote it. */
export class MrvolError extends Error {
  constructor(message: string);
  name: 'MrvolError';
}

/**
 * A semi-regular mesh with its hierarchy and wavelet transforms. Arrays cross it in the caller's
 * vertex order and every array returned is a fresh copy. Call delete() when done: the mesh lives
 * in the WebAssembly heap. Any method of a deleted mesh throws MrvolError.
 */
export interface MultiresMesh {
  /** Number of levels n (the finest mesh is level n). */
  readonly levels: number;
  readonly vertexCount: number;
  readonly faceCount: number;
  /** The caller's indices of the level-0 vertices, ascending. */
  readonly baseVertexIndices: Uint32Array;

  /** Vertex/face counts, levels, base vertices, closedness, genus, volume. */
  info(): MeshInfo;
  /** Current positions, caller's vertex order. */
  positions(): Float64Array;
  faces(): Uint32Array;
  /** Depth (level of birth) of every vertex, caller's order. */
  depths(): Uint8Array;
  toMesh(): Mesh;
  setPositions(positions: Float64Array): void;
  /** Level-e coefficients (coarse for depth <= e, details beyond), caller's vertex order. */
  analyze(positions: Float64Array, options?: TransformOptions): Float64Array;
  /** Positions from level-e coefficients. */
  synthesize(coefficients: Float64Array, options?: TransformOptions): Float64Array;
  /** max |synthesis(analysis(x)) - x| over the current positions. */
  roundtripError(options?: TransformOptions): number;
  /** Connectivity fingerprint (16 hex digits): what a volume tensor depends on besides scheme and level. */
  fingerprint(): string;
  /** Computes the volume tensor theta^e of this mesh for a scheme and level e. */
  computeTheta(options?: ThetaOptions): Theta;
  /** Volume of the current positions through theta (checks that theta matches mesh, scheme and level). */
  thetaVolume(theta: Theta, options?: TransformOptions): number;
  /** Frees the mesh; calling it again does nothing. */
  delete(): void;
}

/** The API object: what wrapModule() and createMrvol() return. */
export interface Mrvol {
  MrvolError: typeof MrvolError;
  /** Parses OBJ text (triangles only) into a mesh with 0-based indices. */
  readObj(text: string): Mesh;
  /** OBJ text: `v` lines (17 significant digits) then `f` lines, vertex order kept. */
  writeObj(mesh: Mesh): string;
  /** Checks manifoldness and orientation; throws MrvolError saying where the mesh is wrong. */
  validate(mesh: Mesh): Topology;
  /** Signed enclosed volume of a valid mesh. */
  volume(mesh: Mesh): number;
  /** Validates the mesh and recovers its semi-regular hierarchy (any vertex order). */
  openMesh(mesh: Mesh, options?: OpenMeshOptions): MultiresMesh;
  /** n levels of zero-detail synthesis (subdivision) of a base mesh. */
  subdivide(base: Mesh, options?: SubdivideOptions): MultiresMesh;
  /** Reads a theta file; throws MrvolError if it is truncated, corrupt or of a future version. */
  readTheta(bytes: Uint8Array): Theta;
}

/**
 * Wraps an instantiated emscripten module (the result of createMrvolModule()). Exported by
 * lib/api.mjs, the environment-agnostic entry point (browsers, workers).
 */
export function wrapModule(module: object): Mrvol;

/**
 * Exported by lib/node.mjs (Node): loads build/wasm/mrvol-node.{mjs,wasm} and returns the API.
 * Rejects with MrvolError if the module is not built.
 */
export function createMrvol(): Promise<Mrvol>;
