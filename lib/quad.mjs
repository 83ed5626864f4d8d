// The quad-mesh part of the public API (Catmull-Clark multiresolution, docs/catmull-clark.md):
// typed arrays in and out, errors as MrvolError. A quad mesh is { positions: Float64Array,
// quads: Uint32Array (4 per face, counter-clockwise) }. wrapModule (lib/api.mjs) mixes these
// calls into its API and sends openMesh / subdivide with scheme 'catmull-clark' here.
import { applyQuadSteps } from './quad-steps.mjs';
import { cageTargetOf, checkCageTarget, freeSetArgs, keepListOf } from './editor-args.mjs';

function checkQuadMesh(mesh, MrvolError) {
  if (!mesh || typeof mesh !== 'object') throw new MrvolError('expected a quad mesh { positions, quads }');
  if (!(mesh.positions instanceof Float64Array)) throw new MrvolError('mesh.positions must be a Float64Array');
  if (!(mesh.quads instanceof Uint32Array))
    throw new MrvolError(`mesh.quads must be a Uint32Array (4 indices per quad)${mesh.faces && !mesh.quads ? ': this mesh has triangles (faces); readObjQuads reads an OBJ file\'s quads' : ''}`);
  return mesh;
}

// surface: the quad calls take the triangle calls' option and keep the one volume they have (the
// bilinear patches'): 'mesh'; 'limit' is refused by name rather than ignored.
function quadSurfaceArg(surface, MrvolError) {
  if (surface === undefined || surface === 'mesh') return 'mesh';
  if (surface === 'limit')
    throw new MrvolError("surface 'limit' is the Loop limit surface of triangle meshes; a quad mesh keeps the volume of its bilinear patches (surface 'mesh')");
  throw new MrvolError(`surface must be 'mesh' or 'limit', got ${JSON.stringify(surface)}`);
}

/**
 * The gradient path a quad editor uses under 'auto' (a path asked for is taken as is): the cage
 * polynomial built from the fine quads when the cage is at least QUAD_COARSE_CAGE_LEVELS levels
 * below the mesh, else the matrix-free pass over the fine quads (bench/RESULTS-quad.md: a drag step
 * on the polynomial is faster from there on).
 */
export function quadGradientPath(mr, { level = 0, path = 'auto' } = {}) {
  if (path !== 'auto') return path;
  return mr.levels - level >= QUAD_COARSE_CAGE_LEVELS ? 'polynomial' : 'matrix-free';
}
const QUAD_COARSE_CAGE_LEVELS = 3;

/**
 * @param {object} module the instantiated emscripten module
 * @param {{ MrvolError, Theta, levelArg }} shared what lib/api.mjs shares (its error and Theta classes)
 */
