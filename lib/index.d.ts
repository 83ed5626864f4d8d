// Type declarations for mrvol's public JS API, the package's main entry: lib/node.mjs (Node),
// lib/browser.mjs (browsers, workers) and lib/api.mjs (the environment-agnostic wrapper around the
// emscripten module). Remeshing has its own entry, `mrvol/remesh` (lib/remesh.d.ts).

/** A triangle mesh as flat typed arrays, in the caller's vertex order. */
export interface Mesh {
  /** 3 doubles per vertex: x0 y0 z0 x1 ... */
  positions: Float64Array;
  /** 3 vertex indices (0-based) per triangle, counter-clockwise seen from outside. */
  faces: Uint32Array;
  /**
   * Set by readObj: the OBJ line of every vertex and face. Errors of validate, volume and openMesh
   * then name each vertex and face with its line ("face 3 (line 17)"); ignored when the lengths
   * no longer match positions and faces.
   */
  lines?: { vertex: Uint32Array; face: Uint32Array };
}

/** What readObj returns: the mesh and what else the OBJ file carried. */
export interface ObjMesh extends Mesh {
  lines: { vertex: Uint32Array; face: Uint32Array };
  /**
   * Vertices welded away: v lines at exactly the position of an earlier one (an exporter's split
   * vertices, e.g. three.js's OBJExporter) are one vertex, as in STL and glTF files. `lines.vertex`
   * and `colors` are each vertex's first v line's; writeObjLike writes every v line back.
   */
  welded: number;
  /** Faces with more than 3 corners (triangulated: a fan if convex, else ear clipping), and their triangles. */
  polygons: number;
  polygonTriangles: number;
  /** 2 per `vt` line, when there are any. */
  texCoords?: Float64Array;
  /** 3 per `vn` line, when there are any. */
  normals?: Float64Array;
  /** 3 per vertex (r g b), when every `v` line has them. */
  colors?: Float64Array;
  /** Per triangle corner, the vt / vn index (0xffffffff: none), when faces refer to them. */
  cornerTexCoords?: Uint32Array;
  cornerNormals?: Uint32Array;
  /** What was left out, in words, when face corners refer to vt / vn lines the file does not have (those attributes dropped; the mesh read). */
  dropped?: string;
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
  /** Whose volume `volume` is: the mesh's triangles, or its Loop limit surface. */
  surface: VolumeSurface;
}

/**
 * The surface whose volume is meant: the mesh itself ('mesh', the default), or the Loop limit
 * surface of the fine mesh ('limit': what zero-detail Loop synthesis converges to; closed meshes
 * only). docs/limit-volume.md has the method.
 */
export type VolumeSurface = 'mesh' | 'limit';

export interface SurfaceOptions {
  surface?: VolumeSurface;
}

/** How much of a volume tensor is kept: the rows of the level-e cage vertices, or every entry. */
export type ThetaStorage = 'cage' | 'full';

export interface ThetaOptions extends TransformOptions {
  /** 'cage' (default) keeps what editing needs; 'full' keeps every entry. */
  storage?: ThetaStorage;
  /** 'limit': theta^e of the Loop limit surface's volume (for editors created with surface 'limit'). */
  surface?: VolumeSurface;
  /** Called with the fraction done (0..1); returning false cancels the computation (surface 'mesh' only). */
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
  /** Whose volume the tensor holds. */
  surface: VolumeSurface;
  /** Connectivity fingerprint (16 hex digits) of the mesh it belongs to. */
  fingerprint: string;
  vertices: number;
  /** Non-zero entries of the full tensor, null when unknown. */
  nnzFull: number | null;
  nnzStored: number;
  bytes: number;
}

/** Stored entries of a theta: theta_{i[t] j[t] k[t]} = values[t], i < j < k, hierarchy order. */
export interface ThetaEntries {
  i: Uint32Array;
  j: Uint32Array;
  k: Uint32Array;
  values: Float64Array;
}

/** A scheme and a lifting level l, 1 <= l <= levels (required): the synthesis from M^(l-1) to M^l. */
export interface LiftingLevelOptions extends SchemeOptions {
  level: number;
}

/** Which lifting phases to run: the first `steps` of the level (synthesis) or the last (analysis). */
export interface LiftingStepsOptions extends LiftingLevelOptions {
  /** 0..number of steps of the level (default: all of them). */
  steps?: number;
}

/**
 * One lifting step (a phase of paper Figure 3), vertex indices in the caller's order. A lift does,
 * for every row r, x[targets[r]] += sum over s in [offsets[r], offsets[r+1]) of
 * weights[s] * x[sources[s]]; a scaling does x[targets[r]] *= weights[r] (offsets and sources empty).
 */
