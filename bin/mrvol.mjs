#!/usr/bin/env node
// mrvol command line: the WASM core under Node. Errors: exit 1 and one line
// `mrvol: error: ...`; bad usage: exit 2. `mrvol help [COMMAND]`, `COMMAND --help`, `--version`.
// Steps over about a second draw a progress bar on stderr when it is a terminal (bin/progress.mjs).
import { open, readFile } from 'node:fs/promises';
import { readFileSync, statSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { parseArgs } from 'node:util';
import { createMrvol, MrvolError, readObjFile } from '../lib/node.mjs';
import { chooseGradientPath } from '../lib/api.mjs';
import { Progress } from './progress.mjs';
import { catmullClarkLevels, QUAD_COMMANDS } from './quad-commands.mjs';

const VERSION = JSON.parse(await readFile(new URL('../package.json', import.meta.url), 'utf8')).version;

// What each command takes and does: `usage` (after `mrvol `), a one-line summary, its options.
const COMMAND_HELP = {
  info: { usage: 'info MESH.obj [--scheme catmull-clark] [--json]', summary: 'counts, levels, base vertices, genus, volume',
          options: ['scheme', 'json'] },
  subdivide: {
    usage: 'subdivide BASE.obj --levels n [--scheme S] -o OUT.obj [--json]',
    summary: 'zero-detail synthesis (subdivision) of a base mesh',
    options: ['levels', 'scheme', 'alpha', 'output', 'json'],
  },
  roundtrip: {
    usage: 'roundtrip MESH.obj [--scheme S] [--level e] [--json]',
    summary: 'max error of synthesis(analysis(x)) - x',
    options: ['scheme', 'alpha', 'level', 'json'],
  },
  volume: {
    usage: 'volume MESH.obj [--scheme S] [--level e] [--storage cage|full] [--theta FILE.theta]\n' +
           '     [--surface mesh|limit] [--json]',
    summary: 'mesh volume and the volume through theta^e (limit: of the Loop limit surface)',
    options: ['scheme', 'alpha', 'level', 'storage', 'theta', 'surface', 'json'],
  },
  theta: {
    usage: 'theta MESH.obj [--scheme S] [--level e] [--storage cage|full] [--surface mesh|limit]\n' +
           '     -o FILE.theta [--json]',
    summary: 'computes theta^e and writes a theta file',
    options: ['scheme', 'alpha', 'level', 'storage', 'surface', 'output', 'json'],
  },
  edit: {
    usage: 'edit MESH.obj [--scheme S] [--level e] --move V:dx,dy,dz [--move ...] [--free cage|all|LIST]\n' +
           '     [--free-details L,...] [--no-preserve] [--tolerance t] [--path auto|polynomial|tensor|matrix-free]\n' +
           '     [--theta FILE.theta] [--surface mesh|limit] [--keep volume[,centroid]] -o OUT.obj [--json]',
    summary: 'moves level-e cage vertices, keeping the volume; OUT.obj is MESH.obj with the new positions (other lines kept)',
    options: ['scheme', 'alpha', 'level', 'move', 'free', 'free-details', 'no-preserve', 'tolerance', 'path', 'theta',
              'surface', 'keep', 'output', 'json'],
  },
  remesh: {
    usage: 'remesh IN.obj [--levels n] [--base-faces k] [--keep-largest] [--repair [--max-hole m] [--smooth k]]\n' +
           '     [--scheme catmull-clark] -o OUT.obj [--json]',
    summary: 'semi-regular remeshing of closed manifold meshes (any genus, pieces, sharp edges; catmull-clark: quads)',
    options: ['levels', 'base-faces', 'keep-largest', 'repair', 'max-hole', 'smooth', 'scheme', 'output', 'json'],
  },
  help: { usage: 'help [COMMAND]', summary: 'this help, or one command\'s', options: [] },
};

const OPTION_HELP = {
  scheme: '--scheme loop|butterfly|linear|catmull-clark\n' +
          '                                 wavelet scheme (default loop); catmull-clark: quad meshes\n' +
          '                                 (OBJ, quads kept; docs/catmull-clark.md)',
  alpha: '--alpha a --beta b               Loop update weights (default -1.70943, 0.42954)',
  level: '--level e                        analysis level, 0 <= e <= n (default 0)',
  levels: '--levels n                       levels of 1-to-4 splits (subdivide: required; remesh: default\n' +
          '                                 as many as keep the detail within 0.5%)',
  storage: '--storage cage|full              theta entries kept: rows of the level-e cage (default) or all;\n' +
           '                                 nnzFull (the full tensor\'s count) is known only with full',
  theta: '--theta FILE                     use a stored theta file instead of computing',
  surface: '--surface mesh|limit             the volume of the fine mesh (default) or of its Loop limit\n' +
           '                                 surface (closed meshes; docs/limit-volume.md)',
  keep: '--keep volume[,centroid]         what the edit keeps: the volume (default), and the centre of mass\n' +
        '                                 (mesh surface; docs/centroid.md)',
  move: '--move V:dx,dy,dz                moves cage vertex V (0-based, file order) by (dx, dy, dz); held',
  free: '--free cage|all|LIST             free set: cage minus the moved vertices (default), all cage\n' +
        '                                 vertices, or a comma-separated list of cage vertices',
  'free-details': '--free-details L,...             also free the details of these levels (matrix-free path)',
  'no-preserve': '--no-preserve                    apply the move without volume correction',
  tolerance: '--tolerance t                    relative volume error to reach (default 1e-5)',
  path: '--path auto|polynomial|tensor|matrix-free\n' +
        '                                 gradient path; auto: the cage polynomial built from the mesh\n' +
        '                                 (no theta) when e <= n - 3, else (or with --free-details)\n' +
        '                                 matrix-free; tensor computes theta (or --theta FILE)',
  'base-faces': '--base-faces k                   remesh: faces of the simplified base mesh (default: the\n' +
                '                                 input\'s faces / 12, within 200..1000: a cage of 100-500 handles)',
  'keep-largest': '--keep-largest                   remesh: keep the largest connected component, drop the others',
  repair: '--repair                         remesh: repair a scan first: weld, drop duplicate faces, fins,\n' +
          '                                 non-manifold and folded faces, close holes (reported in --json)',
  'max-hole': '--max-hole m                     remesh --repair: close holes of at most m edges (default 100)',
  smooth: '--smooth k                       remesh --repair: k Taubin smoothing steps after the repair',
  json: '--json                           print the result as JSON',
  threads: '--threads n                      threads for the core\'s big loops (default: the cores, at most 8;\n' +
           '                                 1: the single-thread WASM build)',
  output: '-o, --output FILE                output file',
};

const EXIT_STATUS = `exit status:
  0  success
  1  error (unreadable or invalid input, a computation that fails): one line 'mrvol: error: ...' on stderr
  2  bad usage (unknown command or option, missing or malformed argument): the message on stderr`;

const PROGRESS_NOTE = `progress: steps over about a second (reading a big file, theta, remeshing) draw a bar on stderr
when stderr is a terminal, none when it is piped; MRVOL_PROGRESS_DELAY_MS sets the delay (default 1000).`;

function usage() {
  const commands = Object.entries(COMMAND_HELP).filter(([name]) => name !== 'help').map(([, c]) => {
    const first = `  ${c.usage.replace(/\n {5}/g, '\n       ')}`;
    return first.length <= 46 && !first.includes('\n') ? first.padEnd(46) + c.summary
      : `${first}\n${' '.repeat(46)}${c.summary}`;
  });
  const options = Object.entries(OPTION_HELP).map(([, text]) => '  ' + text.replace(/\n/g, '\n  '));
  return `usage: mrvol <command> [options]
       mrvol help [COMMAND]       help on one command (also: mrvol COMMAND --help)
       mrvol --version            the version of mrvol

commands:
${commands.join('\n')}

options:
${options.join('\n')}
  -h, --help                       this help, or the command's
  --version                        print the version

${EXIT_STATUS}

${PROGRESS_NOTE}`;
}

function commandUsage(name) {
  const c = COMMAND_HELP[name];
  const options = c.options.map((o) => '  ' + OPTION_HELP[o].replace(/\n/g, '\n  '));
  return `usage: mrvol ${c.usage}

${c.summary[0].toUpperCase() + c.summary.slice(1)}.
${options.length ? `\noptions:\n${options.join('\n')}\n  -h, --help                       this help\n` : ''}
${EXIT_STATUS}`;
}

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
  move: { type: 'string', multiple: true },
  free: { type: 'string' },
  'free-details': { type: 'string' },
  'no-preserve': { type: 'boolean' },
  tolerance: { type: 'string' },
  path: { type: 'string' },
  theta: { type: 'string' },
  surface: { type: 'string' },
  keep: { type: 'string' },
  'base-faces': { type: 'string' },
  'keep-largest': { type: 'boolean' },
  repair: { type: 'boolean' },
  'max-hole': { type: 'string' },
  smooth: { type: 'string' },
  threads: { type: 'string' },
  help: { type: 'boolean', short: 'h' },
  version: { type: 'boolean' },
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
  if (!/^\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*$/.test(value) || !Number.isFinite(x))
    throw new UsageError(`--${name} expects a number, got '${value}'`);
  return x;
}

