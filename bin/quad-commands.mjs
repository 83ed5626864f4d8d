// `mrvol COMMAND --scheme catmull-clark`: the commands on quad meshes (lib/quad.mjs,
// docs/catmull-clark.md). Quad meshes are read from and written to OBJ with their quads kept.
// bin/mrvol.mjs sends these commands here and passes its helpers in `cli`.
import { MrvolError } from '../lib/node.mjs';
import { quadGradientPath } from '../lib/quad.mjs';

async function loadQuads(mrvol, path, cli) {
  if (!/\.obj$/i.test(path)) throw new cli.UsageError(`--scheme catmull-clark reads quad meshes from OBJ files, not ${path}`);
  try {
    return mrvol.readObjQuads(cli.readBytes(path));
  } catch (e) {
    if (!(e instanceof MrvolError) || e.message.startsWith('cannot read')) throw e;
    // triangles or n-gons among the quads: the quad remesher makes a quad mesh of it
    const notQuads = /a face with \d+ corners/.test(e.message);
    throw new MrvolError(`${path}: ${e.message}${notQuads ? ` (mrvol remesh ${path} --scheme catmull-clark -o OUT.obj makes one of it)` : ''}`);
  }
}

async function openQuads(mrvol, path, cli) {
  const mesh = await loadQuads(mrvol, path, cli);
  try {
    return mrvol.openQuadMesh(mesh);
  } catch (e) {
    throw e instanceof MrvolError ? new MrvolError(`${path}: ${e.message}`) : e;
  }
}

/** The Catmull-Clark levels found in the quads of `path` (0: none), or null if it is not a closed-enough quad mesh to open. */
export async function catmullClarkLevels(mrvol, path, cli) {
  try {
    const mr = await openQuads(mrvol, path, cli);
    const levels = mr.levels;
    mr.delete();
    return levels;
  } catch (e) {
    if (e instanceof MrvolError) return null;
    throw e;
  }
}

function levelIn(mr, level, path) {
  if (level < mr.lowestLevel || level > mr.levels)
    throw new MrvolError(`level ${level} is out of range: ${path} has levels ${mr.lowestLevel}..${mr.levels}` +
                         (mr.lowestLevel > 0 ? ' (its base is a cube, whose first split cannot be analysed)' : ''));
  return level;
}

function writeQuadObj(mrvol, path, mesh, cli) {
  if (!/\.obj$/i.test(path)) throw new cli.UsageError(`cannot write ${path}: quad meshes are written as .obj`);
  cli.writeText(path, mrvol.writeObjQuads(mesh));
}

