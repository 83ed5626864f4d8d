#!/usr/bin/env node
// mrvol command line: the WASM core under Node. Errors: exit 1 and one line
// `mrvol: error: ...`; bad usage: exit 2.
import { readFileSync, writeFileSync } from 'node:fs';
import { parseArgs } from 'node:util';
import { createMrvol, MrvolError } from '../lib/node.mjs';

const USAGE = `usage: mrvol <command> [options]

commands:
  info MESH.obj [--json]                      counts, levels, base vertices, genus, volume
  subdivide BASE.obj --levels n [--scheme S] -o OUT.obj [--json]
                                              zero-detail synthesis (subdivision) of a base mesh
  roundtrip MESH.obj [--scheme S] [--level e] [--json]
                                              max error of synthesis(analysis(x)) - x
  volume MESH.obj [--scheme S] [--level e] [--storage cage|full] [--theta FILE.theta] [--json]
                                              mesh volume and the volume through theta^e
  theta MESH.obj [--scheme S] [--level e] [--storage cage|full] -o FILE.theta [--json]
                                              computes theta^e and writes a theta file

options:
  --scheme loop|butterfly|linear   wavelet scheme (default loop)
  --alpha a --beta b               Loop update weights (default -1.70943, 0.42954)
  --level e                        analysis level, 0 <= e <= n (default 0)
  --storage cage|full              theta entries kept: rows of the level-e cage (default) or all;
                                   nnzFull (the full tensor's count) is known only with full
  --theta FILE                     use a stored theta file instead of computing
  --json                           print the result as JSON
  -o, --output FILE                output file`;

class UsageError extends Error {}

const OPTIONS = {
  json: { type: 'boolean' },
  scheme: { type: 'string' },
  alpha: { type: 'string' },
  beta: { type: 'string' },
  level: { type: 'string' },
  levels: { type: 'string' },
  output: { type: 'string', short: 'o' },
  storage: { type: 'string' },
  theta: { type: 'string' },
  help: { type: 'boolean', short: 'h' },
};

function integer(value, name, fallback) {
  if (value === undefined) {
    if (fallback === undefined) throw new UsageError(`--${name} is required`);
    return fallback;
  }
  if (!/^-?\d+$/.test(value)) throw new UsageError(`--${name} expects an integer, got '${value}'`);
  return Number(value);
}

function number(value, name) {
  if (value === undefined) return undefined;
  const x = Number(value);
  if (value.trim() === '' || !Number.isFinite(x)) throw new UsageError(`--${name} expects a number, got '${value}'`);
  return x;
}

function schemeOptions(values) {
  const scheme = values.scheme ?? 'loop';
  if (!['loop', 'butterfly', 'linear'].includes(scheme))
    throw new UsageError(`--scheme must be loop, butterfly or linear, got '${scheme}'`);
  return { scheme, alpha: number(values.alpha, 'alpha'), beta: number(values.beta, 'beta') };
}

function storageOption(values) {
  const storage = values.storage ?? 'cage';
  if (!['cage', 'full'].includes(storage)) throw new UsageError(`--storage must be cage or full, got '${storage}'`);
  return storage;
}

function readBytes(path) {
  try {
    return readFileSync(path);
  } catch (e) {
    throw new MrvolError(`cannot read ${path}: ${e.code === 'ENOENT' ? 'no such file' : e.message}`);
  }
}

function readText(path) {
  try {
    return readFileSync(path, 'utf8');
  } catch (e) {
    throw new MrvolError(`cannot read ${path}: ${e.code === 'ENOENT' ? 'no such file' : e.message}`);
  }
}

function writeText(path, text) {
  try {
    writeFileSync(path, text);
  } catch (e) {
    throw new MrvolError(`cannot write ${path}: ${e.message}`);
  }
}