export interface LiftingStep {
  /** 'U', 'P_o', 'N', 'P_e' (Loop); 'U', 'P' (Butterfly, linear). */
  name: string;
  scaling: boolean;
  /** A lift that reads only the details of the level (does nothing in subdivision). */
  readsOnlyDetails: boolean;
  targets: Uint32Array;
  offsets: Uint32Array;
  sources: Uint32Array;
  weights: Float64Array;
}

/** A volume tensor theta^e. Lives in the WebAssembly heap: call delete() when done. */
export interface Theta {
  /** Milliseconds computeTheta() took; null for a tensor read from a file. */
  readonly precomputeMs: number | null;
  info(): ThetaInfo;
  /** The theta file: versioned header, arrays, checksum (a fresh copy). */
  bytes(): Uint8Array;
  /**
   * The stored entries, one per i < j < k (the tensor is alternating), in storage order. Indices
   * are in hierarchy order (vertices by depth); MultiresMesh.hierarchyOrder() maps them to the
   * caller's vertices.
   */
  entries(): ThetaEntries;
  /** Frees the tensor; calling it again does nothing. Other methods then throw MrvolError. */
  delete(): void;
}

/** Options of a drag or a correction. */
export interface EditOptions {
  /** Relative volume error to reach, 0 < tolerance < 1 (default 1e-5, the paper's threshold). */
  tolerance?: number;
  /** false: apply the move without correcting the volume (default true). */
  preserve?: boolean;
  /** Iterations per sub-step, at least 1 (default 50). */
  maxIterations?: number;
  /** Large moves are split into at most this many sub-steps, at least 1 (default 64). */
  maxSubsteps?: number;
}

/** What a drag or a correction did. */
export interface EditReport {
  /** The volume to keep. */
  volumeReference: number;
  /** The volume of the moved shape before the correction. */
  volumeTarget: number;
  /** The volume after the correction. */
  volumeResult: number;
  /** |volumeResult - volumeReference| / |volumeReference| (with parts: the worst part's). */
  relativeError: number;
  iterations: number;
  substeps: number;
  /** false when the tolerance was not reached; `message` then says why. */
  converged: boolean;
  /** Empty when converged. */
  message: string;
  /** The gradient path the correction used. */
  path: GradientPath;
  /** With parts: each part's volume after the edit, and its reference (empty without parts). */
  partVolumes: Float64Array;
  partReferences: Float64Array;
  /** While the centre of mass is kept: the kept centre and where it ended, [x, y, z]. */
  centroidReference?: Float64Array;
  centroidResult?: Float64Array;
}

/** What an editor keeps: always the volume, optionally the centre of mass. */
export type KeptQuantity = 'volume' | 'centroid';

/**
 * How an editor's gradient is had: 'tensor', the cage's cubic polynomial from theta^e; 'polynomial',
 * the same built from the fine mesh (no theta); 'matrix-free', the adjoint of synthesis.
 */
export type GradientPath = 'tensor' | 'polynomial' | 'matrix-free';

/** One vertex of a drag (caller's vertex index, a level-e cage vertex): a new position or an offset. */
export type VertexMove =
  | { vertex: number; position: Vector3Like }
  | { vertex: number; offset: Vector3Like };

/** Three numbers: an array or a typed array (checked: length 3, finite). */
export type Vector3Like = readonly [number, number, number] | readonly number[] | Float64Array | Float32Array;

/** Which coefficients may absorb the volume correction. */
export interface FreeSetOptions {
  /**
   * Cage vertices: 'minus-held' (default; 'cage' is the same) = all but the held ones, 'all' = the
   * held ones too, or a list of caller vertex indices (cage vertices). Boundary vertices never move.
   */
  cage?: 'minus-held' | 'cage' | 'all' | ArrayLike<number>;
  /** Also the details d^l of these levels l (e <= l < n: the vertices born at level l + 1); matrix-free path. */
  detailLevels?: ArrayLike<number>;
}

export interface EditorOptions extends TransformOptions {
  /** theta^e (cage storage) of this mesh, scheme and level: the tensor gradient path. */
  theta?: Theta;
  /** Without a theta: 'auto' (default) or 'polynomial' builds the cage polynomial from the fine mesh; 'matrix-free' does not. */
  path?: 'auto' | 'polynomial' | 'matrix-free' | 'tensor';
  /** Whose volume is kept: 'mesh' (default) or 'limit' (the Loop limit surface; closed meshes, matrix-free or a limit theta). */
  surface?: VolumeSurface;
  /** ['volume'] (default) or ['volume', 'centroid'] (also the centre of mass; mesh surface, matrix-free), or 'volume,centroid'. */
  keep?: KeptQuantity[] | string;
}

/**
 * A volume-preserving editing session on the level-e cage of a MultiresMesh (method section 7).
 * Vertex indices are the caller's; cage arrays are in cage order (cageVertices()); coefficients()
 * and the matrix-free gradient are in hierarchy order (the cage first). Deleted with its mesh.
 */