export const QUAD_COMMANDS = {
  async info(mrvol, values, positionals, cli) {
    const path = cli.onePath(positionals, 'MESH.obj');
    const mr = await openQuads(mrvol, path, cli);
    const i = mr.info();
    mr.delete();
    const result = {
      scheme: 'catmull-clark', vertices: i.vertices, faces: i.faces, quads: i.faces, levels: i.levels,
      lowestLevel: i.lowestLevel, baseVertices: i.baseVertices, baseVertexIndices: Array.from(i.baseVertexIndices),
      closed: i.closed, boundaryEdges: i.boundaryEdges, genus: i.genus, volume: i.volume, semiRegular: i.levels > 0,
    };
    cli.print(values, result, (r) => [
      `vertices       ${r.vertices}`, `quads          ${r.quads}`, `levels         ${r.levels} (Catmull-Clark splits)`,
      `semi-regular   ${r.semiRegular ? 'yes' : 'no (no Catmull-Clark 1-to-4 splits found)'}`,
      ...(r.lowestLevel > 0 ? [`lowest level   ${r.lowestLevel} (the base is a cube: its first split cannot be analysed)`] : []),
      `base vertices  ${r.baseVertices}`, `closed         ${r.closed}`, `boundary edges ${r.boundaryEdges}`,
      `genus          ${r.closed ? r.genus : '- (not a closed surface)'}`, `volume         ${r.volume} (bilinear patches)`].join('\n'));
  },

  async subdivide(mrvol, values, positionals, cli) {
    const input = cli.onePath(positionals, 'BASE.obj');
    const levels = cli.integer(values.levels, 'levels');
    if (!values.output) throw new cli.UsageError('-o OUT.obj is required');
    const base = await loadQuads(mrvol, input, cli);
    let mr;
    try {
      mr = mrvol.subdivideQuads(base, { levels });
    } catch (e) {
      throw e instanceof MrvolError ? new MrvolError(`${input}: ${e.message}`) : e;
    }
    const mesh = mr.toMesh();
    const info = mr.info();
    mr.delete();
    writeQuadObj(mrvol, values.output, mesh, cli);
    const result = { vertices: info.vertices, faces: info.faces, levels, scheme: 'catmull-clark', volume: info.volume,
                     output: values.output };
    cli.print(values, result, (r) => `wrote ${r.output}: ${r.vertices} vertices, ${r.faces} quads (catmull-clark, ${r.levels} levels)`);
  },

  async roundtrip(mrvol, values, positionals, cli) {
    const path = cli.onePath(positionals, 'MESH.obj');
    const mr = await openQuads(mrvol, path, cli);
    try {
      const level = levelIn(mr, cli.integer(values.level, 'level', mr.lowestLevel), path);
      const maxError = mr.roundtripError({ level });
      let scale = 0;
      for (const x of mr.positions()) scale = Math.max(scale, Math.abs(x));
      const result = { scheme: 'catmull-clark', level, maxError, relativeError: scale > 0 ? maxError / scale : maxError };
      cli.print(values, result, (r) => `max reconstruction error ${r.maxError} (relative ${r.relativeError}), catmull-clark scheme, level ${r.level}`);
    } finally {
      mr.delete();
    }
  },

  async volume(mrvol, values, positionals, cli) {
    cli.print(values, await tensorReport(mrvol, values, positionals, cli, false), cli.describeTensor);
  },

  async theta(mrvol, values, positionals, cli) {
    cli.print(values, await tensorReport(mrvol, values, positionals, cli, true), cli.describeTensor);
  },

  async edit(mrvol, values, positionals, cli) {
    const path = cli.onePath(positionals, 'MESH.obj');
    const moves = cli.parseMoves(values);
    if (!values.output) throw new cli.UsageError('-o OUT.obj is required');
    const tolerance = values.tolerance === undefined ? 1e-5 : cli.number(values.tolerance, 'tolerance');
    if (!(tolerance > 0 && tolerance < 1)) throw new cli.UsageError('--tolerance must be between 0 and 1');
    const gradientPath = values.path ?? 'auto';
    if (!['auto', 'polynomial', 'tensor', 'matrix-free'].includes(gradientPath))
      throw new cli.UsageError(`--path must be auto, polynomial, tensor or matrix-free, got '${gradientPath}'`);
    const free = values.free ?? 'cage';
    const freeList = free === 'cage' || free === 'all' ? null : cli.parseList(free, 'free');
    cli.checkFreeNotMoved(freeList, moves);
    const detailLevels = values['free-details'] ? cli.parseList(values['free-details'], 'free-details') : [];
    if (values.surface !== undefined && values.surface !== 'mesh')
      throw new cli.UsageError(`--surface ${values.surface} is not available for catmull-clark (the bilinear patches' volume is kept)`);
    const keep = (values.keep ?? 'volume').split(',').map((k) => k.trim());
    if (keep.some((k) => k !== 'volume' && k !== 'centroid') || !keep.includes('volume'))
      throw new cli.UsageError(`--keep expects volume or volume,centroid, got '${values.keep}'`);
    const centroid = keep.includes('centroid');
    if (centroid && (gradientPath === 'tensor' || gradientPath === 'polynomial' || values.theta))
      throw new cli.UsageError('--keep centroid runs matrix-free (--path auto or matrix-free, no --theta)');
    const mr = await openQuads(mrvol, path, cli);
    let theta, editor;
    try {
      const level = levelIn(mr, cli.integer(values.level, 'level', mr.lowestLevel), path);
      const preserve = values['no-preserve'] === undefined;
      // auto: the polynomial built from the fine quads on a coarse cage, else matrix-free (quadGradientPath).
      const chosen = values.theta ? 'tensor' : centroid ? 'matrix-free' : quadGradientPath(mr, { level, path: gradientPath });
      editor = mr.createEditor({ level, path: chosen === 'polynomial' && preserve ? 'polynomial' : 'matrix-free' });
      // The bilinear patches' centre of mass, kept where it is now (with the volume).
      const centroidBefore = Array.from(editor.centroid());
      if (centroid) editor.keepCentroid(true);
      editor.setFreeSet({ cage: freeList ?? (free === 'all' ? 'all' : 'minus-held'), detailLevels });
      if (preserve && chosen === 'tensor') {
        try {
          theta = values.theta ? mrvol.readTheta(cli.readBytes(values.theta)) : mr.computeTheta({ level });
          editor.useTheta(theta);
        } catch (e) {
          throw e instanceof MrvolError && values.theta && !e.message.startsWith('cannot read') ? new MrvolError(`${values.theta}: ${e.message}`) : e;
        }
      }
      const started = performance.now();
      const report = editor.moveVertices(moves, { tolerance, preserve });
      const stepMs = performance.now() - started;
      if (!report.converged) throw new MrvolError(`the volume correction did not converge: ${report.message}`);
      // The input OBJ with the new positions: its quads and every other line kept.
      if (!/\.obj$/i.test(values.output)) throw new cli.UsageError(`cannot write ${values.output}: quad meshes are written as .obj`);
      cli.writeText(values.output, mrvol.writeObjLike(cli.readBytes(path), editor.positions()));
      const result = {
        scheme: 'catmull-clark', level, cageVertices: editor.cageSize, volumeReference: report.volumeReference, volumeTarget: report.volumeTarget,
        volumeResult: report.volumeResult, relativeError: report.relativeError, iterations: report.iterations,
        substeps: report.substeps, stepMs: Math.round(stepMs * 1000) / 1000, path: preserve ? report.path : 'none',
        keep, centroidBefore, centroidAfter: Array.from(editor.centroid()), output: values.output,
      };
      const drift = Math.hypot(...result.centroidAfter.map((x, k) => x - centroidBefore[k]));
      cli.print(values, result, (r) => [
        `cage             level ${r.level}, ${r.cageVertices} vertices${values.level === undefined && mr.lowestLevel > 0 ? ' (the lowest level: the base is a cube)' : ''}`,
        `reference volume ${r.volumeReference}`, `target volume    ${r.volumeTarget}`,
        `result volume    ${r.volumeResult} (relative error ${r.relativeError})`,
        `centre of mass   ${r.centroidBefore.join(' ')} -> ${r.centroidAfter.join(' ')} (moved ${drift}${centroid ? ', kept' : ''})`,
        `correction       ${r.iterations} iterations, ${r.substeps} sub-steps, ${r.stepMs} ms, ${r.path} gradient`,
        `wrote            ${r.output}`].join('\n'));
    } finally {
      editor?.delete();
      theta?.delete();
      mr.delete();
    }
  },

  async remesh(mrvol, values, positionals, cli) {
    const input = cli.onePath(positionals, 'IN.obj');
    const levels = cli.integer(values.levels, 'levels', 2);
    if (levels < 0 || levels > 5) throw new cli.UsageError(`--levels must be in 0..5 for catmull-clark, got ${levels}`);
    const baseFaces = values['base-faces'] === undefined ? undefined : cli.integer(values['base-faces'], 'base-faces');
    if (baseFaces !== undefined && baseFaces < 4) throw new cli.UsageError(`--base-faces must be at least 4, got ${baseFaces}`);
    if (!values.output) throw new cli.UsageError('-o OUT.obj is required');
    if (!/\.obj$/i.test(values.output)) throw new cli.UsageError(`cannot write ${values.output}: quad meshes are written as .obj`);
    const mesh = await cli.loadMesh(mrvol, input);
    const { remeshQuads } = await import('../lib/remesh-quad.mjs');
    let r;
    try {
      r = await remeshQuads(mrvol, mesh, { levels, baseFaces, keepLargest: values['keep-largest'] ?? false,
                                          repair: values.repair ?? false });
    } catch (e) {
      throw e instanceof MrvolError ? new MrvolError(`${input}: ${e.message}`) : e;
    }
    cli.writeText(values.output, mrvol.writeObjQuads(r.mesh));
    const round = (x, d) => Math.round(x * 10 ** d) / 10 ** d;
    const result = { scheme: 'catmull-clark', levels: r.levels, baseVertices: r.baseVertices, baseFaces: r.baseFaces,
                     vertices: r.vertices, faces: r.faces, distanceToInput: r.distanceToInput, volumeChange: r.volumeChange,
                     ms: round(r.ms, 1), output: values.output };
    cli.print(values, result, (x) => [
      `wrote            ${x.output}: ${x.vertices} vertices, ${x.faces} quads, ${x.levels} Catmull-Clark levels over ${x.baseVertices} base vertices`,
      `distance         ${round(100 * x.distanceToInput, 3)}% of the bounding-box diagonal (largest, vertices to input)`,
      `volume change    ${round(100 * x.volumeChange, 4)}%`,
      `time             ${x.ms} ms`].join('\n'));
  },
};