// Reads an OBJ file; errors name the file.
function loadMesh(mrvol, path) {
  try {
    return mrvol.readObj(readText(path));
  } catch (e) {
    if (e instanceof MrvolError && !e.message.startsWith('cannot read')) throw new MrvolError(`${path}: ${e.message}`);
    throw e;
  }
}

function openMultires(mrvol, path) {
  const mesh = loadMesh(mrvol, path);
  try {
    return mrvol.openMesh(mesh);
  } catch (e) {
    if (e instanceof MrvolError) throw new MrvolError(`${path}: ${e.message}`);
    throw e;
  }
}

function onePath(positionals, what) {
  if (positionals.length === 0) throw new UsageError(`missing ${what}`);
  if (positionals.length > 1) throw new UsageError(`unexpected argument '${positionals[1]}'`);
  return positionals[0];
}

function print(values, result, text) {
  if (values.json) process.stdout.write(JSON.stringify(result) + '\n');
  else process.stdout.write(text(result) + '\n');
}

// Shared by `volume` and `theta`: the tensor (computed or read) and what it says about the mesh.
function tensorReport(mrvol, values, positionals, { requireOutput }) {
  const path = onePath(positionals, 'MESH.obj');
  const level = integer(values.level, 'level', 0);
  const scheme = schemeOptions(values);
  const storage = storageOption(values);
  if (requireOutput && !values.output) throw new UsageError('-o FILE.theta is required');
  if (values.theta && values.storage) throw new UsageError('--storage applies when computing, not with --theta');
  const mr = openMultires(mrvol, path);
  let theta;
  try {
    if (level < 0 || level > mr.levels)
      throw new MrvolError(`level ${level} is out of range: ${path} has levels 0..${mr.levels}`);
    if (values.theta) {
      try {
        theta = mrvol.readTheta(readBytes(values.theta));
      } catch (e) {
        throw e instanceof MrvolError && !e.message.startsWith('cannot read') ? new MrvolError(`${values.theta}: ${e.message}`) : e;
      }
    } else {
      theta = mr.computeTheta({ level, storage, ...scheme });
    }
    let thetaVolume;
    try {
      thetaVolume = mr.thetaVolume(theta, { level, ...scheme });
    } catch (e) {
      throw e instanceof MrvolError && values.theta ? new MrvolError(`${values.theta}: ${e.message}`) : e;
    }
    const info = theta.info();
    const result = {
      volume: mr.info().volume, thetaVolume, scheme: scheme.scheme, level, storage: info.storage,
      nnzFull: info.nnzFull, nnzStored: info.nnzStored, bytes: info.bytes,
      precomputeMs: values.theta ? null : Math.round(theta.precomputeMs * 10) / 10,
      source: values.theta ? 'file' : 'computed',
    };
    if (values.output) {
      const bytes = theta.bytes();
      writeBytes(values.output, bytes);
      result.output = values.output;
      result.fileBytes = bytes.length;
    }
    return result;
  } finally {
    theta?.delete();
    mr.delete();
  }
}

function writeBytes(path, bytes) {
  try {
    writeFileSync(path, bytes);
  } catch (e) {
    throw new MrvolError(`cannot write ${path}: ${e.message}`);
  }
}

function describeTensor(r) {
  return [`volume          ${r.volume}`, `theta volume    ${r.thetaVolume}`,
          `theta           ${r.scheme} scheme, level ${r.level}, ${r.storage} storage (${r.source})`,
          `entries         ${r.nnzStored} stored, ${r.nnzFull ?? 'unknown (cage storage)'} non-zeros in the full tensor`,
          `memory          ${r.bytes} bytes` + (r.precomputeMs != null ? `, computed in ${r.precomputeMs} ms` : '')]
    .concat(r.output ? [`wrote           ${r.output} (${r.fileBytes} bytes)`] : []).join('\n');
}