export interface VolumeEditor {
  /** The analysis level e. */
  readonly level: number;
  /** Number of level-e cage vertices V_e. */
  readonly cageSize: number;
  /** True once delete() (or the mesh's delete()) ran; every method then throws MrvolError. */
  readonly deleted: boolean;
  /** The caller's index of each cage vertex, in cage order. */
  cageVertices(): Uint32Array;
  /** The cage-order index of a caller's vertex; throws MrvolError if it is not a level-e cage vertex. */
  cageIndexOf(vertex: number): number;
  /** Level-e coarse coefficients, 3 per cage vertex, cage order. */
  cagePositions(): Float64Array;
  /** Fine positions, caller's vertex order. */
  positions(): Float64Array;
  /**
   * The fine positions as float32 (3 per vertex, caller's order) viewing WASM memory, no copy:
   * rewritten in place by the next call after an edit. Invalidated (length 0) when WASM memory
   * grows: take it again after each edit.
   */
  positionsView(): Float32Array;
  /** Area-weighted unit vertex normals of the current positions, a view like positionsView(). */
  normalsView(): Float32Array;
  /** Changes whenever positionsView()'s values do (as of the last view taken). */
  readonly surfaceVersion: number;
  /** The caller's vertices the last rewrite of each view changed (a range to upload). */
  updatedRanges(): { positions: { first: number; count: number }; normals: { first: number; count: number } };
  /** All level-e coefficients (3 N), hierarchy order: the cage, then the details. */
  coefficients(): Float64Array;
  /** The current (exact) volume. */
  volume(): number;
  /** The volume edits keep: the volume at creation unless set. */
  referenceVolume(): number;
  setReferenceVolume(volume: number): void;
  /** The volume gradient's path; while the centre of mass is kept a step runs matrix-free (its report's path). */
  path(): GradientPath;
  /** Uses theta^e (cage storage, this mesh, scheme and level); the editor keeps its own copy. */
  useTheta(theta: Theta): void;
  /** The cage polynomial built from the fine mesh; returns the path in use ('matrix-free' on a cage too fine for it). */
  usePolynomial(): GradientPath;
  useMatrixFree(): void;
  setFreeSet(options?: FreeSetOptions): void;
  /**
   * Localized preservation: parts as lists of caller cage-vertex indices (disjoint), each keeping
   * its own volume; references default to the current part volumes. [] goes back to one constraint.
   */
  setParts(parts: ArrayLike<number>[], references?: ArrayLike<number>): void;
  partVolumes(): Float64Array;
  /** Whose volume is kept. */
  surface(): VolumeSurface;
  /** Keeps the centre of mass where it is now (with the volume), or stops keeping it. */
  keepCentroid(keep?: boolean): void;
  keepsCentroid(): boolean;
  /** The mesh solid's centre of mass now. */
  centroid(): Float64Array;
  /** The centre of mass kept (the current one when it is not kept). */
  referenceCentroid(): Float64Array;
  /**
   * Moves the cage to `target` (3 per cage vertex, cage order), keeping the flagged `held` cage
   * vertices where the target puts them, and restores the volume.
   */
  deformCage(target: Float64Array, held: ArrayLike<number>, options?: EditOptions): EditReport;
  /** A drag: the listed vertices move and are held. */
  moveVertices(moves: VertexMove[], options?: EditOptions): EditReport;
  /** Restores the reference volume of the current shape, holding the flagged cage vertices. */
  correct(held?: ArrayLike<number>, options?: EditOptions): EditReport;
  /**
   * Theta_tau, the gradient of the volume: 'matrix-free' (default) for all 3 N coefficients in
   * hierarchy order; 'tensor' for the 3 V_e cage coefficients (needs useTheta()).
   */
  gradient(path?: GradientPath): Float64Array;
  /** Frees the session; calling it again does nothing. */
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