function schemeOptions(values) {
  const scheme = values.scheme ?? 'loop';
  if (!['loop', 'butterfly', 'linear', 'catmull-clark'].includes(scheme))
    throw new UsageError(`--scheme must be loop, butterfly or linear (catmull-clark for quad meshes), got '${scheme}'`);
  return { scheme, alpha: number(values.alpha, 'alpha'), beta: number(values.beta, 'beta') };
}

// Options every command takes.
const GLOBAL_OPTIONS = new Set(['threads', 'help', 'version']);

/**
 * The options given must be the command's own (an option another command takes was ignored
 * without a word: `remesh --level 2`, `info --scheme foo`); --scheme must be a scheme the command
 * takes, and Loop's weights only with Loop. Throws UsageError naming the option.
 */
function checkCommandOptions(command, values) {
  const own = new Set(COMMAND_HELP[command].options);
  if (own.has('alpha')) own.add('beta');
  for (const name of Object.keys(values)) {
    if (GLOBAL_OPTIONS.has(name) || own.has(name)) continue;
    const list = COMMAND_HELP[command].options.map((o) => (o === 'output' ? '-o' : `--${o}`)).join(', ');
    throw new UsageError(`${command} has no ${name === 'output' ? '-o' : `--${name}`} option${list ? ` (its options: ${list})` : ''}`);
  }
  if (values.scheme === undefined) {
    if ((values.alpha ?? values.beta) !== undefined && !own.has('alpha')) throw new UsageError(`${command} has no --alpha or --beta option`);
    return;
  }
  if (!['loop', 'butterfly', 'linear', 'catmull-clark'].includes(values.scheme))
    throw new UsageError(`--scheme must be loop, butterfly or linear (catmull-clark for quad meshes), got '${values.scheme}'`);
  // info finds the 1-to-4 splits of any triangle scheme alike; remesh makes meshes of linear splits
  // (the scheme is chosen when they are edited): only catmull-clark (quads) changes what they do.
  if ((command === 'info' || command === 'remesh') && values.scheme !== 'catmull-clark')
    throw new UsageError(`${command} takes --scheme catmull-clark only (quad meshes), got '${values.scheme}'`);
  if ((values.alpha ?? values.beta) !== undefined && values.scheme !== 'loop')
    throw new UsageError(`--alpha and --beta are Loop's update weights: not with --scheme ${values.scheme}`);
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

// Progress of one step (see bin/progress.mjs); MRVOL_PROGRESS_DELAY_MS overrides the delay. The
// delay counts from the command's start: once a command has run that long (a big file read), every
// later step shows at once, the ones that run without reporting (opening, the editor) too.
const commandStarted = performance.now();
function progress(label) {
  const given = Number(process.env.MRVOL_PROGRESS_DELAY_MS);
  const delay = Number.isFinite(given) && given >= 0 ? given : 1000;
  return new Progress(label, { delayMs: Math.max(0, delay - (performance.now() - commandStarted)) });
}

/** `work()` under a progress line `label` (drawn before it starts when the command has run past the delay). */
function during(label, work) {
  const bar = progress(label);
  bar.update(null);
  try {
    return work();
  } finally {
    bar.done();
  }
}

const READ_CHUNK = 4 << 20;

// Reads a file's bytes in chunks, with a progress bar when that takes long (a big scan).
async function readFileWithProgress(path) {
  let file;
  const bar = progress(`reading ${path}`);
  try {
    file = await open(path, 'r');
    const size = (await file.stat()).size;
    const buffer = Buffer.allocUnsafe(size);
    for (let at = 0; at < size;) {
      const { bytesRead } = await file.read(buffer, at, Math.min(READ_CHUNK, size - at), at);
      if (bytesRead === 0) break;
      at += bytesRead;
      bar.update(at / size);
    }
    return buffer;
  } catch (e) {
    throw new MrvolError(`cannot read ${path}: ${e.code === 'ENOENT' ? 'no such file' : e.message}`);
  } finally {
    bar.done();
    await file?.close();
  }
}

// An OBJ file read in chunks straight into the WASM reader (never whole in memory), with a progress bar.
async function readObjWithProgress(mrvol, path) {
  const bar = progress(`reading ${path}`);
  try {
    return await readObjFile(mrvol, path, { onProgress: (fraction) => bar.update(fraction) });
  } catch (e) {
    if (e instanceof MrvolError && !e.message.startsWith(`cannot read ${path}`)) throw new MrvolError(`${path}: ${e.message}`);
    throw e;
  } finally {
    bar.done();
  }
}

/**
 * -o checked before any work (a remesh of minutes failed only when it came to write): its folder
 * must exist and be a folder, the path must not be one. Throws MrvolError naming what is wrong.
 */
function checkOutputPath(path) {
  let stat = null;
  try {
    stat = statSync(path);
  } catch {
    // Not there yet: its folder must be.
  }
  if (stat?.isDirectory()) throw new MrvolError(`cannot write ${path}: it is a directory`);
  const folder = dirname(path);
  let folderStat;
  try {
    folderStat = statSync(folder);
  } catch {
    throw new MrvolError(`cannot write ${path}: no such directory ${folder}`);
  }
  if (!folderStat.isDirectory()) throw new MrvolError(`cannot write ${path}: ${folder} is not a directory`);
}

function writeText(path, text) {
  try {
    writeFileSync(path, text);
  } catch (e) {
    throw new MrvolError(`cannot write ${path}: ${e.message}`);
  }
}

// A .gltf's sidecar files (buffers with a relative URI), read beside it: [[uri, bytes]].
function gltfResources(path, bytes) {
  let doc;
  try {
    doc = JSON.parse(new TextDecoder().decode(bytes));
  } catch {
    return undefined;  // the core says what is wrong with the JSON
  }
  const uris = (Array.isArray(doc?.buffers) ? doc.buffers : []).map((b) => b?.uri)
    .filter((uri) => typeof uri === 'string' && !uri.startsWith('data:'));
  return uris.map((uri) => [uri, readBytes(join(dirname(path), decodeURIComponent(uri)))]);
}

// Reads a mesh file: OBJ (bytes straight into the WASM heap); STL, PLY, OFF, glTF, GLB by
// extension or content. Errors name the file.
async function loadMesh(mrvol, path) {
  if (/\.obj$/i.test(path)) return readObjWithProgress(mrvol, path);
  const bytes = await readFileWithProgress(path);
  try {
    return mrvol.readMesh(bytes, { name: path, resources: /\.gltf$/i.test(path) ? gltfResources(path, bytes) : undefined });
  } catch (e) {
    if (e instanceof MrvolError) throw new MrvolError(`${path}: ${e.message}`);
    throw e;
  }
}

// Writes a mesh in the format of the output file's extension: .glb (keeping a glTF source's
// data when given), else OBJ.
function writeMesh(mrvol, path, mesh, source) {
  if (/\.glb$/i.test(path)) return writeBytes(path, mrvol.writeGlb(mesh, { source }));
  if (/\.(stl|ply|off|gltf)$/i.test(path)) throw new UsageError(`cannot write ${path}: mrvol writes .obj and .glb`);
  writeText(path, mrvol.writeObj(mesh));
}

async function openMultires(mrvol, path, mesh = null, { quadNote = false } = {}) {
  mesh ??= await loadMesh(mrvol, path);
  try {
    const mr = Object.assign(during(`finding the levels of ${path}`, () => mrvol.openMesh(mesh)), { source: mesh.source });
    // A file of quads read as triangles has no levels (every vertex a cage vertex) where its quads
    // may have Catmull-Clark ones: said on stderr, the command going on as asked.
    if (quadNote && mr.levels === 0 && isAllQuads(mesh, mr.info().faces)) {
      const levels = await catmullClarkLevels(mrvol, path, QUAD_CLI);
      if (levels > 0)
        process.stderr.write(`mrvol: note: ${path} is read as triangles, which have no levels here (every vertex is a cage vertex); ` +
                             `its quads have ${levels} Catmull-Clark levels: add --scheme catmull-clark to edit them as quads\n`);
    }
    return mr;
  } catch (e) {
    // A mesh the repair mends (a stray vertex, a degenerate or non-manifold face): said where to go.
    const mendable = /is not used by any face|is degenerate|non-manifold/.test(e.message);
    if (e instanceof MrvolError)
      throw new MrvolError(`${path}: ${e.message}${mendable ? ` (mrvol remesh ${path} --repair -o OUT.obj mends it)` : ''}`);
    throw e;
  }
}

/** Whether every face of the file was a quad (each split into 2 of the mesh's `faces` triangles). */
const isAllQuads = (mesh, faces) => mesh.polygons > 0 && 2 * mesh.polygons === mesh.polygonTriangles && mesh.polygonTriangles === faces;

// theta^e with a progress bar.
function computeTheta(mr, options) {
  const bar = progress(`theta^${options.level} (${options.scheme} scheme)`);
  try {
    return mr.computeTheta({ ...options, onProgress: (fraction) => (bar.update(fraction), true) });
  } finally {
    bar.done();
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
async function tensorReport(mrvol, values, positionals, { requireOutput }) {
  const path = onePath(positionals, 'MESH.obj');
  const level = integer(values.level, 'level', 0);
  const scheme = schemeOptions(values);
  const storage = storageOption(values);
  const surface = values.surface ?? 'mesh';
  if (surface !== 'mesh' && surface !== 'limit') throw new UsageError(`--surface must be mesh or limit, got '${surface}'`);
  if (requireOutput && !values.output) throw new UsageError('-o FILE.theta is required');
  if (values.theta && values.storage) throw new UsageError('--storage applies when computing, not with --theta');
  const mr = await openMultires(mrvol, path, null, { quadNote: true });
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
      if (theta.info().surface !== surface)
        throw new MrvolError(`${values.theta}: the theta file holds the volume of the ${theta.info().surface} surface, not of the ${surface} surface (--surface)`);
    } else {
      theta = computeTheta(mr, { level, storage, surface, ...scheme });
    }
    let thetaVolume;
    try {
      thetaVolume = mr.thetaVolume(theta, { level, ...scheme });
    } catch (e) {
      throw e instanceof MrvolError && values.theta ? new MrvolError(`${values.theta}: ${e.message}`) : e;
    }
    const info = theta.info();
    const result = {
      volume: mr.info({ surface }).volume, thetaVolume, surface: info.surface, scheme: scheme.scheme, level, storage: info.storage,
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
          `theta           ${r.scheme} scheme, level ${r.level}, ${r.storage} storage${r.surface === 'limit' ? ', limit surface' : ''} (${r.source})`,
          `entries         ${r.nnzStored} stored, ${r.nnzFull ?? 'unknown (cage storage)'} non-zeros in the full tensor`,
          `memory          ${r.bytes} bytes` + (r.precomputeMs != null ? `, computed in ${r.precomputeMs} ms` : '')]
    .concat(r.output ? [`wrote           ${r.output} (${r.fileBytes} bytes)`] : []).join('\n');
}

const COMMANDS = {
  async info(mrvol, values, positionals) {
    const path = onePath(positionals, 'MESH.obj');
    const mesh = await loadMesh(mrvol, path);
    const mr = await openMultires(mrvol, path, mesh);
    const i = mr.info();
    mr.delete();
    const result = {
      vertices: i.vertices, faces: i.faces, levels: i.levels, baseVertices: i.baseVertices,
      baseVertexIndices: Array.from(i.baseVertexIndices), closed: i.closed, boundaryEdges: i.boundaryEdges,
      genus: i.genus, volume: i.volume, semiRegular: i.levels > 0, polygons: mesh.polygons,
      polygonTriangles: mesh.polygonTriangles,
      // (an OBJ whose faces refer to vt / vn lines it does not have: those attributes are not read)
      ...(mesh.dropped ? { leftOut: mesh.dropped } : {}),
      // Vertices at one position, welded on reading: a mesh split by its exporter (three.js's
      // OBJExporter writes a vertex per face corner; every STL does).
      ...(mesh.welded > 0 ? { welded: mesh.welded } : {}),
      ...(mesh.format ? { format: mesh.format } : {}),
    };
    // A file of quads only, without 1-to-4 splits of its triangles: its quads may have Catmull-Clark
    // levels (--scheme catmull-clark), which the hint names rather than the remesher.
    const allQuads = isAllQuads(mesh, i.faces);
    if (allQuads && !result.semiRegular) result.catmullClarkLevels = await catmullClarkLevels(mrvol, path, QUAD_CLI);
    const notSemiRegular = (r) => r.catmullClarkLevels > 0
      ? `no (as triangles; its quads have ${r.catmullClarkLevels} Catmull-Clark levels: mrvol info ${path} --scheme catmull-clark)`
      : 'no (no 1-to-4 splits found: mrvol remesh makes a semi-regular mesh)';
    print(values, result, (r) => [
      `vertices       ${r.vertices}`, `faces          ${r.faces}`, `levels         ${r.levels}`,
      `semi-regular   ${r.semiRegular ? 'yes' : notSemiRegular(r)}`,
      ...(r.polygons > 0 ? [`polygons       ${r.polygons} (triangulated into ${r.polygonTriangles} triangles)`] : []),
      ...(r.leftOut ? [`left out       ${r.leftOut}`] : []),
      `base vertices  ${r.baseVertices}`, `closed         ${r.closed}`, `boundary edges ${r.boundaryEdges}`,
      ...(r.welded > 0 ? [`welded         ${r.welded} vertices at the position of another (${r.format === 'stl'
        ? 'an STL gives each triangle its own three' : 'split by the exporter'})`] : []),
      // (A genus is a closed surface's: an open one's Euler count says nothing the boundary does not.)
      `genus          ${r.closed ? r.genus : '- (not a closed surface)'}`,
      `volume         ${r.volume}${r.closed ? '' : ' (open: the cones from the origin to its faces)'}`].join('\n'));
  },

  async subdivide(mrvol, values, positionals) {
    const input = onePath(positionals, 'BASE.obj');
    const levels = integer(values.levels, 'levels');
    if (levels < 0 || levels > 12) throw new UsageError(`--levels must be in 0..12, got ${levels}`);
    const scheme = schemeOptions(values);
    if (!values.output) throw new UsageError('-o OUT.obj is required');
    const base = await loadMesh(mrvol, input);
    const mr = during(`subdividing ${input} (${levels} level${levels === 1 ? "" : "s"})`, () => mrvol.subdivide(base, { levels, ...scheme }));
    const mesh = mr.toMesh();
    const info = mr.info();
    mr.delete();
    during(`writing ${values.output}`, () => writeMesh(mrvol, values.output, mesh));
    const result = { vertices: info.vertices, faces: info.faces, levels, scheme: values.scheme ?? 'loop',
                     volume: info.volume, output: values.output };
    print(values, result, (r) => `wrote ${r.output}: ${r.vertices} vertices, ${r.faces} faces (${r.scheme}, ${r.levels} levels)`);
  },

  async roundtrip(mrvol, values, positionals) {
    const path = onePath(positionals, 'MESH.obj');
    const level = integer(values.level, 'level', 0);
    const scheme = schemeOptions(values);
    const mr = await openMultires(mrvol, path, null, { quadNote: true });
    const maxError = mr.roundtripError({ level, ...scheme });
    const positions = mr.positions();
    mr.delete();
    let scale = 0;
    for (const x of positions) scale = Math.max(scale, Math.abs(x));
    const result = { scheme: scheme.scheme, level, maxError, relativeError: scale > 0 ? maxError / scale : maxError };
    print(values, result, (r) => `max reconstruction error ${r.maxError} (relative ${r.relativeError}), ${r.scheme} scheme, level ${r.level}`);
  },
};

function parseMoves(values) {
  if (!values.move?.length) throw new UsageError('at least one --move V:dx,dy,dz is required');
  return values.move.map((text) => {
    const m = /^(\d+):([^,]+),([^,]+),([^,]+)$/.exec(text);
    if (!m) throw new UsageError(`--move expects V:dx,dy,dz (for example 3:0.1,0,-0.2), got '${text}'`);
    const offset = [m[2], m[3], m[4]].map((x) => number(x, 'move'));
    return { vertex: Number(m[1]), offset };
  });
}

/** A vertex both moved and listed in --free was let go by the correction: named instead. */
function checkFreeNotMoved(freeList, moves) {
  const moved = freeList && moves.find((m) => freeList.includes(m.vertex));
  if (moved) throw new UsageError(`--free lists vertex ${moved.vertex}, which --move moves: a moved vertex is held where it is put (leave it out of --free)`);
}

function parseList(text, name) {
  const items = text.split(',').map((x) => x.trim());
  if (items.some((x) => !/^\d+$/.test(x))) throw new UsageError(`--${name} expects a comma-separated list of integers, got '${text}'`);
  return items.map(Number);
}

COMMANDS.edit = async (mrvol, values, positionals) => {
  const path = onePath(positionals, 'MESH.obj');
  const level = integer(values.level, 'level', 0);
  const scheme = schemeOptions(values);
  const moves = parseMoves(values);
  if (!values.output) throw new UsageError('-o OUT.obj is required');
  const tolerance = values.tolerance === undefined ? 1e-5 : number(values.tolerance, 'tolerance');
  if (!(tolerance > 0 && tolerance < 1)) throw new UsageError('--tolerance must be between 0 and 1');
  const gradientPath = values.path ?? 'auto';
  if (!['auto', 'polynomial', 'tensor', 'matrix-free'].includes(gradientPath))
    throw new UsageError(`--path must be auto, polynomial, tensor or matrix-free, got '${gradientPath}'`);
  const free = values.free ?? 'cage';
  const freeList = free === 'cage' || free === 'all' ? null : parseList(free, 'free');
  checkFreeNotMoved(freeList, moves);
  const detailLevels = values['free-details'] ? parseList(values['free-details'], 'free-details') : [];
  const surface = values.surface ?? 'mesh';
  if (surface !== 'mesh' && surface !== 'limit') throw new UsageError(`--surface must be mesh or limit, got '${surface}'`);
  const keep = (values.keep ?? 'volume').split(',').map((k) => k.trim());
  if (keep.some((k) => k !== 'volume' && k !== 'centroid') || !keep.includes('volume'))
    throw new UsageError(`--keep expects volume or volume,centroid, got '${values.keep}'${keep.includes('inertia') ? ' (the inertia tensor is not kept yet)' : ''}`);
  const centroid = keep.includes('centroid');
  if (detailLevels.length > 0 && (gradientPath === 'tensor' || gradientPath === 'polynomial' || values.theta))
    throw new UsageError('--free-details runs matrix-free (--path auto or matrix-free, no --theta)');
  if (centroid && (gradientPath === 'tensor' || gradientPath === 'polynomial' || values.theta))
    throw new UsageError('--keep centroid runs matrix-free (--path auto or matrix-free, no --theta)');
  if (centroid && surface === 'limit')
    throw new UsageError('--keep centroid keeps the mesh surface\'s centre of mass: not with --surface limit (keep the volume only there)');
  if (surface === 'limit' && gradientPath === 'polynomial')
    throw new UsageError('--path polynomial sums the mesh\'s triangles: with --surface limit use --path auto or matrix-free (or --theta of the limit surface)');
  const mr = await openMultires(mrvol, path, null, { quadNote: true });
  let theta;
  try {
    if (level < 0 || level > mr.levels)
      throw new MrvolError(`level ${level} is out of range: ${path} has levels 0..${mr.levels}`);
    // auto: the polynomial built from the mesh (no theta) on a coarse cage, else matrix-free; the
    // limit surface and the centre of mass run matrix-free unless given a theta.
    const chosen = values.theta ? 'tensor'
      : (surface === 'limit' || centroid) && gradientPath === 'auto' ? 'matrix-free'
      : chooseGradientPath(mr, { level, path: gradientPath, detailLevels, ...scheme }).path;
    const preserve = values['no-preserve'] === undefined;
    const editor = during(`making the editor of ${path} (level ${level}, ${mr.vertexCount} vertices)`,
                          () => mr.createEditor({ level, ...scheme, surface, keep,
                                                  path: chosen === 'polynomial' && preserve ? 'polynomial' : 'matrix-free' }));
    // The centre of mass before and after (null where it is undefined: a solid of zero volume).
    const centroidOf = () => {
      try {
        return Array.from(editor.centroid());
      } catch (e) {
        if (e instanceof MrvolError) return null;
        throw e;
      }
    };
    const centroidBefore = centroidOf();
    editor.setFreeSet({ cage: freeList ?? (free === 'all' ? 'all' : 'minus-held'), detailLevels });
    const wantTensor = chosen === 'tensor';
    if (wantTensor && preserve) {
      if (values.theta) {
        try {
          theta = mrvol.readTheta(readBytes(values.theta));
          editor.useTheta(theta);
        } catch (e) {
          throw e instanceof MrvolError && !e.message.startsWith('cannot read') ? new MrvolError(`${values.theta}: ${e.message}`) : e;
        }
      } else {
        theta = computeTheta(mr, { level, surface, ...scheme });
        editor.useTheta(theta);
      }
    }
    const started = performance.now();
    const report = during('moving the cage', () => editor.moveVertices(moves, { tolerance, preserve: !values['no-preserve'] }));
    const stepMs = performance.now() - started;
    if (!report.converged) throw new MrvolError(`the volume correction did not converge: ${report.message}`);
    // An OBJ written as OBJ keeps every other line of the input (vt, vn, groups, materials).
    during(`writing ${values.output}`, () => {
      if (/\.obj$/i.test(path) && !/\.glb$/i.test(values.output))
        writeText(values.output, mrvol.writeObjLike(readBytes(path), editor.positions()));
      else writeMesh(mrvol, values.output, { positions: editor.positions(), faces: mr.faces() }, mr.source);
    });
    const result = {
      volumeReference: report.volumeReference, volumeTarget: report.volumeTarget, volumeResult: report.volumeResult,
      relativeError: report.relativeError, iterations: report.iterations, substeps: report.substeps,
      stepMs: Math.round(stepMs * 1000) / 1000, path: values['no-preserve'] ? 'none' : report.path,
      surface, keep, centroidBefore, centroidAfter: centroidOf(),
      output: values.output,
    };
    const drift = centroidBefore && result.centroidAfter ? Math.hypot(...result.centroidAfter.map((x, k) => x - centroidBefore[k])) : null;
    print(values, result, (r) => [
      `reference volume ${r.volumeReference}${surface === 'limit' ? ' (limit surface)' : ''}`, `target volume    ${r.volumeTarget}`,
      `result volume    ${r.volumeResult} (relative error ${r.relativeError})`,
      ...(drift === null ? [] : [`centre of mass   ${r.centroidBefore.join(' ')} -> ${r.centroidAfter.join(' ')} (moved ${drift}${centroid ? ', kept' : ''})`]),
      `correction       ${r.iterations} iterations, ${r.substeps} sub-steps, ${r.stepMs} ms, ${r.path} gradient`,
      `wrote            ${r.output}`].join('\n'));
  } finally {
    theta?.delete();
    mr.delete();
  }
};

COMMANDS.remesh = async (mrvol, values, positionals) => {
  const input = onePath(positionals, 'IN.obj');
  // Without --levels: as many as keep the input's detail (lib/remesh.mjs).
  const levels = values.levels === undefined ? undefined : integer(values.levels, 'levels');
  if (levels < 0 || levels > 6) throw new UsageError(`--levels must be in 0..6, got ${levels}`);
  const baseFaces = values['base-faces'] === undefined ? undefined : integer(values['base-faces'], 'base-faces');
  if (baseFaces !== undefined && baseFaces < 4) throw new UsageError(`--base-faces must be at least 4, got ${baseFaces}`);
  const maxHoleEdges = values['max-hole'] === undefined ? undefined : integer(values['max-hole'], 'max-hole');
  if (maxHoleEdges !== undefined && (maxHoleEdges < 3 || !values.repair)) throw new UsageError('--max-hole needs --repair and at least 3 edges');
  const smooth = values.smooth === undefined ? 0 : integer(values.smooth, 'smooth');
  if (smooth < 0 || (smooth > 0 && !values.repair)) throw new UsageError('--smooth needs --repair and a count >= 0');
  if (!values.output) throw new UsageError('-o OUT.obj is required');
  const mesh = await loadMesh(mrvol, input);
  // Loaded here: the other commands do without three.js, three-mesh-bvh and meshoptimizer.
  const { remesh } = await import('../lib/remesh.mjs');
  const bar = progress(`remeshing ${input}`);
  let r;
  try {
    r = await remesh(mrvol, mesh, { levels, baseFaces, keepLargest: values['keep-largest'] ?? false,
                                    repair: values.repair ?? false, maxHoleEdges, smooth,
                                    onProgress: (fraction, stage) => bar.update(fraction, `remeshing ${input}: ${stage}`) });
  } catch (e) {
    throw e instanceof MrvolError ? new MrvolError(`${input}: ${e.message}`) : e;
  } finally {
    bar.done();
  }
  during(`writing ${values.output}`, () => writeMesh(mrvol, values.output, r.mesh));
  const round = (x, d) => Math.round(x * 10 ** d) / 10 ** d;
  const result = {
    levels: r.levels, baseVertices: r.baseVertices, baseFaces: r.baseFaces, vertices: r.vertices, faces: r.faces,
    hausdorff: r.hausdorff, hausdorffToInput: r.hausdorffToInput, hausdorffFromInput: r.hausdorffFromInput,
    flippedTriangles: r.flippedTriangles, volumeChange: r.volumeChange, volumeChangeFromUnsmoothed: r.volumeChangeFromUnsmoothed,
    ms: round(r.ms, 1), output: values.output,
    genus: r.input.genus, components: r.components, features: r.features, untangledTriangles: r.untangledTriangles,
    droppedPieces: r.input.droppedPieces, repair: r.repair, fit: r.fit, parametrisedFallback: r.parametrisedFallback,
    baseGrown: r.baseGrown,
  };
  print(values, result, (x) => [
    `wrote            ${x.output}: ${x.vertices} vertices, ${x.faces} faces, ${x.levels} levels over ${x.baseVertices} base vertices`,
    `hausdorff        ${round(100 * x.hausdorff, 3)}% of the bounding-box diagonal (to input ${round(100 * x.hausdorffToInput, 3)}%, from input ${round(100 * x.hausdorffFromInput, 3)}%)`,
    ...(x.baseGrown ? [`base grown       the first fit on --base-faces ${x.baseGrown.asked} folded: the base was made larger (${x.baseFaces} faces)`] : []),
    `flipped          ${x.flippedTriangles} triangles`,
    `fit              ${x.fit}${x.parametrisedFallback ? ` (parametrised fallback ${x.parametrisedFallback.error ?? `${round(100 * x.parametrisedFallback.hausdorff, 3)}%`}, ${x.parametrisedFallback.kept ? 'kept' : 'not kept'})` : ''}`,
    `volume change    ${round(100 * x.volumeChange, 4)}%${x.volumeChangeFromUnsmoothed === null ? '' : ` (of the smoothed surface fitted; from the input before smoothing ${round(100 * x.volumeChangeFromUnsmoothed, 4)}%)`}`,
    ...(x.repair?.smoothing ? [`smoothing        ${x.repair.smoothIterations} Taubin steps moved vertices up to ${round(100 * x.repair.smoothing.largestMove, 3)}% of the diagonal (the distances above are to the smoothed surface)`] : []),
    `pieces           ${x.components} component(s), genus ${x.genus}${x.droppedPieces ? `, ${x.droppedPieces} empty piece(s) dropped` : ''}`,
    `features         ${x.features.edges} crease edges, ${x.features.corners} corners (${x.features.cornerVertices} base corners held, ${x.features.creaseVertices} vertices on creases)`,
    ...(x.repair ? [`repaired         ${Object.entries(x.repair).filter(([k, v]) => v && k !== 'smoothing').map(([k, v]) => `${k} ${v}`).join(', ') || 'nothing'}`] : []),
    `time             ${x.ms} ms`].join('\n'));
};

COMMANDS.volume = async (mrvol, values, positionals) =>
  print(values, await tensorReport(mrvol, values, positionals, { requireOutput: false }), describeTensor);
COMMANDS.theta = async (mrvol, values, positionals) =>
  print(values, await tensorReport(mrvol, values, positionals, { requireOutput: true }), describeTensor);

// What the catmull-clark commands (bin/quad-commands.mjs) share with the others.
const QUAD_CLI = { UsageError, onePath, integer, number, print, readBytes, writeText, writeBytes, parseMoves, checkFreeNotMoved, describeTensor,
                   loadMesh, parseList };

/**
 * argv with a negative number after an option that takes a value joined to it (`--levels -1` as
 * `--levels=-1`): parseArgs calls it ambiguous, where the option's own check says what is wrong.
 */
function joinNegativeValues(argv) {
  const out = [];
  for (let i = 0; i < argv.length; i++) {
    const name = /^--[a-z-]+$/.test(argv[i]) ? argv[i].slice(2) : null;
    if (name && OPTIONS[name]?.type === 'string' && /^-\.?\d/.test(argv[i + 1] ?? '')) out.push(`${argv[i]}=${argv[++i]}`);
    else out.push(argv[i]);
  }
  return out;
}

/**
 * parseArgs' refusal in one line of our own words (its text spoke of positionals after '--'), with
 * where to look: the command's help when the command is known.
 */
function argumentError(e, argv) {
  const command = argv.find((a) => !a.startsWith('-') && Object.hasOwn(COMMAND_HELP, a));
  const help = command ? `mrvol help ${command}` : 'mrvol help';
  const option = /'(-[^' ]*)/.exec(e.message)?.[1];
  switch (e.code) {
    case 'ERR_PARSE_ARGS_UNKNOWN_OPTION': return `unknown option ${option ?? ''} (${help} lists the options)`;
    case 'ERR_PARSE_ARGS_INVALID_OPTION_VALUE':
      return option && /argument missing|ambiguous/.test(e.message) ? `${option} needs a value (${help})` : `${e.message.split('\n')[0]} (${help})`;
    default: return `${e.message.split('\n')[0]} (${help})`;
  }
}

