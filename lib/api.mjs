// The public JS API over the raw embind module: typed arrays in and out, errors as MrvolError.
// Environment-agnostic: lib/node.mjs and the web app each load the module their own way and wrap
// it here.
import { wrapQuad } from './quad.mjs';
import { cageTargetOf, checkCageTarget, freeSetArgs, keepListOf } from './editor-args.mjs';
import { createClosestPoints } from './closest-points.mjs';

/** An error reported by mrvol's core, with its message as the core wrote it. */
export class MrvolError extends Error {
  constructor(message) {
    super(message);
    this.name = 'MrvolError';
  }
}

/** The default scheme and its Loop weights alpha, beta (the paper's); part of a theta file's key. */
export const DEFAULT_SCHEME = Object.freeze({ scheme: 'loop', alpha: -1.70943, beta: 0.42954 });

/**
 * The gradient path an editor uses, one rule for the CLI and the web editor: a path asked for is
 * taken as is. Under 'auto': 'matrix-free' when details are free; else, with thetaInBackground (a
 * caller that computes theta^e off the editing thread, like the web app's worker), 'tensor' when
 * theta^e's estimate fits (memory and time); else 'polynomial' (the cage polynomial built from the
 * fine mesh: the tensor path's steps without computing theta^e) when the cage is coarse against the
 * mesh (at least 3 levels of details, N >= ~64 cage vertices' worth), 'matrix-free' otherwise: at
 * e = n - 2 and finer a step over the fine mesh is faster than one over the polynomial's cage
 * triples (bench/RESULTS.md, solver-step). Returns { path, estimate (null unless consulted) }.
 */
export function chooseGradientPath(mr, { level = 0, path = 'auto', detailLevels = [], thetaInBackground = false, ...scheme } = {}) {
  if (GRADIENT_PATHS.includes(path)) return { path, estimate: null };
  if (path !== 'auto') throw new MrvolError(`gradient path must be auto, polynomial, tensor or matrix-free, got '${path}'`);
  if (detailLevels.length > 0) return { path: 'matrix-free', estimate: null };
  const coarse = mr.levels - level >= COARSE_CAGE_LEVELS ? 'polynomial' : 'matrix-free';
  if (!thetaInBackground) return { path: coarse, estimate: null };
  const estimate = mr.estimateTheta({ level, ...scheme });
  return { path: estimate.fits ? 'tensor' : coarse, estimate };
}
const GRADIENT_PATHS = ['polynomial', 'tensor', 'matrix-free'];
// subdivide(): results past this many faces are refused before any work (beyond 4 GB for certain).
const MAX_SUBDIVIDED_FACES = 2 ** 25;
// Levels of details from which the cage polynomial beats a pass over the fine mesh.
const COARSE_CAGE_LEVELS = 3;

function schemeArgs(options = {}) {
  const scheme = options.scheme ?? DEFAULT_SCHEME.scheme;
  const alpha = options.alpha ?? DEFAULT_SCHEME.alpha;
  const beta = options.beta ?? DEFAULT_SCHEME.beta;
  if (typeof scheme !== 'string') throw new MrvolError('scheme must be a string (loop, butterfly or linear)');
  if (!Number.isFinite(alpha) || !Number.isFinite(beta)) throw new MrvolError('alpha and beta must be finite numbers');
  return { scheme, alpha, beta };
}

function levelArg(level, name = 'level') {
  const l = level ?? 0;
  if (!Number.isInteger(l)) throw new MrvolError(`${name} must be an integer, got ${level}`);
  // embind would wrap values beyond 32 bits silently; in range, the core says what fits the mesh.
  if (l < -0x80000000 || l > 0x7fffffff) throw new MrvolError(`${name} ${l} is out of range`);
  return l;
}

// Which surface's volume: the mesh's triangles, or the Loop limit surface of the mesh.
function surfaceArg(surface) {
  const s = surface ?? 'mesh';
  if (s !== 'mesh' && s !== 'limit') throw new MrvolError(`surface must be 'mesh' or 'limit', got ${JSON.stringify(surface)}`);
  return s;
}

// The Loop limit surface's volume form takes about this many bytes per triangle at its peak (the
// 163,842-vertex sphere: 1.1 GB); a form past LIMIT_FORM_MAX_BYTES is refused before it is made
// (at 655k vertices it ran 40 s into the 4 GB a WebAssembly module can address, then out of memory).
const LIMIT_FORM_BYTES_PER_TRIANGLE = 3400, LIMIT_FORM_MAX_BYTES = 2.5e9;
function checkLimitFormSize(triangles) {
  const bytes = LIMIT_FORM_BYTES_PER_TRIANGLE * triangles;
  if (bytes > LIMIT_FORM_MAX_BYTES)
    throw new MrvolError(`the limit surface's volume of ${triangles} triangles needs about ${(bytes / 1e9).toFixed(1)} GB ` +
                         `(about ${LIMIT_FORM_BYTES_PER_TRIANGLE} bytes a triangle), more than a WebAssembly module can give it ` +
                         `(up to ${Math.floor(LIMIT_FORM_MAX_BYTES / LIMIT_FORM_BYTES_PER_TRIANGLE)} triangles): keep the mesh's volume, or edit a coarser level of the model`);
}

// What an editor keeps (editor-args.mjs: the quad editor takes the same).
const keepArg = (keep) => keepListOf(keep, MrvolError);

// Lifting steps belong to a level l >= 1, which has no default.
function stepLevelArg(level) {
  if (level === undefined) throw new MrvolError('level is required: level l (1..n) builds M^l from M^(l-1)');
  return levelArg(level);
}

function checkMesh(mesh) {
  if (!mesh || typeof mesh !== 'object') throw new MrvolError('expected a mesh { positions, faces }');
  if (!(mesh.positions instanceof Float64Array)) throw new MrvolError('mesh.positions must be a Float64Array');
  if (!(mesh.faces instanceof Uint32Array))
    throw new MrvolError(`mesh.faces must be a Uint32Array${mesh.quads && !mesh.faces ? ': this is a quad mesh { positions, quads } (quadVolume gives its volume, openMesh opens it)' : ''}`);
  return mesh;
}