  /** Vertex/face counts, levels, base vertices, closedness, genus, volume (of `surface`, default 'mesh'). */
  info(options?: SurfaceOptions): MeshInfo;
  /** Current positions, caller's vertex order. */
  positions(): Float64Array;
  faces(): Uint32Array;
  /** Triangles of the level-l mesh (the level-l cage), caller's vertex indices. */
  levelFaces(level: number): Uint32Array;
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
  /** The lifting steps of level l, in the order synthesis applies them. */
  liftingSteps(options: LiftingLevelOptions): LiftingStep[];
  /**
   * Runs the first `steps` lifting steps of level l on level-(l-1) coefficients (caller's order,
   * 3 per vertex; only vertices of depth <= l change); all steps give the level-l coefficients.
   */
  synthesizeSteps(coefficients: Float64Array, options: LiftingStepsOptions): Float64Array;
  /**
   * Analysis phase by phase: undoes the last `steps` lifting steps of level l, in reverse order,
   * on level-l coefficients; analyzeSteps(synthesizeSteps(c, all), S - k) equals synthesizeSteps(c, k).
   */
  analyzeSteps(coefficients: Float64Array, options: LiftingStepsOptions): Float64Array;
  /**
   * The adjoint of level l's synthesis phase by phase (paper Figure 5: each mask applied outwards,
   * x_s += w x_t): the transposes of the last `steps` steps, in reverse order, on a covector of the
   * level-l vertices; all of them give the covector of (c^(l-1), d^(l-1)).
   */
  transposeSteps(covector: Float64Array, options: LiftingStepsOptions): Float64Array;
  /**
   * The level-l approximation of `positions` (paper Figure 1): analysis at level l (options.level,
   * 0..levels), the details of the vertices born after level l set to zero, synthesis. Same
   * vertices and faces; level = levels gives the positions back.
   */
  approximation(positions: Float64Array, options?: TransformOptions): Float64Array;
  /** Caller's vertex index of each hierarchy index (hierarchy order: by depth, as theta entries). */
  hierarchyOrder(): Uint32Array;
  /** Connectivity fingerprint (16 hex digits): what a volume tensor depends on besides scheme and level. */
  fingerprint(): string;
  /** The hierarchy as flat arrays, for openMeshWithHierarchy in another instance of the module. */
  hierarchyArrays(): HierarchyArrays;
  /**
   * What computing theta^e with cage storage would take (sampled patches, no tensor work); `fits`
   * is the policy the CLI and the web editor follow (tensor when it fits, else matrix-free).
   */
  estimateTheta(options?: { level?: number } & SchemeOptions): ThetaEstimate;
  /** Computes the volume tensor theta^e of this mesh for a scheme and level e. */
  computeTheta(options?: ThetaOptions): Theta;
  /** Volume of the current positions through theta (checks that theta matches mesh, scheme and level; the surface is theta's own). */
  thetaVolume(theta: Theta, options?: TransformOptions): number;
  /** Starts an editing session at level e from the current positions (the editor copies them). */
  createEditor(options?: EditorOptions): VolumeEditor;
  /** Frees the mesh and its editors; calling it again does nothing. */
  delete(): void;
}

/** A mesh file format mrvol reads. */
export type MeshFormat = 'obj' | 'stl' | 'ply' | 'off' | 'gltf' | 'glb';

/** What readMesh returns: the mesh and what reading it did. */
export interface ImportedMesh extends Mesh {
  format: MeshFormat;
  /** 'binary STL', 'ASCII STL', 'ASCII PLY', 'binary little-endian PLY', 'binary big-endian PLY', 'OFF', 'COFF', 'glTF', 'GLB', 'OBJ', ... */
  variant: string;
  /**
   * For each vertex, its first source vertex: the file's vertex index (OBJ, PLY, OFF), the
   * triangle corner 3 t + k (STL), the running index over the scene's POSITION accessors (glTF).
   */
  sourceVertex: Uint32Array;
  /** Vertices in the file (STL: 3 per triangle). */
  sourceVertices: number;
  /** Faces in the file (polygons; glTF triangles after strips and fans). */
  sourceFaces: number;
  /** Source vertices merged into an earlier one at exactly the same position. */
  welded: number;
  /** Polygons of more than 3 corners split into triangle fans. */
  triangulated: number;
  /** glTF and GLB only: the file, for writeGlb(mesh, { source }). */
  source?: GltfSource;
}

/** What writeGlb needs to write a glTF again with its own data (ImportedMesh.source, not enumerable). */
export interface GltfSource {
  bytes: Uint8Array;
  format: 'gltf' | 'glb';
  resources?: Array<[string, Uint8Array]>;
}

export interface ReadMeshOptions {
  /** File name: its extension tells the format when the content has no signature. */
  name?: string;
  /** Forces the format. */
  format?: MeshFormat;
  /** A .gltf's sidecar files (buffers), by the URI the .gltf names them with. */
  resources?: Record<string, Uint8Array> | Map<string, Uint8Array> | Array<[string, Uint8Array]>;
}

/** A chunked OBJ reader (Mrvol.createObjReader). */
export interface ObjReader {
  push(chunk: Uint8Array): void;
  finish(): ObjMesh;
  cancel(): void;
  readonly bytesRead: number;
}

/** Closest points on a fixed triangle mesh (Mrvol.closestPoints): a tree built once in the core. */
export interface ClosestPoints {
  readonly triangleCount: number;
  /**
   * The closest point written into out: x, y, z, distance, triangle index. maxDistance (Infinity: none) prunes the
   * walk: the closest point if within it; else false (out untouched), or the closest of the triangles in boxes that
   * reach within it (as three-mesh-bvh's closestPointToPoint).
   */
  closest(x: number, y: number, z: number, maxDistance: number, out: Float64Array | number[]): boolean;
  /** Batched queries (3 numbers per point); bounds prune (a query with nothing within its bound is searched without it). */
  closestMany(points: Float64Array, bounds?: Float64Array | null): { points: Float64Array; distances: Float64Array; triangles: Uint32Array };
  /** Largest distance from the other mesh's samples (vertices, then 4 points per face, strided to maxSamples) to this mesh. */
  sampledDistanceFrom(other: Mesh, maxSamples?: number): number;
  /** Frees the tree now (else when the object is collected). */
  dispose(): void;
}

