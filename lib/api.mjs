// The public JS API over the raw embind module: typed arrays in and out, errors as MrvolError.
// Environment-agnostic: lib/node.mjs and the web app each load the module their own way and wrap
// it here.

/** An error reported by mrvol's core, with its message as the core wrote it. */
export class MrvolError extends Error {
  constructor(message) {
    super(message);
    this.name = 'MrvolError';
  }
}

const DEFAULT_SCHEME = Object.freeze({ scheme: 'loop', alpha: -1.70943, beta: 0.42954 });

function schemeArgs(options = {}) {
  const scheme = options.scheme ?? DEFAULT_SCHEME.scheme;
  const alpha = options.alpha ?? DEFAULT_SCHEME.alpha;
  const beta = options.beta ?? DEFAULT_SCHEME.beta;
  if (typeof scheme !== 'string') throw new MrvolError('scheme must be a string (loop, butterfly or linear)');
  if (!Number.isFinite(alpha) || !Number.isFinite(beta)) throw new MrvolError('alpha and beta must be finite numbers');
  return [scheme, alpha, beta];
}

function levelArg(level) {
  const l = level ?? 0;
  if (!Number.isInteger(l)) throw new MrvolError(`level must be an integer, got ${level}`);
  return l;
}

function checkMesh(mesh) {
  if (!mesh || typeof mesh !== 'object') throw new MrvolError('expected a mesh { positions, faces }');
  if (!(mesh.positions instanceof Float64Array)) throw new MrvolError('mesh.positions must be a Float64Array');
  if (!(mesh.faces instanceof Uint32Array)) throw new MrvolError('mesh.faces must be a Uint32Array');
  return mesh;
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
    delete() {
      if (this.#raw) this.#raw.delete();
      this.#raw = null;
    }
  }

  class MultiresMesh {
    #raw;
    constructor(raw) {
      this.#raw = raw;
      this.levels = raw.levels();
      const info = call((r) => r.info(), raw);
      this.vertexCount = info.vertices;
      this.faceCount = info.faces;
      this.baseVertexIndices = info.baseVertexIndices;
    }
    #live() {
      if (!this.#raw) throw new MrvolError('this MultiresMesh has been deleted');
      return this.#raw;
    }
    /** Vertex/face counts, levels, base vertices, closedness, genus, volume. */
    info() { return call((r) => r.info(), this.#live()); }
    /** Current positions, caller's vertex order. */
    positions() { return call((r) => r.positions(), this.#live()); }
    faces() { return call((r) => r.faces(), this.#live()); }
    /** Depth (level of birth) of every vertex, caller's order. */
    depths() { return call((r) => r.depths(), this.#live()); }
    toMesh() { return { positions: this.positions(), faces: this.faces() }; }
    setPositions(positions) {
      if (!(positions instanceof Float64Array)) throw new MrvolError('positions must be a Float64Array');
      call((r, p) => r.setPositions(p), this.#live(), positions);
    }
    /** Level-e coefficients (coarse for depth <= e, details beyond), caller's vertex order. */
    analyze(positions, options = {}) {
      if (!(positions instanceof Float64Array)) throw new MrvolError('positions must be a Float64Array');
      return call((r) => r.analyze(positions, levelArg(options.level), ...schemeArgs(options)), this.#live());
    }
    /** Positions from level-e coefficients. */
    synthesize(coefficients, options = {}) {
      if (!(coefficients instanceof Float64Array)) throw new MrvolError('coefficients must be a Float64Array');
      return call((r) => r.synthesize(coefficients, levelArg(options.level), ...schemeArgs(options)), this.#live());
    }
    /** max |synthesis(analysis(x)) - x| over the current positions. */
    roundtripError(options = {}) {
      return call((r) => r.roundtripError(levelArg(options.level), ...schemeArgs(options)), this.#live());
    }
    /** Connectivity fingerprint (hex): what theta depends on besides scheme and level. */
    fingerprint() { return call((r) => r.fingerprint(), this.#live()); }
    /**
     * Computes theta^e. storage 'cage' keeps the rows of the level-e cage vertices (what editing
     * needs); 'full' keeps every entry. onProgress(fraction) may return false to cancel.
     */
    computeTheta(options = {}) {
      const storage = options.storage ?? 'cage';
      const onProgress = options.onProgress ?? undefined;
      const started = globalThis.performance?.now() ?? Date.now();
      const raw = call((r) => r.computeTheta(levelArg(options.level), ...schemeArgs(options), storage, onProgress), this.#live());
      return new Theta(raw, (globalThis.performance?.now() ?? Date.now()) - started);
    }
    /** Volume of the current positions through theta (checks that theta matches mesh, scheme, level). */
    thetaVolume(theta, options = {}) {
      if (!(theta instanceof Theta)) throw new MrvolError('thetaVolume expects a Theta');
      return call((r) => r.thetaVolume(theta.raw, levelArg(options.level), ...schemeArgs(options)), this.#live());
    }
    delete() {
      if (this.#raw) this.#raw.delete();
      this.#raw = null;
    }
  }

  return {
    /** Reads a theta file (Uint8Array); throws MrvolError if truncated, corrupt or of a future version. */
    readTheta(bytes) {
      if (!(bytes instanceof Uint8Array)) throw new MrvolError('readTheta expects a Uint8Array');
      return new Theta(call(module._readTheta, bytes));
    },
    MrvolError,
    /** Parses OBJ text into { positions: Float64Array, faces: Uint32Array } (0-based). */
    readObj(text) {
      if (typeof text !== 'string') throw new MrvolError('readObj expects the OBJ file as a string');
      return call(module._readObj, text);
    },
    writeObj(mesh) {
      checkMesh(mesh);
      return call(module._writeObj, mesh.positions, mesh.faces);
    },
    /** Checks manifoldness and orientation; returns { edges, boundaryEdges, components, closed, genus }. */
    validate(mesh) {
      checkMesh(mesh);
      return call(module._validate, mesh.positions, mesh.faces);
    },
    /** Signed enclosed volume of a valid mesh. */
    volume(mesh) {
      checkMesh(mesh);
      return call(module._volume, mesh.positions, mesh.faces);
    },
    /** Validates the mesh and recovers its semi-regular hierarchy (any vertex order). */
    openMesh(mesh, options = {}) {
      checkMesh(mesh);
      const maxLevels = options.maxLevels ?? 16;
      return new MultiresMesh(call(module._openMesh, mesh.positions, mesh.faces, maxLevels));
    },
    /** n levels of zero-detail synthesis (subdivision) of a base mesh. Returns a MultiresMesh. */
    subdivide(base, options = {}) {
      checkMesh(base);
      const levels = options.levels ?? 1;
      if (!Number.isInteger(levels)) throw new MrvolError(`levels must be an integer, got ${levels}`);
      return new MultiresMesh(call(module._subdivideBase, base.positions, base.faces, levels, ...schemeArgs(options)));
    },
  };
}