const COMMANDS = {
  info(mrvol, values, positionals) {
    const mr = openMultires(mrvol, onePath(positionals, 'MESH.obj'));
    const i = mr.info();
    mr.delete();
    const result = {
      vertices: i.vertices, faces: i.faces, levels: i.levels, baseVertices: i.baseVertices,
      baseVertexIndices: Array.from(i.baseVertexIndices), closed: i.closed, boundaryEdges: i.boundaryEdges,
      genus: i.genus, volume: i.volume,
    };
    print(values, result, (r) => [
      `vertices       ${r.vertices}`, `faces          ${r.faces}`, `levels         ${r.levels}`,
      `base vertices  ${r.baseVertices}`, `closed         ${r.closed}`, `boundary edges ${r.boundaryEdges}`,
      `genus          ${r.genus}`, `volume         ${r.volume}`].join('\n'));
  },

  subdivide(mrvol, values, positionals) {
    const input = onePath(positionals, 'BASE.obj');
    const levels = integer(values.levels, 'levels');
    const scheme = schemeOptions(values);
    if (!values.output) throw new UsageError('-o OUT.obj is required');
    const base = loadMesh(mrvol, input);
    const mr = mrvol.subdivide(base, { levels, ...scheme });
    const mesh = mr.toMesh();
    const info = mr.info();
    mr.delete();
    writeText(values.output, mrvol.writeObj(mesh));
    const result = { vertices: info.vertices, faces: info.faces, levels, scheme: values.scheme ?? 'loop',
                     volume: info.volume, output: values.output };
    print(values, result, (r) => `wrote ${r.output}: ${r.vertices} vertices, ${r.faces} faces (${r.scheme}, ${r.levels} levels)`);
  },

  roundtrip(mrvol, values, positionals) {
    const path = onePath(positionals, 'MESH.obj');
    const level = integer(values.level, 'level', 0);
    const scheme = schemeOptions(values);
    const mr = openMultires(mrvol, path);
    const maxError = mr.roundtripError({ level, ...scheme });
    const positions = mr.positions();
    mr.delete();
    let scale = 0;
    for (const x of positions) scale = Math.max(scale, Math.abs(x));
    const result = { scheme: scheme.scheme, level, maxError, relativeError: scale > 0 ? maxError / scale : maxError };
    print(values, result, (r) => `max reconstruction error ${r.maxError} (relative ${r.relativeError}), ${r.scheme} scheme, level ${r.level}`);
  },
};

COMMANDS.volume = (mrvol, values, positionals) =>
  print(values, tensorReport(mrvol, values, positionals, { requireOutput: false }), describeTensor);
COMMANDS.theta = (mrvol, values, positionals) =>
  print(values, tensorReport(mrvol, values, positionals, { requireOutput: true }), describeTensor);

export async function main(argv) {
  let values, positionals;
  try {
    ({ values, positionals } = parseArgs({ args: argv, options: OPTIONS, allowPositionals: true, strict: true }));
  } catch (e) {
    process.stderr.write(`mrvol: error: ${e.message}\n${USAGE}\n`);
    return 2;
  }
  if (values.help || positionals.length === 0) {
    (values.help ? process.stdout : process.stderr).write(USAGE + '\n');
    return values.help ? 0 : 2;
  }
  const [command, ...rest] = positionals;
  const run = Object.hasOwn(COMMANDS, command) ? COMMANDS[command] : null;
  if (!run) {
    process.stderr.write(`mrvol: error: unknown command '${command}'\n${USAGE}\n`);
    return 2;
  }
  try {
    const mrvol = await createMrvol();
    await run(mrvol, values, rest);
    return 0;
  } catch (e) {
    if (e instanceof UsageError) {
      process.stderr.write(`mrvol: error: ${e.message}\n`);
      return 2;
    }
    const message = e instanceof MrvolError ? e.message : `internal error: ${e?.message ?? e}`;
    process.stderr.write(`mrvol: error: ${message.split('\n')[0]}\n`);
    return 1;
  }
}

process.exitCode = await main(process.argv.slice(2));