/** The API object: what wrapModule() and createMrvol() return. */
export interface Mrvol {
  MrvolError: typeof MrvolError;
  /** How many threads the core's big loops run on (1: the single-thread build). */
  readonly threads: number;
  /**
   * Parses an OBJ file (its bytes, e.g. a Node Buffer, or its text) into a mesh with 0-based
   * indices, polygons triangulated, and the line of each vertex and face.
   */
  readObj(input: Uint8Array | string): ObjMesh;
  /**
   * An OBJ file read in chunks as they arrive: push(bytes) each chunk (split anywhere), then finish()
   * gives what readObj gives for the whole file. Errors (MrvolError, with the line) come from the push
   * that completes the bad line, or from finish; the reader is then spent. cancel() frees one left unfinished.
   */
  createObjReader(options?: { size?: number }): ObjReader;
  /**
   * Closest points on the mesh's triangles (the core's tree, or `tree`: 6 bounds (lo, hi), a first and a count per
   * node, count 0xffffffff for an inner node whose second child is at `first`); throws MrvolError for an index out
   * of range, a non-finite corner or a bad tree.
   */
  closestPoints(mesh: Mesh, options?: { tree?: { bounds: Float64Array; first: Uint32Array; count: Uint32Array } }): ClosestPoints;
  /** three-mesh-bvh's tree (0.9.x MeshBVH, default options) built in the core, bit for bit: for MeshBVH.deserialize. */
  threeMeshBvh(positions: Float32Array, index: Uint32Array): { roots: ArrayBuffer[]; index: Uint32Array };
  /** OBJ text: `v` lines (17 significant digits) then `f` lines, vertex order kept. */
  writeObj(mesh: Mesh): string;
  /**
   * The original OBJ file with its vertex positions replaced (same vertex count): every other line
   * and byte is kept. Returns a Uint8Array for a Uint8Array, a string for a string.
   */
  writeObjLike<T extends Uint8Array | string>(original: T, positions: Float64Array): T extends string ? string : Uint8Array;
  /**
   * Reads OBJ, STL (binary, ASCII), PLY (ASCII, binary little/big endian), OFF (COFF, NOFF, ...),
   * glTF 2.0 (.gltf with data: URIs or `resources`) and GLB: all meshes of the default scene with
   * their node transforms (their lines and points left out). Polygons become triangle fans; vertices
   * the format splits are welded by exact position (STL's corners, PLY's, OFF's and glTF's repeats).
   * An OBJ keeps one vertex per `v` line (its numbering is the file's, kept on export): one written
   * with a vertex per face corner (three.js's OBJExporter of a non-indexed geometry) reads open, and
   * remesh's / repair's weld closes it. Throws MrvolError naming the file part and offset or element.
   */
  readMesh(bytes: Uint8Array | ArrayBuffer, options?: ReadMeshOptions): ImportedMesh;
  /** The format of a file from its name (extension) and content; throws when it is none mrvol reads. */
  detectFormat(bytes: Uint8Array | ArrayBuffer, name?: string): MeshFormat;
  /**
   * A GLB file: one triangle primitive, float32 POSITION (rounded from the doubles), vertex NORMAL,
   * uint32 indices. With `source` (the `source` of a mesh readMesh read from glTF or GLB, triangles
   * unchanged): the source's JSON and data kept (materials, textures, other attributes, node
   * transforms), POSITION replaced, NORMAL recomputed where present.
   */
  writeGlb(mesh: Mesh, options?: { source?: GltfSource }): Uint8Array;
  /** Checks manifoldness and orientation; throws MrvolError saying where the mesh is wrong. */
  validate(mesh: Mesh): Topology;
  /** Signed enclosed volume of a valid mesh; surface 'limit': of its Loop limit surface (closed meshes). */
  volume(mesh: Mesh, options?: SurfaceOptions): number;
  /** Validates the mesh and recovers its semi-regular hierarchy (any vertex order). */
  openMesh(mesh: Mesh, options?: OpenMeshOptions): MultiresMesh;
  /** A quad mesh (or scheme 'catmull-clark'): its Catmull-Clark hierarchy (openQuadMesh). */
  openMesh(mesh: QuadMesh, options?: OpenMeshOptions & { scheme?: 'catmull-clark' }): QuadMultiresMesh;
  /** n levels of zero-detail synthesis (subdivision) of a base mesh. */
  subdivide(base: Mesh, options?: SubdivideOptions): MultiresMesh;
  /** Opens a mesh with the hierarchy another instance found (no validation or detection again). */
  openMeshWithHierarchy(mesh: Mesh, arrays: HierarchyArrays): MultiresMesh;
  /**
   * A mesh and its editor, with a copy of the part of this instance's memory in use, for
   * adoptTransferred in another instance that ran the same calls first (web/module-transfer.js warmUp).
   */
  transferable(mesh: MultiresMesh, editor: VolumeEditor, options?: SchemeOptions & { /** false: no copy (warming an instance up, or handing the memory over with copyMemory) */ memory?: boolean }): TransferredEditor;
  /**
   * Copies this instance's memory from byte `offset` into `into` (as much as fits) and returns the
   * bytes copied: a transferable({ memory: false })'s memory handed over a slice at a time.
   */
  copyMemory(offset: number, into: Uint8Array): number;
  /**
   * Grows this instance's memory to at least `bytes` ahead of a take-over and writes once to each
   * 4 KB page above what is in use (the page faults paid before the take-over), a slice at a time,
   * awaiting `between(fraction)` after each; stops early when `signal` is aborted (an AbortSignal, or
   * anything with `aborted`: the package's types name no DOM or Node global). Resolves to the
   * memory's size in bytes. The instance keeps working (the pages written hold zeros, as before).
   */
  growMemoryAhead(bytes: number, options?: { sliceBytes?: number; between?: (fraction: number) => Promise<void>; signal?: { readonly aborted: boolean } | null }): Promise<number>;
  /** Takes over what transferable gave, in an instance made for it (its memory is replaced); a single-thread one (threads: 1): a threaded instance refuses. */
  adoptTransferred(transfer: TransferredEditor): MultiresMesh;
  /**
   * adoptTransferred with the memory copied a slice at a time, awaiting `between(fraction copied)`
   * after each (a page keeps drawing); nothing else may use this instance until it resolves.
   * `memory` may be an async iterable of the consecutive slices (`memoryBytes` in all: the other
   * instance's copyMemory).
   */
  adoptTransferredInSlices(transfer: TransferredEditor | (Omit<TransferredEditor, 'memory'> & { memory: AsyncIterable<Uint8Array> }),
                           options?: { sliceBytes?: number; between?: (fraction: number) => Promise<void> }): Promise<MultiresMesh>;
  /** A quad base: n levels of Catmull-Clark subdivision (subdivideQuads). */
  subdivide(base: QuadMesh, options?: { levels?: number; scheme?: 'catmull-clark' }): QuadMultiresMesh;
  /** OBJ text to a quad mesh: every face must have 4 corners (MrvolError naming the line otherwise). */
  readObjQuads(input: Uint8Array | string): QuadMesh;
  /** A quad mesh as OBJ text with `f a b c d` lines. */
  writeObjQuads(mesh: QuadMesh): string;
  /** The volume enclosed by the bilinear patches of a valid quad mesh (docs/catmull-clark.md). */
  quadVolume(mesh: QuadMesh): number;
  openQuadMesh(mesh: QuadMesh, options?: OpenMeshOptions): QuadMultiresMesh;
  subdivideQuads(base: QuadMesh, options?: { levels?: number }): QuadMultiresMesh;
  /** Reads a theta file; throws MrvolError if it is truncated, corrupt or of a future version. */
  readTheta(bytes: Uint8Array): Theta;
}