export function wrapQuad(module, { MrvolError, Theta, levelArg }) {
  const call = (fn, ...args) => {
    const result = fn(...args);
    const error = module._takeQuadError();
    if (error) throw new MrvolError(error);
    return result;
  };

  /** A volume-preserving editing session on the level-e cage of a quad mesh (bilinear volume). */
  class QuadVolumeEditor {
    #raw;
    #mesh;
    constructor(raw, mesh) {
      this.#raw = raw;
      this.#mesh = mesh;
      this.level = raw.level();
      this.cageSize = raw.cageSize();
    }
    #live() {
      if (!this.#raw) throw new MrvolError('this QuadVolumeEditor has been deleted');
      return this.#raw;
    }
    cageVertices() { return call((r) => r.cageVertices(), this.#live()); }
    cageIndexOf(vertex) {
      if (!Number.isInteger(vertex)) throw new MrvolError('vertex index must be a non-negative integer');
      return call((r) => r.cageIndexOf(vertex), this.#live());
    }
    cagePositions() { return call((r) => r.cagePositions(), this.#live()); }
    positions() { return call((r) => r.positions(), this.#live()); }
    volume() { return call((r) => r.volume(), this.#live()); }
    referenceVolume() { return call((r) => r.referenceVolume(), this.#live()); }
    setReferenceVolume(volume) { call((r) => r.setReferenceVolume(volume), this.#live()); }
    /** Level-e coefficients, hierarchy order (3 per vertex). */
    coefficients() { return call((r) => r.coefficients(), this.#live()); }
    /** 'tensor', 'polynomial' or 'matrix-free'. */
    path() { return call((r) => r.path(), this.#live()); }
    useTheta(theta) {
      if (!(theta instanceof Theta)) throw new MrvolError('useTheta expects a Theta');
      call((r) => r.useTheta(this.#mesh, theta.raw), this.#live());
    }
    /**
     * The cage polynomial built from the fine quads (no theta; rebuilt when free details moved).
     * Returns the path in use: 'polynomial', or 'matrix-free' on a cage too fine for it.
     */
    usePolynomial() {
      call((r) => r.usePolynomial(), this.#live());
      return this.path();
    }
    useMatrixFree() { call((r) => r.useMatrixFree(), this.#live()); }
    /**
     * Free set: cage 'minus-held' (default), 'all', or a list of caller vertex indices; plus the
     * details of chosen levels (matrix-free path), as VolumeEditor.setFreeSet.
     */
    setFreeSet(options = {}) {
      const args = freeSetArgs(this, options, { MrvolError, levelArg });
      call((r) => r.setFreeSet(...args), this.#live());
    }
    /** Theta_tau for the coefficients: 'matrix-free' (all, 3N hierarchy order) or 'tensor'/'polynomial' (cage). */
    gradient(path = 'matrix-free') { return call((r) => r.gradient(path), this.#live()); }
    // VolumeEditor's surface and parts, for callers that take either editor: quads keep the bilinear
    // patches' volume as one global constraint (no limit surface or parts yet), and optionally
    // their centre of mass.
    /** 'mesh': the bilinear patches' volume is kept. */
    surface() { return 'mesh'; }
    /** Keeps the bilinear patches' centre of mass (its current place) with the volume, or stops keeping it. */
    keepCentroid(keep = true) { call((r) => r.keepCentroid(Boolean(keep)), this.#live()); }
    keepsCentroid() { return call((r) => r.keepsCentroid(), this.#live()); }
    /** The solid's centre of mass now, [x, y, z] (Float64Array). */
    centroid() { return call((r) => r.centroid(), this.#live()); }
    /** The centre of mass kept (the current one when it is not kept). */
    referenceCentroid() { return call((r) => r.referenceCentroid(), this.#live()); }
    partVolumes() { return new Float64Array(0); }
    setParts(parts) {
      if (parts?.length) throw new MrvolError('localized preservation (parts) is not available for quad meshes yet');
    }
    deformCage(target, held, options = {}) {
      checkCageTarget(target, MrvolError);
      return call((r) => r.deformCage(target, Uint8Array.from(held), options), this.#live());
    }
    /** moves = [{ vertex, position } | { vertex, offset }] (caller indices); those vertices are held. */
    moveVertices(moves, options = {}) {
      const { target, held } = cageTargetOf(this, moves, MrvolError);
      return this.deformCage(target, held, options);
    }
    correct(held = new Uint8Array(this.cageSize), options = {}) {
      return call((r) => r.correct(Uint8Array.from(held), options), this.#live());
    }
    delete() {
      if (this.#raw) this.#raw.delete();
      this.#raw = null;
    }
    get deleted() { return !this.#raw; }
  }

  /** A semi-regular quad mesh with its Catmull-Clark hierarchy; positions live here. */
  class QuadMultiresMesh {
    #raw;
    #positions;
    constructor(raw, positions) {
      this.#raw = raw;
      this.#positions = positions;
      this.scheme = 'catmull-clark';
      this.levels = raw.levels();
      this.lowestLevel = raw.lowestLevel();
      const info = call((r) => r.info(positions), raw);
      this.vertexCount = info.vertices;
      this.faceCount = info.faces;
      this.baseVertexIndices = info.baseVertexIndices;
    }
    #live() {
      if (!this.#raw) throw new MrvolError('this QuadMultiresMesh has been deleted');
      return this.#raw;
    }
    /** Counts, levels (and lowestLevel analysis reaches), base vertices, topology, bilinear volume. */
    info(options = {}) {
      quadSurfaceArg(options.surface, MrvolError);
      return call((r) => r.info(this.#positions), this.#live());
    }
    positions() {
      this.#live();
      return this.#positions.slice();
    }
    quads() { return call((r) => r.quads(), this.#live()); }
    levelQuads(level) { return call((r) => r.levelQuads(levelArg(level)), this.#live()); }
    depths() { return call((r) => r.depths(), this.#live()); }
    toMesh() { return { positions: this.positions(), quads: this.quads() }; }
    setPositions(positions) {
      if (!(positions instanceof Float64Array)) throw new MrvolError('positions must be a Float64Array');
      if (positions.length !== 3 * this.vertexCount)
        throw new MrvolError(`expected ${3 * this.vertexCount} coordinates (3 per vertex), got ${positions.length}`);
      this.#positions = positions.slice();
    }
    analyze(positions, options = {}) {
      return call((r) => r.analyze(positions ?? this.#positions, levelArg(options.level)), this.#live());
    }
    synthesize(coefficients, options = {}) {
      return call((r) => r.synthesize(coefficients, levelArg(options.level)), this.#live());
    }
    roundtripError(options = {}) {
      return call((r) => r.roundtripError(this.#positions, levelArg(options.level)), this.#live());
    }
    /**
     * Level l's synthesis steps (l = 1..n) in order, caller's vertex indices: [{ name: 'P_f' | 'P_e' |
     * 'N_3k' | 'P_3k' | 'N_v' | 'P_v', scaling, readsOnlyDetails, targets, offsets, sources, weights }]
     * (a lift: x_t += sum w x_s over sources[offsets[r]..offsets[r+1]); a scaling: x_t *= weights[r]).
     */
    liftingSteps(options = {}) {
      if (options.level === undefined) throw new MrvolError('level is required: level l (1..n) builds M^l from M^(l-1)');
      return call((r) => r.liftingSteps(levelArg(options.level)), this.#live());
    }
    /**
     * The first `steps` lifting steps of level l (all by default) on level-(l-1) coefficients; the
     * teaching views' phase-by-phase synthesis (lib/quad-steps.mjs, in JS over liftingSteps).
     */
    synthesizeSteps(coefficients, options = {}) { return this.#steps('synthesize', coefficients, options); }
    /** Undoes the last `steps` lifting steps of level l (all by default), in reverse order. */
    analyzeSteps(coefficients, options = {}) { return this.#steps('analyze', coefficients, options); }
    /** The transposes of the last `steps` steps of level l, in reverse order, on a covector. */
    transposeSteps(covector, options = {}) { return this.#steps('transpose', covector, options); }
    #stepCache = new Map(); // level -> its lifting steps
    #steps(direction, x, options) {
      if (!(x instanceof Float64Array)) throw new MrvolError('coefficients must be a Float64Array');
      if (x.length !== 3 * this.vertexCount) throw new MrvolError(`expected ${3 * this.vertexCount} coefficients (3 per vertex), got ${x.length}`);
      const level = levelArg(options.level);
      if (!this.#stepCache.has(level)) this.#stepCache.set(level, this.liftingSteps({ level }));
      const steps = this.#stepCache.get(level);
      return applyQuadSteps(steps, x, direction, options.steps === undefined ? steps.length : levelArg(options.steps, 'steps'));
    }
    /**
     * The level-l approximation of `positions`: analysis at level l, the details of the vertices
     * born after level l set to zero, synthesis (as MultiresMesh.approximation).
     */
    approximation(positions, options = {}) {
      const level = levelArg(options.level);
      if (level < 0 || level > this.levels) throw new MrvolError(`level ${level} is outside 0..${this.levels}`);
      const coefficients = this.analyze(positions, { level });
      this.#depths ??= this.depths();
      for (let i = 0; i < this.#depths.length; i++)
        if (this.#depths[i] > level) coefficients.fill(0, 3 * i, 3 * i + 3);
      return this.synthesize(coefficients, { level });
    }
    #depths = null;
    /** theta^e of the bilinear volume: { level, storage: 'cage' | 'full' }. */
    computeTheta(options = {}) {
      quadSurfaceArg(options.surface, MrvolError);
      const started = performance.now();
      const raw = call((r) => r.computeTheta(levelArg(options.level), options.storage ?? 'cage'), this.#live());
      return new Theta(raw, Math.round((performance.now() - started) * 1000) / 1000);
    }
    thetaVolume(theta, options = {}) {
      if (!(theta instanceof Theta)) throw new MrvolError('thetaVolume expects a Theta');
      return call((r) => r.thetaVolume(theta.raw, levelArg(options.level ?? theta.info().level), this.#positions), this.#live());
    }
    fingerprint() { return call((r) => r.fingerprint(), this.#live()); }
    /**
     * { level, path: 'auto' (default) | 'polynomial' | 'tensor' | 'matrix-free', theta, keep,
     * surface } as MultiresMesh.createEditor: a theta is used as given; 'tensor' computes theta^e;
     * 'auto' builds the cage polynomial when the cage is coarse against the mesh (quadGradientPath);
     * keep ['volume', 'centroid'] keeps the centre of mass too (matrix-free); surface 'mesh' only.
     */
    createEditor(options = {}) {
      const path = options.path ?? 'auto';
      if (!['auto', 'polynomial', 'tensor', 'matrix-free'].includes(path))
        throw new MrvolError(`gradient path must be auto, polynomial, tensor or matrix-free, got '${path}'`);
      quadSurfaceArg(options.surface, MrvolError);
      const centroid = keepListOf(options.keep, MrvolError).includes('centroid');
      if (centroid && path === 'polynomial')
        throw new MrvolError("the polynomial path sums the quads for the volume alone: with the centroid kept use 'auto' or 'matrix-free'");
      const raw = call((r) => r.createEditor(levelArg(options.level), this.#positions), this.#live());
      const editor = new QuadVolumeEditor(raw, this.#live());
      try {
        if (centroid) editor.keepCentroid(true);
        if (options.theta) editor.useTheta(options.theta);
        else if (centroid) editor.useMatrixFree();
        else if (path === 'tensor') {
          const theta = this.computeTheta({ level: editor.level });
          try {
            editor.useTheta(theta);
          } finally {
            theta.delete();
          }
        } else if (quadGradientPath(this, { level: editor.level, path }) === 'polynomial') editor.usePolynomial();
      } catch (e) {
        editor.delete();
        throw e;
      }
      return editor;
    }
    delete() {
      if (this.#raw) this.#raw.delete();
      this.#raw = null;
    }
  }

  const objBytes = (input, what) => {
    if (input instanceof Uint8Array) return input;
    if (typeof input === 'string') return new TextEncoder().encode(input);
    throw new MrvolError(`${what} expects the OBJ file as a Uint8Array or a string`);
  };

  return {
    /** OBJ text (Uint8Array or string) to { positions, quads }: every face must be a quad. */
    readObjQuads(input) { return call(module._readObjQuads, objBytes(input, 'readObjQuads')); },
    /** { positions, quads } to OBJ text with `f a b c d` lines. */
    writeObjQuads(mesh) {
      checkQuadMesh(mesh, MrvolError);
      return new TextDecoder().decode(call(module._writeObjQuads, mesh.positions, mesh.quads));
    },
    /** The volume enclosed by the bilinear patches of a valid quad mesh. */
    quadVolume(mesh) {
      checkQuadMesh(mesh, MrvolError);
      return call(module._quadVolume, mesh.positions, mesh.quads);
    },
    /** Validates a quad mesh and recovers its Catmull-Clark splits (any vertex order). */
    openQuadMesh(mesh, options = {}) {
      checkQuadMesh(mesh, MrvolError);
      const maxLevels = levelArg(options.maxLevels ?? 16, 'maxLevels');
      return new QuadMultiresMesh(call(module._openQuadMesh, mesh.positions, mesh.quads, maxLevels), mesh.positions.slice());
    },
    /** n levels of Catmull-Clark subdivision of a base quad mesh. */
    subdivideQuads(base, options = {}) {
      checkQuadMesh(base, MrvolError);
      const levels = levelArg(options.levels ?? 1, 'levels');
      const raw = call(module._subdivideQuads, base.positions, base.quads, levels);
      try {
        return new QuadMultiresMesh(raw, call((r) => r.subdivisionPositions(base.positions), raw));
      } catch (e) {
        raw.delete();
        throw e;
      }
    },
  };
}