export async function main(argv) {
  let values, positionals;
  try {
    ({ values, positionals } = parseArgs({ args: joinNegativeValues(argv), options: OPTIONS, allowPositionals: true, strict: true }));
  } catch (e) {
    process.stderr.write(`mrvol: error: ${argumentError(e, argv)}\n`);
    return 2;
  }
  if (values.version) {
    process.stdout.write(`mrvol ${VERSION}\n`);
    return 0;
  }
  if (positionals.length === 0) {
    (values.help ? process.stdout : process.stderr).write(usage() + '\n');
    return values.help ? 0 : 2;
  }
  const [command, ...rest] = positionals;
  const known = (name) => Object.hasOwn(COMMAND_HELP, name);
  if (!known(command)) {
    process.stderr.write(`mrvol: error: unknown command '${command}'\n${usage()}\n`);
    return 2;
  }
  // `mrvol help [COMMAND]` and `mrvol COMMAND --help`.
  if (command === 'help' || values.help) {
    const topic = command === 'help' ? rest[0] : command;
    if (command === 'help' && rest.length > 1) {
      process.stderr.write(`mrvol: error: unexpected argument '${rest[1]}'\n`);
      return 2;
    }
    if (topic !== undefined && !known(topic)) {
      process.stderr.write(`mrvol: error: unknown command '${topic}'; the commands: ${Object.keys(COMMAND_HELP).join(', ')}\n`);
      return 2;
    }
    process.stdout.write((topic === undefined || topic === 'help' ? usage() : commandUsage(topic)) + '\n');
    return 0;
  }
  try {
    checkCommandOptions(command, values);
    if (values.scheme === 'catmull-clark' && !QUAD_COMMANDS[command]) throw new UsageError(`${command} has no --scheme catmull-clark`);
    const threads = values.threads === undefined ? undefined : integer(values.threads, 'threads');
    if (threads !== undefined && (threads < 1 || threads > 16)) throw new UsageError(`--threads must be in 1..16, got ${threads}`);
    if (values.output !== undefined) checkOutputPath(values.output);
    // a format mrvol does not write, refused before the work (an edit or remesh of minutes failed only at the end)
    if (values.output !== undefined && ['subdivide', 'edit', 'remesh'].includes(command) && /\.(stl|ply|off|gltf)$/i.test(values.output))
      throw new UsageError(`cannot write ${values.output}: mrvol writes .obj and .glb${values.scheme === 'catmull-clark' ? ' (quad meshes: .obj)' : ''}`);
    const mrvol = await createMrvol({ threads });
    if (values.scheme === 'catmull-clark') await QUAD_COMMANDS[command](mrvol, values, rest, QUAD_CLI);
    else await COMMANDS[command](mrvol, values, rest);
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