/**
 * Wraps an instantiated emscripten module (the result of createMrvolModule()): for hosts that
 * instantiate the module themselves. Exported by every entry point (lib/api.mjs, lib/node.mjs,
 * lib/browser.mjs).
 */
export function wrapModule(module: object): Mrvol;

/** The default scheme and its Loop weights (the paper's); exported by lib/api.mjs. */
export const DEFAULT_SCHEME: Readonly<{ scheme: 'loop'; alpha: number; beta: number }>;

/**
 * The gradient path an editor uses (the rule of the CLI and the web editor): a path asked for is
 * taken as is; under 'auto' (default) matrix-free when detail levels are free, else 'polynomial',
 * or with thetaInBackground 'tensor' when theta^e's estimate fits. `estimate` is null unless it was
 * consulted.
 */
export function chooseGradientPath(mr: MultiresMesh, options?: { level?: number; path?: 'auto' | GradientPath;
  detailLevels?: number[]; thetaInBackground?: boolean } & SchemeOptions): { path: GradientPath; estimate: ThetaEstimate | null };

/**
 * Where createMrvol() finds the WebAssembly module, for hosts that move or serve it themselves.
 * Without any of them it is next to the entry point: build/wasm/ of the package (a bundler such as
 * vite follows the browser entry's `new URL(..., import.meta.url)` and copies the file).
 */