// `volume` and `theta`: theta^e of the bilinear volume (computed or read) and what it gives.
async function tensorReport(mrvol, values, positionals, cli, requireOutput) {
  const path = cli.onePath(positionals, 'MESH.obj');
  if (requireOutput && !values.output) throw new cli.UsageError('-o FILE.theta is required');
  if (values.surface && values.surface !== 'mesh')
    throw new cli.UsageError(`--surface ${values.surface} is not available for catmull-clark (the bilinear patches' volume is kept)`);
  const storage = values.storage ?? 'cage';
  if (!['cage', 'full'].includes(storage)) throw new cli.UsageError(`--storage must be cage or full, got '${storage}'`);
  const mr = await openQuads(mrvol, path, cli);
  let theta;
  try {
    const level = levelIn(mr, cli.integer(values.level, 'level', mr.lowestLevel), path);
    let source = 'computed';
    if (values.theta && !requireOutput) {
      theta = mrvol.readTheta(cli.readBytes(values.theta));
      source = values.theta;
    } else {
      theta = mr.computeTheta({ level, storage });
    }
    const info = theta.info();
    const result = {
      volume: mr.info().volume, thetaVolume: mr.thetaVolume(theta, { level }), scheme: 'catmull-clark', level,
      storage: info.storage, surface: 'mesh', source, nnzStored: info.nnzStored, nnzFull: info.nnzFull, bytes: info.bytes,
      precomputeMs: theta.precomputeMs,
    };
    if (requireOutput) {
      const bytes = theta.bytes();
      cli.writeBytes(values.output, bytes);
      result.output = values.output;
      result.fileBytes = bytes.length;
    }
    return result;
  } finally {
    theta?.delete();
    mr.delete();
  }
}