// The OBJ lines readObj attached, when they still describe these arrays (else undefined).
function linesOf(mesh) {
  const l = mesh.lines;
  if (!l || !(l.vertex instanceof Uint32Array) || !(l.face instanceof Uint32Array)) return undefined;
  return l.vertex.length * 3 === mesh.positions.length && l.face.length * 3 === mesh.faces.length ? l : undefined;
}

// OBJ input as bytes: a Uint8Array as it is, a string encoded as UTF-8 (one fast native copy).
// OBJ bytes beyond this go into the WASM heap in chunks of this size (ObjReader), not at once.
const OBJ_CHUNK_BYTES = 16 << 20;

function objBytes(input, what) {
  if (input instanceof Uint8Array) return input;
  if (typeof input === 'string') return new TextEncoder().encode(input);
  throw new MrvolError(`${what} expects the OBJ file as a Uint8Array or a string`);
}

/**
 * Wraps an instantiated emscripten module.
 * @param {object} module the result of createMrvolModule()
 */
export function wrapModule(module) {
  // Every raw call returns undefined/null on failure and leaves its message behind.
  const call = (fn, ...args) => {
    const result = fn(...args);
    const error = module._takeError();
    if (error) throw new MrvolError(error);
    return result;
  };

  /**
   * An OBJ file read in chunks as they arrive (a file read piece by piece, a stream): push(bytes)
   * each chunk (a Uint8Array, split anywhere), then finish() gives what readObj gives for the whole
   * file. Errors (MrvolError, with the line) come from the push that completes the bad line or
   * from finish; the reader is then spent. `size`: the file's size when known. cancel() frees a
   * reader that will not be finished. The app reads a File with file.slice(at, at + 16 MB)
   * .arrayBuffer() and pushes each piece, so that neither it nor the heap holds the whole text.
   */
  function createObjReader({ size = 0 } = {}) {
    let raw = module._createObjReader(Number(size) > 0 ? Number(size) : 0);
    const check = () => {
      const error = module._takeObjReaderError();
      if (!error) return;
      raw?.delete();
      raw = null;
      throw new MrvolError(error);
    };
    check();
    const live = () => {
      if (!raw) throw new MrvolError('this OBJ reader has finished (or failed); make a new one');
      return raw;
    };
    return {
      push(chunk) {
        if (!(chunk instanceof Uint8Array)) throw new MrvolError('an OBJ chunk must be a Uint8Array');
        const r = live();
        const address = r.buffer(chunk.length);
        check();
        module.HEAPU8.set(chunk, address);  // the heap's view after buffer() (it may have grown)
        r.feed(chunk.length);
        check();
      },
      finish() {
        const mesh = live().finish();
        check();
        raw.delete();
        raw = null;
        return mesh;
      },
      cancel() {
        raw?.delete();
        raw = null;
      },
      get bytesRead() {
        return raw ? raw.bytesRead() : 0;
      },
    };
  }

  /** A volume tensor theta^e with the header that says what it was computed for. */
  class Theta {
    #raw;
    constructor(raw, precomputeMs = null) {
      this.#raw = raw;
      this.precomputeMs = precomputeMs;
    }
    get raw() {
      if (!this.#raw) throw new MrvolError('this Theta has been deleted');
      return this.#raw;
    }
    /** { formatVersion, scheme, alpha, beta, levels, level, storage, fingerprint, vertices, nnzFull, nnzStored, bytes } */
    info() { return call((r) => r.info(), this.raw); }
    /** The theta file: versioned header, arrays, checksum. */
    bytes() { return call((r) => r.bytes(), this.raw); }
    /**
     * The stored entries, one per i < j < k, in storage order: { i, j, k: Uint32Array, values:
     * Float64Array }. Indices are in hierarchy order (by depth; MultiresMesh.hierarchyOrder() maps
     * them to the caller's vertices).
     */
    entries() { return call((r) => r.entries(), this.raw); }
    delete() {
      if (this.#raw) this.#raw.delete();
      this.#raw = null;
    }
  }


  /**
   * A volume-preserving editing session on the level-e cage. Vertex indices are the caller's;
   * cage arrays (positions, flags) are in cage order, given by cageVertices().
   */
  class VolumeEditor {
    #raw;
    #mesh;
    #scheme;
    constructor(raw, mesh, scheme) {
      this.#raw = raw;
      this.#mesh = mesh;
      this.#scheme = scheme;
      this.level = raw.level();
      this.cageSize = raw.cageSize();
    }
    #live() {
      if (!this.#raw) throw new MrvolError('this VolumeEditor has been deleted');
      return this.#raw;
    }
    _raw() { return this.#live(); }
    /** Caller's vertex index of each cage vertex, in cage order. */
    cageVertices() { return call((r) => r.cageVertices(), this.#live()); }
    /** Cage order index of a caller's vertex; throws if it is not a level-e cage vertex. */
    cageIndexOf(vertex) {
      const known = this.#cageIndex.get(vertex); // a drag asks for the same vertex every step
      if (known !== undefined) return this.#live(), known;
      if (!Number.isInteger(vertex)) throw new MrvolError('vertex index must be a non-negative integer');
      const index = call((r) => r.cageIndexOf(vertex), this.#live());
      this.#cageIndex.set(vertex, index);
      return index;
    }
    #cageIndex = new Map();
    cagePositions() { return call((r) => r.cagePositions(), this.#live()); }
    // The cage coefficients in place (WASM memory; the view made again after the memory grew).
    #cageView = null;
    #dragTarget = null;
    /** cagePositions() into a buffer kept for drags (moveVertices): no call into WASM, no allocation. */
    _dragTarget() {
      const raw = this.#live();
      const buffer = module.HEAPU8.buffer;
      if (this.#cageView?.buffer !== buffer)
        this.#cageView = new Float64Array(buffer, call((r) => r.cageAddress(), raw), 3 * this.cageSize);
      this.#dragTarget ??= new Float64Array(3 * this.cageSize);
      this.#dragTarget.set(this.#cageView);
      return this.#dragTarget;
    }
    /** Fine positions, caller's vertex order. */
    positions() { return call((r) => r.positions(), this.#live()); }
    coefficients() { return call((r) => r.coefficients(), this.#live()); }
    volume() { return call((r) => r.volume(), this.#live()); }
    referenceVolume() { return call((r) => r.referenceVolume(), this.#live()); }
    setReferenceVolume(volume) { call((r) => r.setReferenceVolume(volume), this.#live()); }
    /** 'tensor', 'polynomial' or 'matrix-free'. */
    path() { return call((r) => r.path(), this.#live()); }
    /** Uses theta^e (cage storage, this mesh, scheme and level) for the gradients. */
    useTheta(theta) {
      if (!(theta instanceof Theta)) throw new MrvolError('useTheta expects a Theta');
      call((r) => r.useTheta(this.#mesh, theta.raw, this.#scheme), this.#live());
    }
    /**
     * The cage polynomial built from the fine mesh (no theta; rebuilt when free details moved).
     * Returns the path in use: 'polynomial', or 'matrix-free' on a cage too fine for it.
     */
    usePolynomial() {
      // an adopted editor (adoptTransferred) comes with the polynomial built where it was made
      if (!(this.adopted && this.path() === 'polynomial')) call((r) => r.usePolynomial(), this.#live());
      this.adopted = false;
      return this.path();
    }
    useMatrixFree() { call((r) => r.useMatrixFree(), this.#live()); }
    /**
     * Free set: cage 'minus-held' (default), 'all', or a list of caller vertex indices; plus the
     * details of chosen levels (matrix-free path).
     */
    setFreeSet(options = {}) {
      const args = freeSetArgs(this, options, { MrvolError, levelArg });
      call((r) => r.setFreeSet(...args), this.#live());
    }
    /** Localized preservation: parts as lists of caller cage-vertex indices, optional references. */
    setParts(parts, references) {
      const local = parts.map((p) => Uint32Array.from(p, (v) => this.cageIndexOf(v)));
      call((r) => r.setParts(local, references ? Float64Array.from(references) : undefined), this.#live());
    }
    partVolumes() { return call((r) => r.partVolumes(), this.#live()); }
    /** 'mesh' or 'limit': whose volume is kept. */
    surface() { return call((r) => r.limitSurface(), this.#live()) ? 'limit' : 'mesh'; }
    /** Keeps the centre of mass (its current place) with the volume, or stops keeping it. */
    keepCentroid(keep = true) { call((r) => r.keepCentroid(Boolean(keep)), this.#live()); }
    keepsCentroid() { return call((r) => r.keepsCentroid(), this.#live()); }
    /** The mesh solid's centre of mass now, [x, y, z] (Float64Array). */
    centroid() { return call((r) => r.centroid(), this.#live()); }
    /** The centre of mass kept (the current one when it is not kept). */
    referenceCentroid() { return call((r) => r.referenceCentroid(), this.#live()); }
    /**
     * Moves the cage to `target` (Float64Array, 3 per cage vertex, cage order), keeping the `held`
     * cage vertices (Uint8Array flags, cage order) where the target puts them, and restores the volume.
     * options: { tolerance = 1e-5, preserve = true, maxIterations, maxSubsteps }.
     */
    deformCage(target, held, options = {}) {
      checkCageTarget(target, MrvolError);
      return call((r) => r.deformCage(target, held instanceof Uint8Array ? held : Uint8Array.from(held), options), this.#live());
    }
    /**
     * Convenience for drags: moves = [{ vertex, position: [x, y, z] } | { vertex, offset: [dx, dy, dz] }]
     * with caller vertex indices; those vertices are held.
     */
    moveVertices(moves, options = {}) {
      const { target, held } = cageTargetOf(this, moves, MrvolError);
      return this.deformCage(target, held, options);
    }
    /** Restores the volume of the current shape, holding the flagged cage vertices. */
    correct(held = new Uint8Array(this.cageSize), options = {}) {
      return call((r) => r.correct(Uint8Array.from(held), options), this.#live());
    }
    /** Theta_tau for the coefficients: 'matrix-free' (all, 3N hierarchy order) or 'tensor'/'polynomial' (cage). */
    gradient(path = 'matrix-free') { return call((r) => r.gradient(path), this.#live()); }
    // Renderer buffers (float32, caller's order, in WASM memory), made on first use.
    #surface = null;
    #surfaceVersion = 0;
    #updateSurface(normals) {
      const raw = this.#live();
      this.#surface ??= call(module._createSurfaceBuffers, this.#mesh);
      this.#surfaceVersion = call((s) => s.update(raw, normals), this.#surface);
      return this.#surface;
    }
    /**
     * The fine positions after the last edit as a Float32Array (3 per vertex, caller's order) that
     * views WASM memory: no copy; its values are rewritten in place by the next positionsView()
     * after an edit (only what changed is recomputed). The view is invalidated (length 0) when WASM
     * memory grows, which any later call may do: take the view again after each edit (cheap).
     */
    positionsView() { return this.#updateSurface(false).positions(); }
    /**
     * Area-weighted unit vertex normals of the current positions, a Float32Array over WASM memory
     * like positionsView() (same order and validity); computed in WASM when asked for.
     */
    normalsView() { return this.#updateSurface(true).normals(); }
    /** Changes whenever positionsView()'s values do (as of the last positionsView()/normalsView()). */
    get surfaceVersion() { return this.#surfaceVersion; }
    /**
     * The caller's vertices the last rewrite of each view changed, as { positions: { first, count },
     * normals: { first, count } } (a range to upload; the whole mesh after a move of the whole cage,
     * a few hundred vertices after a move of one vertex that needed no correction).
     */
    updatedRanges() {
      this.#live();
      const r = this.#surface ? call((s) => s.ranges(), this.#surface) : { positions: [0, 0], normals: [0, 0] };
      const range = ([first, end]) => ({ first, count: end - first });
      return { positions: range(r.positions), normals: range(r.normals) };
    }
    delete() {
      this.#surface?.delete();
      this.#surface = null;
      if (this.#raw) this.#raw.delete();
      this.#raw = null;
    }
    get deleted() { return !this.#raw; }
  }

  // The raw mesh holds connectivity, hierarchy and transforms; the positions live here and are
  // passed to the calls that need them.
  class MultiresMesh {
    #raw;
    #positions;
    // info: this mesh's info() for these positions when known (an adopted mesh's: a pass less)
    constructor(raw, positions, info = null) {
      this.#raw = raw;
      this.#positions = positions;
      this.levels = raw.levels();
      info ??= call((r) => r.info(positions), raw);
      this.#info = info;
      this.vertexCount = info.vertices;
      this.faceCount = info.faces;
      this.baseVertexIndices = info.baseVertexIndices.slice(); // its own: info() hands out copies of the kept one
    }
    #live() {
      if (!this.#raw) throw new MrvolError('this MultiresMesh has been deleted');
      return this.#raw;
    }
    /**
     * Vertex/face counts, levels, base vertices, closedness, genus, volume. surface: 'mesh'
     * (default) or 'limit' (volume of the Loop limit surface; closed meshes only).
     */
    // The mesh surface's info for the current positions (a pass over a big mesh: kept until they change).
    #info = null;
    info(options = {}) {
      const surface = surfaceArg(options.surface);
      const raw = this.#live();
      this.#info ??= call((r) => r.info(this.#positions), raw);
      const info = { ...this.#info, baseVertexIndices: this.#info.baseVertexIndices.slice() };
      if (surface === 'limit') {
        checkLimitFormSize(this.faceCount);
        info.volume = call((r) => r.limitVolume(this.#positions), this.#live());
      }
      info.surface = surface;
      return info;
    }
    /** Current positions, caller's vertex order. */
    positions() {
      this.#live();
      return this.#positions.slice();
    }
    faces() { return call((r) => r.faces(), this.#live()); }
    /** Triangles of the level-l mesh (the level-l cage), caller's vertex indices. */
    levelFaces(level) { return call((r) => r.levelFaces(levelArg(level)), this.#live()); }
    /** Depth (level of birth) of every vertex, caller's order. */
    depths() { return call((r) => r.depths(), this.#live()); }
    toMesh() { return { positions: this.positions(), faces: this.faces() }; }
    setPositions(positions) {
      if (!(positions instanceof Float64Array)) throw new MrvolError('positions must be a Float64Array');
      call((r) => r.checkPositions(positions), this.#live());
      const same = positions.length === this.#positions.length && positions.every((x, i) => x === this.#positions[i]);
      this.#positions = positions.slice();
      if (same) return;
      this.#info = null;
      this.#dropPrepared(); // made for the positions before
    }
    /** Level-e coefficients (coarse for depth <= e, details beyond), caller's vertex order. */
    analyze(positions, options = {}) {
      if (!(positions instanceof Float64Array)) throw new MrvolError('positions must be a Float64Array');
      return call((r) => r.analyze(positions, levelArg(options.level), schemeArgs(options)), this.#live());
    }
    /** Positions from level-e coefficients. */
    synthesize(coefficients, options = {}) {
      if (!(coefficients instanceof Float64Array)) throw new MrvolError('coefficients must be a Float64Array');
      return call((r) => r.synthesize(coefficients, levelArg(options.level), schemeArgs(options)), this.#live());
    }
    /**
     * The lifting steps of level l (1..n: the synthesis from M^(l-1) to M^l), in the order they
     * apply: [{ name ('U', 'P_o', 'N', 'P_e' for Loop; 'U', 'P' otherwise), scaling, readsOnlyDetails,
     * targets, offsets, sources: Uint32Array, weights: Float64Array }], caller's vertex indices.
     * A lift adds sum of weights[s] * x[sources[s]] for s in offsets[r]..offsets[r+1] to x[targets[r]];
     * a scaling multiplies x[targets[r]] by weights[r].
     */
    liftingSteps(options = {}) {
      return call((r) => r.liftingSteps(stepLevelArg(options.level), schemeArgs(options)), this.#live());
    }
    /**
     * The first `steps` lifting steps of level l (all by default) on level-(l-1) coefficients
     * (caller's order); all of them give the level-l coefficients.
     */
    synthesizeSteps(coefficients, options = {}) {
      return this.#steps('synthesizeSteps', coefficients, options);
    }
    /**
     * Analysis of level l phase by phase: undoes the last `steps` lifting steps (all by default) of
     * level-l coefficients, in reverse order; all of them give the level-(l-1) coefficients.
     */
    analyzeSteps(coefficients, options = {}) {
      return this.#steps('analyzeSteps', coefficients, options);
    }
    /**
     * The adjoint of level l's synthesis phase by phase (paper Figure 5, the masks applied
     * outwards): the transposes of the last `steps` steps (all by default), in reverse order, on a
     * covector of the level-l vertices (caller's order, 3 per vertex).
     */
    transposeSteps(covector, options = {}) {
      return this.#steps('transposeSteps', covector, options, 'covector');
    }
    #steps(name, coefficients, options, what = 'coefficients') {
      if (!(coefficients instanceof Float64Array)) throw new MrvolError(`${what} must be a Float64Array`);
      const level = stepLevelArg(options.level), scheme = schemeArgs(options);
      const steps = options.steps === undefined
        ? call((r) => r.liftingStepCount(level, scheme), this.#live())
        : levelArg(options.steps, 'steps');
      return call((r) => r[name](coefficients, level, steps, scheme), this.#live());
    }
    /**
     * The level-l approximation of `positions` (paper Figure 1): analysis at level l, the details
     * of the vertices born after level l set to zero, synthesis. Same vertices and faces.
     */
    approximation(positions, options = {}) {
      if (!(positions instanceof Float64Array)) throw new MrvolError('positions must be a Float64Array');
      const level = levelArg(options.level);
      if (level < 0 || level > this.levels) throw new MrvolError(`level ${level} is outside 0..${this.levels}`);
      const transform = { ...options, level };
      const coefficients = this.analyze(positions, transform);
      this.#depths ??= this.depths();
      for (let i = 0; i < this.#depths.length; i++)
        if (this.#depths[i] > level) coefficients.fill(0, 3 * i, 3 * i + 3);
      return this.synthesize(coefficients, transform);
    }
    #depths = null;
    _raw() { return this.#live(); }
    /** Caller's vertex index of each hierarchy index (the order of theta entries: by depth). */
    hierarchyOrder() { return call((r) => r.hierarchyOrder(), this.#live()); }
    /** max |synthesis(analysis(x)) - x| over the current positions. */
    roundtripError(options = {}) {
      return call((r) => r.roundtripError(this.#positions, levelArg(options.level), schemeArgs(options)), this.#live());
    }
    /**
     * The hierarchy as flat typed arrays (plus the topology validation found), for
     * openMeshWithHierarchy in another instance of the module: a worker detects, the page opens.
     */
    hierarchyArrays() { return call((r) => r.hierarchyArrays(), this.#live()); }
    /** Connectivity fingerprint (hex): what theta depends on besides scheme and level. */
    fingerprint() { return call((r) => r.fingerprint(), this.#live()); }
    /**
     * What computing theta^e (cage storage) would take, from a few sampled patches, without doing it:
     * { cageSize, maxPatch, entries, bytes, denseBytes, milliseconds, fits }. `fits` is the policy
     * editors follow: the tensor when it fits, the matrix-free gradient otherwise.
     */
    estimateTheta(options = {}) {
      return call((r) => r.estimateTheta(levelArg(options.level), schemeArgs(options)), this.#live());
    }
    /**
     * Computes theta^e. storage 'cage' keeps the rows of the level-e cage vertices (what editing
     * needs); 'full' keeps every entry. onProgress(fraction) may return false to cancel.
     */
    computeTheta(options = {}) {
      const storage = options.storage ?? 'cage';
      if (surfaceArg(options.surface) === 'limit') {  // theta^e of the Loop limit surface's volume
        checkLimitFormSize(this.faceCount);
        const started = globalThis.performance?.now() ?? Date.now();
        const raw = call((r) => r.computeLimitTheta(levelArg(options.level), schemeArgs(options), storage), this.#live());
        return new Theta(raw, (globalThis.performance?.now() ?? Date.now()) - started);
      }
      const onProgress = options.onProgress ?? undefined;
      const started = globalThis.performance?.now() ?? Date.now();
      const raw = call((r) => r.computeTheta(levelArg(options.level), schemeArgs(options), storage, onProgress), this.#live());
      return new Theta(raw, (globalThis.performance?.now() ?? Date.now()) - started);
    }
    /** Volume of the current positions through theta (checks that theta matches mesh, scheme, level). */
    thetaVolume(theta, options = {}) {
      if (!(theta instanceof Theta)) throw new MrvolError('thetaVolume expects a Theta');
      const method = theta.info().surface === 'limit' ? 'limitThetaVolume' : 'thetaVolume';
      return call((r) => r[method](theta.raw, levelArg(options.level), schemeArgs(options), this.#positions), this.#live());
    }
    /**
     * Starts an editing session at level e from the current positions. With options.theta it uses
     * that tensor; else options.path 'auto' (default) or 'polynomial' builds the cage polynomial
     * from the fine mesh (matrix-free on a cage too fine for it), 'matrix-free' skips it.
     * surface 'limit' keeps the Loop limit surface's volume (closed meshes; matrix-free, or the
     * tensor path with a theta computed with surface 'limit'). keep ['volume', 'centroid'] keeps
     * the centre of mass too (mesh surface, matrix-free).
     */
    createEditor(options = {}) {
      const scheme = schemeArgs(options);
      const path = options.path ?? 'auto';
      const surface = surfaceArg(options.surface);
      const prepared = this.#takePrepared(options, scheme, surface);
      if (prepared) return prepared;
      const centroid = keepArg(options.keep).includes('centroid');
      if (!['auto', 'polynomial', 'matrix-free'].includes(path) && !(path === 'tensor' && options.theta))
        throw new MrvolError(`createEditor path must be auto, polynomial or matrix-free (tensor with a theta), got '${path}'`);
      if (path === 'polynomial' && (surface === 'limit' || centroid))
        throw new MrvolError(`the polynomial path sums the mesh's triangles for the volume alone: with ${surface === 'limit' ? "surface 'limit'" : 'the centroid kept'} use 'auto' or 'matrix-free'${surface === 'limit' ? " (or a theta computed with surface 'limit')" : ''}`);
      if (surface === 'limit') checkLimitFormSize(this.faceCount);
      const raw = call((r) => r.createEditor(levelArg(options.level), scheme, this.#positions), this.#live());
      const editor = new VolumeEditor(raw, this.#live(), scheme);
      this.#editors.add(editor);
      try {
        if (surface === 'limit') call((r) => r.useLimitSurface(this.#live()), raw);
        if (centroid) editor.keepCentroid(true);
        if (options.theta) editor.useTheta(options.theta);
        else if (surface === 'limit' || centroid) editor.useMatrixFree();
        else if (path === 'polynomial' || (path === 'auto' &&
                 chooseGradientPath(this, { level: levelArg(options.level), ...scheme }).path === 'polynomial'))
          editor.usePolynomial();
      } catch (e) {
        editor.delete();
        this.#editors.delete(editor);
        throw e;
      }
      return editor;
    }
    #editors = new Set();
    // An editor made elsewhere for these positions (adoptTransferred): the first createEditor at its
    // level, scheme, surface and keep (no theta) returns it as it was made, path included.
    #prepared = null;
    _prepareEditor(raw, { level, ...options }) {
      const editor = new VolumeEditor(raw, this.#live(), schemeArgs(options));
      editor.adopted = true;
      editor.madeElsewhere = true; // stays (adopted goes with the first usePolynomial)
      this.#editors.add(editor);
      this.#prepared = { editor, level, scheme: schemeArgs(options), surface: editor.surface(), centroid: editor.keepsCentroid() };
    }
    #takePrepared(options, scheme, surface) {
      const p = this.#prepared;
      if (!p || options.theta || surface !== p.surface || keepArg(options.keep).includes('centroid') !== p.centroid ||
          levelArg(options.level) !== p.level ||
          scheme.scheme !== p.scheme.scheme || scheme.alpha !== p.scheme.alpha || scheme.beta !== p.scheme.beta) return null;
      this.#prepared = null;
      return p.editor;
    }
    #dropPrepared() {
      if (!this.#prepared) return;
      this.#editors.delete(this.#prepared.editor);
      this.#prepared.editor.delete();
      this.#prepared = null;
    }
    delete() {
      // Editors refer to this mesh's hierarchy: they go first.
      for (const editor of this.#editors) editor.delete();
      this.#editors.clear();
      if (this.#raw) this.#raw.delete();
      this.#raw = null;
    }
  }

  // Mesh files other than OBJ (wasm/bindings/io_bindings.cpp keeps its own error slot).
  // Quad meshes and the catmull-clark scheme (lib/quad.mjs).
  const quad = wrapQuad(module, { MrvolError, Theta, levelArg });
  const isQuad = (mesh, options) => options?.scheme === 'catmull-clark' || mesh?.quads instanceof Uint32Array;

  const callIo = (fn, ...args) => {
    const result = fn(...args);
    const error = module._takeIoError();
    if (error) throw new MrvolError(error);
    return result;
  };
  const toBytes = (bytes, what) => {
    if (bytes instanceof Uint8Array) return bytes;
    if (bytes instanceof ArrayBuffer) return new Uint8Array(bytes);
    throw new MrvolError(`${what} expects the file as a Uint8Array`);
  };

  // adoptTransferred: the memory grown to fit what transferable() gave, then (once it is copied in) the objects.
  // Returns how many bytes the copy brings and how many of this instance's own are in use before it.
  // `memory`: a Uint8Array, or (adoptTransferredInSlices) an async iterable of consecutive slices of
  // `memoryBytes` in all (another instance's copyMemory).
  const reserveForTransfer = ({ memory, memoryBytes, mesh, editor, positions } = {}, { slices = false } = {}) => {
    const whole = memory instanceof Uint8Array;
    const sliced = slices && typeof memory?.[Symbol.asyncIterator] === 'function' && Number.isInteger(memoryBytes) && memoryBytes > 0;
    if (!(whole || sliced) || !(positions instanceof Float64Array) || !Number.isFinite(mesh) || !Number.isFinite(editor))
      throw new MrvolError('adoptTransferred expects what transferable() gave');
    // A threaded instance's memory also holds its threads' state: a copied image would overwrite it.
    if (module._threadCount() > 1)
      throw new MrvolError('adoptTransferred needs a single-thread instance: createMrvol({ threads: 1 })');
    const bytes = whole ? memory.byteLength : memoryBytes;
    const ownInUse = call(module._memoryInUse);
    if (bytes > module.HEAPU8.byteLength) call(module._reserveMemory, bytes);
    if (bytes > module.HEAPU8.byteLength)
      throw new MrvolError(`out of memory: ${Math.round(bytes / 2 ** 20)} MB do not fit this WebAssembly module`);
    return { bytes, ownInUse };
  };
  // What this instance had in use above the copy is cleared: the copy's heap ends below it and
  // takes that memory as never handed out.
  const clearAbove = ({ bytes, ownInUse }) => {
    if (ownInUse > bytes) module.HEAPU8.fill(0, bytes, ownInUse);
  };
  const adoptCopied = ({ mesh, editor, positions, info, level, scheme }) => {
    const known = info && typeof info === 'object' && info.vertices * 3 === positions.length ? info : null;
    const mr = new MultiresMesh(call(module._adoptMesh, mesh), positions, known);
    mr._prepareEditor(call(module._adoptEditor, editor), { level, ...scheme });
    return mr;
  };

  return {
    /** How many threads the core's big loops run on (1: the single-thread module). */
    get threads() {
      return module._threadCount();
    },

    /**
     * Reads a mesh file of any format mrvol knows (OBJ, STL, PLY, OFF, glTF, GLB), told by
     * `format` or else by `name`'s extension and the content. `resources` ({ uri: Uint8Array } or
     * [[uri, bytes]]) gives a .gltf's sidecar files. Returns { positions, faces, format, variant,
     * sourceVertex, sourceVertices, sourceFaces, welded, triangulated } (and `lines` for OBJ).
     */
    readMesh(bytes, { name = '', format = '', resources } = {}) {
      const data = toBytes(bytes, 'readMesh');
      const pairs = resources === undefined ? undefined
        : (resources instanceof Map ? [...resources] : Array.isArray(resources) ? resources : Object.entries(resources))
          .map(([uri, b]) => [String(uri), toBytes(b, 'readMesh resources')]);
      const mesh = callIo(module._readMesh, data, String(name), String(format), pairs);
      // A glTF keeps what writeGlb needs to write it again with its other data: writeGlb(mesh, { source: mesh.source }).
      if (mesh.format === 'gltf' || mesh.format === 'glb')
        Object.defineProperty(mesh, 'source', { value: { bytes: data, format: mesh.format, resources: pairs }, enumerable: false });
      return mesh;
    },
    /** The format ('obj', 'stl', 'ply', 'off', 'gltf', 'glb') of a file from its name and content. */
    detectFormat(bytes, name = '') {
      return callIo(module._detectFormat, toBytes(bytes, 'detectFormat'), String(name));
    },
    /**
     * A GLB file (Uint8Array) of the mesh: float32 positions, vertex normals, uint32 indices. With
     * `source` (a glTF mesh's `source` from readMesh; the triangles unchanged), the source's data
     * is kept: materials, textures, other attributes; POSITION replaced, NORMAL recomputed.
     */
    writeGlb(mesh, { source } = {}) {
      checkMesh(mesh);
      if (source === undefined) return callIo(module._writeGlb, mesh.positions, mesh.faces);
      return callIo(module._writeGlbKeeping, toBytes(source.bytes, 'writeGlb source'), '', String(source.format ?? ''),
                    source.resources, mesh.positions, mesh.faces);
    },
    /** Reads a theta file (Uint8Array); throws MrvolError if truncated, corrupt or of a future version. */
    readTheta(bytes) {
      if (!(bytes instanceof Uint8Array)) throw new MrvolError('readTheta expects a Uint8Array');
      return new Theta(call(module._readTheta, bytes));
    },
    MrvolError,
    ...quad,
    /**
     * Parses an OBJ file (a Uint8Array of its bytes, e.g. a Node Buffer, or a string) into
     * { positions: Float64Array, faces: Uint32Array } (0-based, polygons triangulated; vertices at
     * exactly one position welded into one, `welded` of them, as an exporter's split ones), with
     * lines: { vertex, face } (Uint32Array: the OBJ line of each), which validate, volume and
     * openMesh use to name the line of a vertex or face in their errors; polygons (how many faces
     * had more than 3 corners) and polygonTriangles; and when the file has them texCoords (2 per vt),
     * normals (3 per vn), colors (3 per vertex), cornerTexCoords / cornerNormals (per triangle
     * corner, 0xffffffff where none); dropped: what was left out, in words, when face corners
     * refer to vt or vn lines the file does not have (the mesh is read, those attributes not).
     */
    readObj(input) {
      const bytes = objBytes(input, 'readObj');
      if (bytes.length <= OBJ_CHUNK_BYTES) return call(module._readObj, bytes);
      // A large file goes in in chunks: the heap never holds its whole text.
      const reader = createObjReader({ size: bytes.length });
      for (let at = 0; at < bytes.length; at += OBJ_CHUNK_BYTES) reader.push(bytes.subarray(at, at + OBJ_CHUNK_BYTES));
      return reader.finish();
    },
    createObjReader,
    /**
     * The original OBJ file (Uint8Array or string, as given to readObj) with its vertex positions
     * replaced (Float64Array, 3 per vertex as readObj read them: a welded vertex's position written
     * into each of its v lines; or 3 per v line): every other line and byte kept
     * (vt, vn, faces, groups, materials, comments, colours). Returns the same type as `original`.
     */
    writeObjLike(original, positions) {
      if (!(positions instanceof Float64Array)) throw new MrvolError('positions must be a Float64Array');
      const bytes = call(module._writeObjLike, objBytes(original, 'writeObjLike'), positions);
      return typeof original === 'string' ? new TextDecoder().decode(bytes) : bytes;
    },
    writeObj(mesh) {
      checkMesh(mesh);
      return new TextDecoder().decode(call(module._writeObj, mesh.positions, mesh.faces));
    },
    /**
     * Closest points on the mesh's triangles (a tree built once in the core, or `tree`: one built
     * elsewhere, { bounds, first, count } per node): closest(x, y, z, maxDistance, out),
     * closestMany(points, bounds), sampledDistanceFrom(other), dispose().
     */
    closestPoints(mesh, { tree } = {}) {
      checkMesh(mesh);
      return createClosestPoints(module, mesh, MrvolError, tree);
    },
    /**
     * three-mesh-bvh's tree (0.9.x MeshBVH, default options) built in the core, bit for bit:
     * positions (Float32Array, 3 per vertex) and index (Uint32Array, 3 per triangle) in; { roots:
     * [ArrayBuffer of the packed nodes], index (reordered as the library reorders it) } out, for
     * MeshBVH.deserialize({ ...it, version: 1 }, geometry). The remesher's trees (lib/remesh.mjs).
     */
    threeMeshBvh(positions, index) {
      if (!(positions instanceof Float32Array) || !(index instanceof Uint32Array))
        throw new MrvolError('threeMeshBvh expects positions as a Float32Array and the index as a Uint32Array');
      const built = module._buildBvh(positions, index);
      const error = module._takeClosestPointsError();
      if (error) throw new MrvolError(error);
      return { roots: [built.nodes.buffer], index: built.index };
    },
    /** Checks manifoldness and orientation; returns { edges, boundaryEdges, components, closed, genus }. */
    validate(mesh) {
      checkMesh(mesh);
      return call(module._validate, mesh.positions, mesh.faces, linesOf(mesh));
    },
    /** Signed enclosed volume of a valid mesh; surface 'limit': of its Loop limit surface (closed only). */
    volume(mesh, options = {}) {
      checkMesh(mesh);
      const limit = surfaceArg(options.surface) === 'limit';
      if (limit) checkLimitFormSize(mesh.faces.length / 3);
      const fn = limit ? module._limitVolume : module._volume;
      return call(fn, mesh.positions, mesh.faces, linesOf(mesh));
    },
    /** Validates the mesh and recovers its semi-regular hierarchy (any vertex order). */
    openMesh(mesh, options = {}) {
      if (isQuad(mesh, options)) return quad.openQuadMesh(mesh, options);
      checkMesh(mesh);
      const maxLevels = levelArg(options.maxLevels ?? 16, 'maxLevels');
      return new MultiresMesh(call(module._openMesh, mesh.positions, mesh.faces, maxLevels, linesOf(mesh)), mesh.positions.slice());
    },
    /**
     * Opens a mesh whose hierarchy another instance found (MultiresMesh.hierarchyArrays() of the same
     * faces): no validation or detection again, a few linear passes. Throws MrvolError when the
     * arrays do not fit the mesh.
     */
    openMeshWithHierarchy(mesh, arrays) {
      checkMesh(mesh);
      const typed = { vertexCount: Uint32Array, coarseFaces: Uint32Array, ends: Uint32Array, wings: Uint32Array, boundary: Uint8Array, inputIndex: Uint32Array };
      const t = arrays?.topology;
      if (!arrays || typeof arrays !== 'object' || !Number.isInteger(arrays.levels) || !t || typeof t.closed !== 'boolean' ||
          ['edges', 'boundaryEdges', 'components', 'genus'].some((k) => !Number.isInteger(t[k])) ||
          Object.entries(typed).some(([key, type]) => !(arrays[key] instanceof type)))
        throw new MrvolError('openMeshWithHierarchy expects the arrays of MultiresMesh.hierarchyArrays()');
      if (arrays.inputIndex.length * 3 !== mesh.positions.length)
        throw new MrvolError(`the hierarchy arrays are for ${arrays.inputIndex.length} vertices, the mesh has ${mesh.positions.length / 3}`);
      return new MultiresMesh(call(module._openWithHierarchy, mesh.faces, arrays), mesh.positions.slice());
    },
    /**
     * A mesh and its editor made here, ready to move to another instance of the module (the web
     * app's file worker makes them off the page's thread): a copy of this instance's whole memory
     * (transfer its buffer), where the two are in it, the positions, level and scheme. Both
     * instances must have run the same calls before (web/module-transfer.js warms them alike):
     * embind keeps per-call-site ids in memory that index tables of the JS side.
     */
    transferable(mr, editor, options = {}) {
      // only the part in use (up to the heap's top): what lies above it was never handed out
      const memoryBytes = call(module._memoryInUse);
      return {
        // memory: false: the calls alone, no copy (an instance warming up for a later take-over, or
        // one that hands its memory over a slice at a time: copyMemory)
        memory: options.memory === false ? null : module.HEAPU8.slice(0, memoryBytes), memoryBytes,
        mesh: call(module._meshAddress, mr._raw()), editor: call(module._editorAddress, editor._raw()),
        positions: mr.positions(), info: mr.info(), level: editor.level, scheme: schemeArgs(options),
      };
    },
    /**
     * Takes over what transferable() gave, in an instance made for it (its memory is replaced: any
     * object made in it before is gone). Returns the MultiresMesh; its first createEditor at that
     * level and scheme returns the editor made there.
     */
    adoptTransferred(transfer) {
      const room = reserveForTransfer(transfer);
      module.HEAPU8.set(transfer.memory);
      clearAbove(room);
      return adoptCopied(transfer);
    },
    /**
     * adoptTransferred with the memory copied a slice at a time (`sliceBytes`), awaiting
     * `between(fraction copied)` after each: a page keeps drawing while a big editor's memory (a GB
     * or more) comes in. `transfer.memory` may also be an async iterable of the consecutive slices
     * (Uint8Array; `transfer.memoryBytes` in all: transferable with memory: false, then the other
     * instance's copyMemory, e.g. from a worker through buffers sent back and forth). Nothing else
     * may use this instance until it resolves (to the MultiresMesh).
     */
    async adoptTransferredInSlices(transfer, { sliceBytes = 16 * 2 ** 20, between = () => new Promise((r) => setTimeout(r, 0)) } = {}) {
      const room = reserveForTransfer(transfer, { slices: true });
      const { memory } = transfer;
      if (memory instanceof Uint8Array) {
        for (let at = 0; at < memory.byteLength; at += sliceBytes) {
          module.HEAPU8.set(memory.subarray(at, Math.min(memory.byteLength, at + sliceBytes)), at);
          await between(Math.min(1, (at + sliceBytes) / memory.byteLength));
        }
      } else {
        let at = 0;
        for await (const slice of memory) {
          if (!(slice instanceof Uint8Array) || at + slice.byteLength > room.bytes)
            throw new MrvolError(`adoptTransferredInSlices: the slices overrun the ${room.bytes} bytes the transfer gave`);
          module.HEAPU8.set(slice, at);
          at += slice.byteLength;
          await between(at / room.bytes);
        }
        if (at !== room.bytes) throw new MrvolError(`adoptTransferredInSlices: the slices ended at ${at} of ${room.bytes} bytes`);
      }
      clearAbove(room);
      return adoptCopied(transfer);
    },
    /**
     * Grows this instance's memory to at least `bytes` ahead of a take-over (adoptTransferredInSlices
     * of about that much) and writes once to each 4 KB page above what is in use, `sliceBytes` at a
     * time, awaiting `between(fraction done)` after each: the first write to a page of freshly grown
     * memory costs a page fault, most of a take-over's time (bench/NOTES-transfer.md), paid here
     * while the other instance still works. Stops early once `signal` (an AbortSignal) is aborted.
     * What it writes is zero, as that memory was: this instance keeps working. Resolves to the bytes
     * of memory it reached.
     */
    async growMemoryAhead(bytes, { sliceBytes = 16 * 2 ** 20, between = () => new Promise((r) => setTimeout(r, 0)), signal = null } = {}) {
      if (!Number.isFinite(bytes) || bytes < 0) throw new MrvolError('growMemoryAhead expects a number of bytes');
      if (module._threadCount() > 1) return module.HEAPU8.byteLength; // a threaded instance takes no transfer
      if (bytes > module.HEAPU8.byteLength) call(module._reserveMemory, bytes);
      const end = Math.min(bytes, module.HEAPU8.byteLength);
      const PAGE = 4096;
      const start = Math.ceil(call(module._memoryInUse) / PAGE) * PAGE;
      for (let at = start; at < end && !signal?.aborted;) {
        const heap = module.HEAPU8; // taken again after each await: the memory may have grown meanwhile
        const stop = Math.min(end, at + sliceBytes);
        for (; at < stop; at += PAGE) heap[at] = 0;
        await between((at - start) / (end - start));
      }
      return module.HEAPU8.byteLength;
    },
    /**
     * Copies this instance's memory from byte `offset` into `into` (a Uint8Array; as much as fits,
     * up to the end of the memory) and returns how many bytes it copied: the memory of a
     * transferable({ memory: false }) handed over a slice at a time, through buffers used again (a
     * fresh buffer of hundreds of MB costs a page fault per 4 KB page; bench/NOTES-transfer.md).
     * Nothing may run in this instance between the transferable() and the last slice.
     */
    copyMemory(offset, into) {
      if (!(into instanceof Uint8Array) || !Number.isInteger(offset) || offset < 0)
        throw new MrvolError('copyMemory expects a byte offset and a Uint8Array');
      const end = Math.min(module.HEAPU8.byteLength, offset + into.byteLength);
      if (end <= offset) return 0;
      into.set(module.HEAPU8.subarray(offset, end));
      return end - offset;
    },
    /** n levels of zero-detail synthesis (subdivision) of a base mesh. Returns a MultiresMesh. */
    subdivide(base, options = {}) {
      if (isQuad(base, options)) return quad.subdivideQuads(base, options);
      checkMesh(base);
      const levels = levelArg(options.levels ?? 1, 'levels');
      const scheme = schemeArgs(options);
      // The result, not the input, is what may not fit: named as such, at once where it cannot
      // (4 GB holds about 10 million faces with the hierarchy: 21 million failed after 18 s).
      const made = (base.faces.length / 3) * 4 ** levels;
      const tooMany = () => `${levels} levels on ${(base.faces.length / 3).toLocaleString('en-US')} faces make ` +
        `${made.toLocaleString('en-US')} faces, too many for this WebAssembly module: ask fewer levels`;
      if (levels <= 12 && made > MAX_SUBDIVIDED_FACES) throw new MrvolError(tooMany());  // (past 12: the core's message)
      let raw;
      try {
        raw = call(module._subdivideBase, base.positions, base.faces, levels);
        return new MultiresMesh(raw, call((r) => r.subdivisionPositions(base.positions, scheme), raw));
      } catch (e) {
        raw?.delete();
        if (e instanceof MrvolError && e.message.startsWith('out of memory')) throw new MrvolError(`out of memory: ${tooMany()}`);
        throw e;
      }
    },
  };
}