export interface CreateMrvolOptions {
  /**
   * URL of the .wasm, a string or a URL (browser: fetched; Node: a path or file: URL, read).
   * Both entries run `mrvol-web.wasm` (the Node and web builds differ in their JS only).
   */
  wasmUrl?: string | { readonly href: string };
  /** emscripten's hook: the URL (browser) or path (Node) of `path`, the .wasm's file name. */
  locateFile?: (path: string, prefix: string) => string;
  /** The .wasm bytes themselves (no fetch, no file read). */
  wasmBinary?: ArrayBuffer | ArrayBufferView;
  /**
   * Browser entry only: a WebAssembly.Module compiled already (say by a page, handed to its
   * worker). Typed as object so that the declarations need no DOM library.
   */
  wasmModule?: object;
  /**
   * Threads for the core's big loops (1..16; the renderer's surface passes, the cage basis table).
   * More than 1 loads the threaded build (`mrvol-node-mt` / `mrvol-web-mt`: WASM pthreads, a pool
   * of workers): in Node whenever it is built; in browsers only where the page is cross-origin
   * isolated (COOP same-origin, COEP require-corp), else the single-thread build. Default: the
   * cores, at most 8 (and 1 when the single-thread module's wasmUrl, wasmBinary or wasmModule is
   * given); in a browser, a threaded build that does not start then gives way to the single-thread
   * one (a console warning says why). 1: the single-thread build. A number given is kept to: the
   * threaded build not starting rejects.
   */
  threads?: number;
  /**
   * Browser entry only: where the threaded build's files are (default: beside the entry point,
   * build/wasm/): its factory .mjs and its .wasm; `worker`, a classic script for its pool's workers
   * (default: the script the package holds as text, started from a blob: URL of the page's origin).
   */
  threadedUrls?: { factory: string; wasm: string; worker?: string };
  /**
   * Browser entry only: ms the threaded build's pool may take to start (default 30000); past it, or
   * when a pool worker fails to start, createMrvol rejects with a MrvolError naming the files.
   */
  threadStartTimeout?: number;
}

/**
 * Whether the threaded build can run here: in a browser, whether this page or worker is cross-origin
 * isolated (SharedArrayBuffer exists); in Node, always.
 */
export function canUseThreads(): boolean;

/**
 * Loads the WASM core and returns the API: in Node (lib/node.mjs) the Node build, read from
 * disk; in browsers and workers (lib/browser.mjs) the web build, fetched and compiled.
 * Rejects with MrvolError if the module cannot be found or loaded.
 */
export function createMrvol(options?: CreateMrvolOptions): Promise<Mrvol>;


/** The estimate of MultiresMesh.estimateTheta. */
export interface ThetaEstimate {
  cageSize: number;
  /** Largest patch (indices the dense 2-form of one cage vertex spans). */
  maxPatch: number;
  entries: number;
  bytes: number;
  denseBytes: number;
  milliseconds: number;
  fits: boolean;
}

/** A quad mesh: 4 vertex indices per face, counter-clockwise seen from outside. */
export interface QuadMesh {
  positions: Float64Array;
  quads: Uint32Array;
}

/** QuadMultiresMesh.info(): MeshInfo's fields (volume: the bilinear patches') and lowestLevel. */
export interface QuadMeshInfo {
  vertices: number;
  faces: number;
  levels: number;
  /** The lowest level analysis reaches: 1 when the base is a cube (its first split is not invertible), else 0. */
  lowestLevel: number;
  baseVertices: number;
  baseVertexIndices: Uint32Array;
  closed: boolean;
  boundaryEdges: number;
  genus: number;
  components: number;
  volume: number;
}

/** A semi-regular quad mesh with its Catmull-Clark hierarchy (docs/catmull-clark.md). */
export interface QuadMultiresMesh {
  readonly scheme: 'catmull-clark';
  readonly levels: number;
  readonly lowestLevel: number;
  readonly vertexCount: number;
  readonly faceCount: number;
  readonly baseVertexIndices: Uint32Array;
  /** surface: 'mesh' only (a quad mesh's volume is its bilinear patches'; 'limit' is refused). */
  info(options?: { surface?: 'mesh' }): QuadMeshInfo;
  positions(): Float64Array;
  quads(): Uint32Array;
  levelQuads(level: number): Uint32Array;
  depths(): Uint8Array;
  toMesh(): QuadMesh;
  setPositions(positions: Float64Array): void;
  analyze(positions?: Float64Array, options?: { level?: number }): Float64Array;
  synthesize(coefficients: Float64Array, options?: { level?: number }): Float64Array;
  roundtripError(options?: { level?: number }): number;
  /** Level l's synthesis steps (P_f, P_e, N_3k/P_3k per valence-3 layer, N_v, P_v), caller's indices. */
  liftingSteps(options: { level: number }): LiftingStep[];
  /** The first `steps` lifting steps of level l (default all) on level-(l-1) coefficients (in JS over liftingSteps). */
  synthesizeSteps(coefficients: Float64Array, options: { level: number; steps?: number }): Float64Array;
  /** Undoes the last `steps` lifting steps of level l, in reverse order. */
  analyzeSteps(coefficients: Float64Array, options: { level: number; steps?: number }): Float64Array;
  /** The transposed last `steps` steps of level l, in reverse order (masks applied outwards). */
  transposeSteps(covector: Float64Array, options: { level: number; steps?: number }): Float64Array;
  /** The level-l approximation: analysis at l, the details of vertices born after l zeroed, synthesis. */
  approximation(positions: Float64Array, options: { level: number }): Float64Array;
  computeTheta(options?: { level?: number; storage?: 'cage' | 'full'; surface?: 'mesh' }): Theta;
  thetaVolume(theta: Theta, options?: { level?: number }): number;
  fingerprint(): string;
  /** path 'auto' (default): the cage polynomial when the cage is 3 or more levels below the mesh, else matrix-free. */
  /**
   * keep ['volume', 'centroid']: the centre of mass too (matrix-free). surface: 'mesh' (the bilinear
   * patches' volume); 'limit' is refused (the limit surface is Loop's, for triangle meshes).
   */
  createEditor(options?: { level?: number; path?: 'auto' | 'polynomial' | 'tensor' | 'matrix-free'; theta?: Theta;
                           keep?: KeptQuantity[] | string; surface?: 'mesh' }): QuadVolumeEditor;
  delete(): void;
}

/** Volume-preserving editing of a quad mesh's level-e cage (bilinear volume; boundary fixed). */
export interface QuadVolumeEditor {
  readonly level: number;
  readonly cageSize: number;
  readonly deleted: boolean;
  cageVertices(): Uint32Array;
  cageIndexOf(vertex: number): number;
  cagePositions(): Float64Array;
  positions(): Float64Array;
  volume(): number;
  referenceVolume(): number;
  setReferenceVolume(volume: number): void;
  coefficients(): Float64Array;
  /** The volume gradient's path; while the centre of mass is kept a step runs matrix-free (its report's path). */
  path(): 'tensor' | 'polynomial' | 'matrix-free';
  useTheta(theta: Theta): void;
  /** The cage polynomial built from the fine quads; returns the path in use ('matrix-free' on a cage too fine for it). */
  usePolynomial(): 'polynomial' | 'matrix-free';
  useMatrixFree(): void;
  /** As VolumeEditor.setFreeSet: cage 'minus-held' (default), 'all' or caller vertex indices; free detail levels run matrix-free. */
  setFreeSet(options?: { cage?: 'minus-held' | 'all' | ArrayLike<number>; detailLevels?: number[] }): void;
  /** Theta_tau: 'matrix-free' (3N, hierarchy order) or 'tensor' / 'polynomial' (the cage). */
  gradient(path?: 'matrix-free' | 'tensor' | 'polynomial'): Float64Array;
  /** VolumeEditor's surface: quads keep the bilinear patches' volume, one global constraint. */
  surface(): 'mesh';
  keepsCentroid(): boolean;
  /** Keeps the bilinear patches' centre of mass where it is now (with the volume; matrix-free), or stops keeping it. */
  keepCentroid(keep?: boolean): void;
  /** The solid's centre of mass now, and the one kept (the current one when none is), [x, y, z]. */
  centroid(): Float64Array;
  referenceCentroid(): Float64Array;
  partVolumes(): Float64Array;
  /** Throws unless parts is empty: not available for quad meshes yet. */
  setParts(parts: ArrayLike<number>[], references?: ArrayLike<number>): void;
  deformCage(target: Float64Array, held: ArrayLike<number>, options?: EditOptions): EditReport;
  moveVertices(moves: VertexMove[], options?: EditOptions): EditReport;
  correct(held?: ArrayLike<number>, options?: EditOptions): EditReport;
  delete(): void;
}

/** MultiresMesh.hierarchyArrays(): the hierarchy of a mesh, hierarchy indices (kNone = 0xffffffff). */
export interface HierarchyArrays {
  levels: number;
  vertexCount: Uint32Array;
  coarseFaces: Uint32Array;
  ends: Uint32Array;
  wings: Uint32Array;
  boundary: Uint8Array;
  inputIndex: Uint32Array;
  topology: { edges: number; boundaryEdges: number; components: number; closed: boolean; genus: number };
}

/** Mrvol.transferable(): a module's memory with a mesh and editor in it. */
export interface TransferredEditor {
  /** The memory in use (null with memory: false). */
  memory: Uint8Array | null;
  /** How many bytes of the memory are in use (memory's length). */
  memoryBytes: number;
  mesh: number;
  editor: number;
  positions: Float64Array;
  /** The mesh's info() for these positions (the adopting instance skips a pass over the mesh). */
  info?: MeshInfo;
  level: number;
  scheme: { scheme: string; alpha: number; beta: number };
}
