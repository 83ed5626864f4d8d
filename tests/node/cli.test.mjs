// The mrvol command line (bin/mrvol.mjs) run as a child process: info, subdivide and roundtrip
// with --json, the error contract (exit 1 with one line `mrvol: error: ...`, exit 2 on bad
// usage), --version and help, and the progress bar (its renderer, and the command on a terminal
// through util-linux `script` and piped). Test meshes are made with the JS API and written to a
// fresh temporary folder.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { writeFileSync, readFileSync, existsSync, openSync, closeSync } from 'node:fs';
import { join } from 'node:path';
import { createMrvol } from '../../lib/node.mjs';
import { Progress, renderProgress } from '../../bin/progress.mjs';
import {
  ROOT, CLI, model, tempFolder, runCliSync, json, failsWith, usageError, icosahedron, rng, shuffleMesh,
} from './helpers.mjs';

// The CLI waits at most 30 s per run here.
const mrvolCli = (...args) => runCliSync(args, { timeout: 30000 });

let mrvol;
const file = tempFolder('mrvol-cli-test-');

before(async () => {
  mrvol = await createMrvol();
  writeFileSync(file('ico.obj'), mrvol.writeObj(icosahedron()));
});

// ---- info --------------------------------------------------------------------------------------

describe('info', () => {
  test('--json on a shuffled subdivided mesh: exact fields, base vertices in file order', () => {
    const built = mrvol.subdivide(icosahedron(), { levels: 3, scheme: 'butterfly' });
    const { mesh, perm } = shuffleMesh(built.toMesh(), 42);
    const volume = built.info().volume;
    built.delete();
    writeFileSync(file('shuffled.obj'), mrvol.writeObj(mesh));
    const r = json(mrvolCli('info', file('shuffled.obj'), '--json'));
    assert.deepEqual(Object.keys(r).sort(),
      ['baseVertexIndices', 'baseVertices', 'boundaryEdges', 'closed', 'faces', 'genus', 'levels', 'polygonTriangles',
       'polygons', 'semiRegular', 'vertices', 'volume']);
    assert.equal(r.semiRegular, true);
    assert.equal(r.polygons, 0);
    assert.equal(r.vertices, 642);
    assert.equal(r.faces, 1280);
    assert.equal(r.levels, 3);
    assert.equal(r.baseVertices, 12);
    // 0-based indices, in file order, of the vertices that were the icosahedron's.
    assert.deepEqual(r.baseVertexIndices, perm.slice(0, 12).sort((a, b) => a - b));
    const lines = readFileSync(file('shuffled.obj'), 'utf8').split('\n');
    for (const [k, i] of r.baseVertexIndices.entries()) {
      const v = perm.indexOf(i);
      assert.ok(v < 12, `file vertex ${i} (listed ${k}th) is a base vertex`);
      assert.deepEqual(lines[i].split(' ').slice(1).map(Number), Array.from(icosahedron().positions.subarray(3 * v, 3 * v + 3)));
    }
    assert.equal(r.closed, true);
    assert.equal(r.boundaryEdges, 0);
    assert.equal(r.genus, 0);
    assert.ok(Math.abs(r.volume - volume) < 1e-12 * volume);
  });

  test('plain text output and an open mesh', () => {
    // The icosahedron with one face removed: 3 boundary edges, not closed.
    const m = icosahedron();
    writeFileSync(file('open.obj'), mrvol.writeObj({ positions: m.positions, faces: m.faces.subarray(3) }));
    const r = json(mrvolCli('info', '--json', file('open.obj')));
    assert.equal(r.closed, false);
    assert.equal(r.boundaryEdges, 3);
    assert.equal(r.levels, 0);
    assert.deepEqual(r.baseVertexIndices, Array.from({ length: 12 }, (_, i) => i));
    const text = mrvolCli('info', file('ico.obj'));
    assert.equal(text.status, 0);
    assert.equal(text.stderr, '');
    assert.match(text.stdout, /^vertices\s+12$/m);
    assert.match(text.stdout, /^faces\s+20$/m);
    assert.match(text.stdout, /^levels\s+0$/m);
    assert.match(text.stdout, /^genus\s+0$/m);
  });

  test('a mesh whose vertices repeat positions (split by its exporter) is welded and says so; a stray vertex names the repair', () => {
    // The icosahedron as three.js's OBJExporter writes a non-indexed geometry: three vertices per face.
    const m = icosahedron();
    const positions = Float64Array.from(Array.from(m.faces).flatMap((v) => Array.from(m.positions.subarray(3 * v, 3 * v + 3))));
    writeFileSync(file('split.obj'), mrvol.writeObj({ positions, faces: Uint32Array.from({ length: 60 }, (_, i) => i) }));
    const r = json(mrvolCli('info', '--json', file('split.obj')));
    assert.deepEqual([r.vertices, r.closed, r.genus, r.welded], [12, true, 0, 48]);
    assert.match(mrvolCli('info', file('split.obj')).stdout, /^welded\s+48 vertices at the position of another \(split by the exporter\)$/m);
    assert.equal(json(mrvolCli('info', '--json', file('ico.obj'))).welded, undefined, 'nothing welded: not said');
    // the same triangles as a binary STL: welded because the format splits them
    const stl = Buffer.alloc(84 + 50 * 20);
    stl.writeUInt32LE(20, 80);
    positions.forEach((x, i) => stl.writeFloatLE(x, 84 + 50 * Math.floor(i / 9) + 12 + 4 * (i % 9)));
    writeFileSync(file('split.stl'), stl);
    assert.match(mrvolCli('info', file('split.stl')).stdout, /^welded\s+48 vertices at the position of another \(an STL gives each triangle its own three\)$/m);
    writeFileSync(file('stray.obj'), `${mrvol.writeObj(m)}v 5 5 5\n`);
    failsWith(mrvolCli('info', file('stray.obj')), /vertex 12 \(line \d+\) is not used by any face \(mrvol remesh .*stray\.obj --repair -o OUT\.obj mends it\)$/);
  });
});

// ---- subdivide ---------------------------------------------------------------------------------

describe('subdivide', () => {
  for (const scheme of ['loop', 'butterfly', 'linear'])
    test(`${scheme}: -o OUT.obj, then info detects the levels; vertex order kept`, () => {
      const out = file(`sub-${scheme}.obj`);
      const r = json(mrvolCli('subdivide', file('ico.obj'), '--levels', '2', '--scheme', scheme, '-o', out, '--json'));
      assert.equal(r.vertices, 162);
      assert.equal(r.faces, 320);
      assert.equal(r.levels, 2);
      assert.equal(r.scheme, scheme);
      assert.equal(r.output, out);
      const info = json(mrvolCli('info', out, '--json'));
      assert.equal(info.levels, 2);
      assert.equal(info.vertices, 162);
      assert.deepEqual(info.baseVertexIndices, Array.from({ length: 12 }, (_, i) => i), 'the base comes first');
      assert.ok(Math.abs(info.volume - r.volume) < 1e-12 * Math.abs(r.volume));
      const written = mrvol.readObj(readFileSync(out, 'utf8'));
      const base = icosahedron().positions;
      if (scheme !== 'loop') assert.deepEqual(written.positions.subarray(0, 36), base, 'interpolating: base positions exactly');
      else assert.notDeepEqual(written.positions.subarray(0, 36), base, 'Loop moves the base vertices');
      // Same as the API's subdivision.
      const api = mrvol.subdivide(icosahedron(), { levels: 2, scheme });
      assert.deepEqual(written.positions, api.positions());
      assert.deepEqual(written.faces, api.faces());
      api.delete();
    });

  test('--output long form, --alpha/--beta and text output', () => {
    const out = file('sub-plain.obj');
    const r = mrvolCli('subdivide', file('ico.obj'), '--levels', '1', '--alpha', '0', '--beta', '0', '--output', out);
    assert.equal(r.status, 0, r.stderr);
    assert.match(r.stdout, /^wrote .*sub-plain\.obj: 42 vertices, 80 faces/);
    const api = mrvol.subdivide(icosahedron(), { levels: 1, alpha: 0, beta: 0 });
    assert.deepEqual(mrvol.readObj(readFileSync(out, 'utf8')).positions, api.positions());
    api.delete();
  });
});

// ---- roundtrip ---------------------------------------------------------------------------------

describe('roundtrip', () => {
  test('--json: tiny error; --scheme and --level are honoured', () => {
    // A 2-level mesh with random positions in a random vertex order: every scheme has details.
    const built = mrvol.subdivide(icosahedron(), { levels: 2 });
    const r = rng(9);
    const positions = Float64Array.from({ length: 3 * built.vertexCount }, () => 2 * r() - 1);
    const { mesh } = shuffleMesh({ positions, faces: built.faces() }, 5);
    built.delete();
    writeFileSync(file('random.obj'), mrvol.writeObj(mesh));
    const mr = mrvol.openMesh(mesh);
    for (const [scheme, level] of [['loop', 0], ['butterfly', 1], ['linear', 2]]) {
      const res = json(mrvolCli('roundtrip', file('random.obj'), '--scheme', scheme, '--level', String(level), '--json'));
      assert.deepEqual(Object.keys(res).sort(), ['level', 'maxError', 'relativeError', 'scheme']);
      assert.equal(res.scheme, scheme);
      assert.equal(res.level, level);
      assert.ok(res.maxError < 1e-12, `${scheme} level ${level}: ${res.maxError}`);
      assert.ok(res.relativeError >= res.maxError && res.relativeError <= res.maxError / 0.9);
      // The very computation of the API with these options.
      assert.equal(res.maxError, mr.roundtripError({ scheme, level }));
    }
    const def = json(mrvolCli('roundtrip', file('random.obj'), '--json'));
    assert.equal(def.scheme, 'loop');
    assert.equal(def.level, 0);
    assert.equal(def.maxError, mr.roundtripError());
    // Text output; --alpha/--beta honoured (the number printed is the JS number, exactly).
    const text = mrvolCli('roundtrip', file('random.obj'), '--alpha', '0', '--beta', '0', '--level', '1');
    assert.equal(text.status, 0, text.stderr);
    const m = text.stdout.match(/^max reconstruction error (\S+) \(relative \S+\), loop scheme, level 1\n$/);
    assert.ok(m, text.stdout);
    assert.equal(Number(m[1]), mr.roundtripError({ alpha: 0, beta: 0, level: 1 }));
    mr.delete();
  });

  test('a level beyond the mesh\'s is an error', () => {
    failsWith(mrvolCli('roundtrip', file('ico.obj'), '--level', '1'), /level 1 is out of range/);
  });
});

// ---- errors ------------------------------------------------------------------------------------

describe('errors', () => {
  test('missing file: exit 1, one line', () => {
    const missing = file('does-not-exist.obj');
    failsWith(mrvolCli('info', missing), /does-not-exist\.obj/);
    failsWith(mrvolCli('subdivide', missing, '--levels', '1', '-o', file('never.obj')), /does-not-exist\.obj/);
    assert.ok(!existsSync(file('never.obj')));
  });

  test('invalid OBJ or mesh: exit 1, one line naming the file', () => {
    writeFileSync(file('quad.obj'), 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 1 3\n');
    failsWith(mrvolCli('info', file('quad.obj')), /quad\.obj: line 5: polygon with 4 vertices uses vertex 1 more than once/);
    writeFileSync(file('flip.obj'), 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 4 3\nf 2 3 4\n');
    failsWith(mrvolCli('info', file('flip.obj'), '--json'), /flip\.obj: inconsistent orientation/);
    // (A level count past 0..12 is a malformed argument: exit 2, as remesh's --levels.)
    usageError(mrvolCli('subdivide', file('ico.obj'), '--levels', '13', '-o', file('big.obj')), /^mrvol: error: --levels must be in 0\.\.12, got 13$/);
  });

  test('a negative number given to an option: the option\'s own message', () => {
    usageError(mrvolCli('remesh', file('ico.obj'), '--levels', '-1', '-o', file('never.obj')), /^mrvol: error: --levels must be in 0\.\.6, got -1$/);
    usageError(mrvolCli('remesh', file('ico.obj'), '--base-faces', '-5', '-o', file('never.obj')), /^mrvol: error: --base-faces must be at least 4, got -5$/);
    usageError(mrvolCli('subdivide', file('ico.obj'), '--levels', '-2', '-o', file('never.obj')), /^mrvol: error: --levels must be in 0\.\.12, got -2$/);
    assert.ok(!existsSync(file('never.obj')));
  });

  test('info of an open surface: no genus, its volume said to be the cones\' from the origin', () => {
    writeFileSync(file('open-tet.obj'), 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n');
    const text = mrvolCli('info', file('open-tet.obj')).stdout;
    assert.match(text, /^closed {9}false$/m);
    assert.match(text, /^genus {10}- \(not a closed surface\)$/m);
    assert.match(text, /^volume {9}0\.1666+7? \(open: the cones from the origin to its faces\)$/m);
    assert.match(mrvolCli('info', file('ico.obj')).stdout, /^genus {10}0$/m);
  });

  test('output that cannot be written: exit 1, said before any work', () => {
    failsWith(mrvolCli('subdivide', file('ico.obj'), '--levels', '1', '-o', file(join('no', 'such', 'dir.obj'))),
              new RegExp(`cannot write .*dir\\.obj: no such directory .*${join('no', 'such')}`));
    // Checked before the work: a remesh, an edit and a theta name the folder, not a file error after minutes.
    const missing = file(join('missing', 'out.obj'));
    failsWith(mrvolCli('remesh', file('ico.obj'), '-o', missing), /cannot write .*out\.obj: no such directory/);
    failsWith(mrvolCli('edit', file('ico.obj'), '--move', '0:0.1,0,0', '-o', missing), /cannot write .*out\.obj: no such directory/);
    failsWith(mrvolCli('theta', file('ico.obj'), '-o', file(join('missing', 'x.theta'))), /cannot write .*x\.theta: no such directory/);
    failsWith(mrvolCli('subdivide', file('ico.obj'), '--levels', '1', '-o', file('')), /cannot write .*: it is a directory/);
    failsWith(mrvolCli('subdivide', file('ico.obj'), '--levels', '1', '-o', join(file('ico.obj'), 'x.obj')), /cannot write .*x\.obj: .*ico\.obj is not a directory/);
    // a format mrvol does not write: usage, before any work (and nothing written)
    for (const [command, ...args] of [['edit', '--move', '0:0.1,0,0'], ['remesh'], ['subdivide', '--levels', '1']])
      for (const ext of ['ply', 'stl', 'off', 'gltf']) {
        const out = file(`out-${command}.${ext}`);
        usageError(mrvolCli(command, file('ico.obj'), ...args, '-o', out), new RegExp(`cannot write .*out-${command}\\.${ext}: mrvol writes \\.obj and \\.glb`));
        assert.equal(existsSync(out), false);
      }
  });

  test('bad usage: exit 2', () => {
    usageError(mrvolCli());
    usageError(mrvolCli('frobnicate', file('ico.obj')), /^mrvol: error: unknown command 'frobnicate'/);
    usageError(mrvolCli('info'), /^mrvol: error: missing MESH\.obj/);
    usageError(mrvolCli('info', file('ico.obj'), file('ico.obj')), /^mrvol: error: unexpected argument/);
    // One line in our words (not parseArgs' text about positionals after '--', then the whole usage).
    const bogus = mrvolCli('info', file('ico.obj'), '--bogus');
    usageError(bogus, /^mrvol: error: unknown option --bogus \(mrvol help info lists the options\)$/);
    assert.equal(bogus.stderr.trim().split('\n').length, 1);
    usageError(mrvolCli('remesh', file('ico.obj'), '--levels'), /^mrvol: error: --levels needs a value \(mrvol help remesh\)$/);
    usageError(mrvolCli('remesh', file('ico.obj'), '--levels', '-o', file('x.obj')), /^mrvol: error: --levels needs a value \(mrvol help remesh\)$/);
    usageError(mrvolCli('subdivide', file('ico.obj'), '-o', file('x.obj')), /^mrvol: error: --levels is required/);
    usageError(mrvolCli('subdivide', file('ico.obj'), '--levels', '1'), /-o OUT\.obj is required/);
    usageError(mrvolCli('subdivide', file('ico.obj'), '--levels', '1', '--scheme', 'cubic', '-o', file('x.obj')),
      /--scheme must be loop, butterfly or linear/);
    usageError(mrvolCli('roundtrip', file('ico.obj'), '--level', '1.5'), /--level expects an integer/);
    usageError(mrvolCli('roundtrip', file('ico.obj'), '--level'), /^mrvol: error: /);
    // Another command's option, a scheme the command does not take, Loop's weights with another
    // scheme: named (they were ignored without a word, exit 0).
    usageError(mrvolCli('remesh', file('ico.obj'), '--level', '2', '-o', file('x.obj')),
      /^mrvol: error: remesh has no --level option \(its options: --levels, --base-faces, .*-o, --json\)/);
    usageError(mrvolCli('info', file('ico.obj'), '--alpha', '3'), /^mrvol: error: info has no --alpha option/);
    usageError(mrvolCli('info', file('ico.obj'), '-o', file('x.obj')), /^mrvol: error: info has no -o option/);
    usageError(mrvolCli('info', file('ico.obj'), '--scheme', 'foo'), /--scheme must be loop, butterfly or linear .*got 'foo'/);
    usageError(mrvolCli('info', file('ico.obj'), '--scheme', 'butterfly'), /info takes --scheme catmull-clark only \(quad meshes\), got 'butterfly'/);
    usageError(mrvolCli('remesh', file('ico.obj'), '--scheme', 'loop', '-o', file('x.obj')), /remesh takes --scheme catmull-clark only/);
    usageError(mrvolCli('volume', file('ico.obj'), '--scheme', 'butterfly', '--alpha', '3'),
      /--alpha and --beta are Loop's update weights: not with --scheme butterfly/);
    usageError(mrvolCli('edit', file('ico.obj'), '--move', '0:0.1,0,0', '--free-details', '0', '--path', 'polynomial', '-o', file('x.obj')),
      /--free-details runs matrix-free \(--path auto or matrix-free, no --theta\)/);
    assert.ok(!existsSync(file('x.obj')));
  });

  test('--help: exit 0, usage on stdout', () => {
    const r = mrvolCli('--help');
    assert.equal(r.status, 0);
    assert.match(r.stdout, /^usage: mrvol <command>/);
    assert.equal(r.stderr, '');
  });
});

// ---- version, help, exit codes ------------------------------------------------------------------

describe('version and help', () => {
  test('--version prints the version of package.json', () => {
    const { version } = JSON.parse(readFileSync(join(ROOT, 'package.json'), 'utf8'));
    const r = mrvolCli('--version');
    assert.equal(r.status, 0);
    assert.equal(r.stdout, `mrvol ${version}\n`);
    assert.equal(r.stderr, '');
  });

  test('help: every command listed, the exit codes written; help COMMAND equals COMMAND --help', () => {
    const all = mrvolCli('help');
    assert.equal(all.status, 0);
    assert.equal(all.stderr, '');
    assert.equal(all.stdout, mrvolCli('--help').stdout);
    assert.match(all.stdout, /^exit status:\n {2}0 {2}success\n {2}1 {2}error .*\n {2}2 {2}bad usage/m);
    const commands = ['info', 'subdivide', 'roundtrip', 'volume', 'theta', 'edit', 'remesh'];
    for (const command of commands) {
      assert.match(all.stdout, new RegExp(`^ {2}${command} `, 'm'), command);
      const one = mrvolCli('help', command);
      assert.equal(one.status, 0, one.stderr);
      assert.equal(one.stderr, '');
      assert.match(one.stdout, new RegExp(`^usage: mrvol ${command} `));
      assert.match(one.stdout, /^exit status:$/m);
      // The same text as COMMAND --help, also with other arguments around.
      assert.equal(mrvolCli(command, '--help').stdout, one.stdout);
      assert.equal(mrvolCli(command, 'x.obj', '-h').stdout, one.stdout);
    }
    // Each command's help lists its own options only.
    const edit = mrvolCli('help', 'edit').stdout, remesh = mrvolCli('help', 'remesh').stdout;
    assert.match(edit, /--move V:dx,dy,dz/);
    assert.doesNotMatch(edit, /--base-faces/);
    assert.match(remesh, /--base-faces k/);
    assert.doesNotMatch(remesh, /--move/);
  });

  test('help on what does not exist: exit 2', () => {
    usageError(mrvolCli('help', 'frobnicate'), /^mrvol: error: unknown command 'frobnicate'; the commands: info, /);
    usageError(mrvolCli('help', 'info', 'edit'), /^mrvol: error: unexpected argument 'edit'/);
    usageError(mrvolCli('frobnicate', '--help'), /^mrvol: error: unknown command 'frobnicate'/);
  });
});

// ---- progress ----------------------------------------------------------------------------------

describe('progress bar', () => {
  test('renderProgress: bar, percentage, elapsed time; unknown fraction; a label cut to the width', () => {
    assert.equal(renderProgress('theta^0', 0.38, 1234), `theta^0 [${'#'.repeat(9)}${'-'.repeat(15)}]  38%  1.2 s`);
    assert.equal(renderProgress('x', 1, 0), `x [${'#'.repeat(24)}] 100%  0.0 s`);
    assert.equal(renderProgress('x', 7, 0), renderProgress('x', 1, 0), 'clamped to 1');
    assert.equal(renderProgress('x', -1, 0), `x [${'-'.repeat(24)}]   0%  0.0 s`);
    assert.equal(renderProgress('reading a.obj', null, 2500), 'reading a.obj [working]  2.5 s');
    const long = renderProgress('reading ' + 'd/'.repeat(100) + 'big.obj', 0.5, 1000, 60);
    assert.equal(long.length, 59);
    assert.match(long, /^reading d\/d\/.*… \[#{12}-{12}\] {2}50% {2}1\.0 s$/);
  });

  test('Progress: nothing before the delay, throttled redraws but for a new label, the line erased at the end', () => {
    const path = file('progress.txt');
    const fd = openSync(path, 'w');
    let t = 0;
    const bar = new Progress('theta^0', { enabled: true, delayMs: 1000, fd, columns: 80, now: () => t });
    bar.update(0.1);
    t = 999;
    bar.update(0.2);
    assert.equal(readFileSync(path, 'utf8'), '', 'within the delay: nothing');
    t = 1000;
    bar.update(0.5);
    t = 1050;
    bar.update(0.6);  // within 100 ms of the last redraw: skipped
    t = 1060;
    bar.update(0.7, 'theta^0 (almost)');  // a new label: drawn
    t = 1100;
    bar.update(0.8);  // skipped
    t = 1200;
    bar.update(0.9);
    bar.done();
    closeSync(fd);
    const line = (label, fraction, ms) => `\r${renderProgress(label, fraction, ms)}\x1b[K`;
    assert.equal(readFileSync(path, 'utf8'), line('theta^0', 0.5, 1000) + line('theta^0 (almost)', 0.7, 1060) +
                 line('theta^0 (almost)', 0.9, 1200) + '\r\x1b[K');
    // Disabled (stderr not a terminal), or a step that ends within the delay: no output at all.
    const quiet = new Progress('x', { enabled: false, delayMs: 0, fd: 1 });
    quiet.update(0.5);
    quiet.done();
  });

  const hasScript = spawnSync('script', ['--version']).status === 0;
  test('on a terminal (script -qec): theta and remesh draw a bar on stderr, then erase it', { skip: !hasScript && 'util-linux script is missing' }, () => {
    const env = { ...process.env, MRVOL_PROGRESS_DELAY_MS: '0' };
    const quote = (s) => `'${s.replace(/'/g, `'\\''`)}'`;
    // A wide terminal, so that no label is cut.
    const inTerminal = (...args) => spawnSync('script', ['-qec', 'stty cols 250; ' + [process.execPath, CLI, ...args].map(quote).join(' '), '/dev/null'],
                                              { encoding: 'utf8', env, timeout: 60000 });
    const theta = inTerminal('theta', model('spiky-ball'), '-o', file('tty.theta'), '--json');
    assert.equal(theta.status, 0, theta.stdout);
    assert.match(theta.stdout, /\rreading \S*spiky-ball\.obj \[#+\] 100% {2}\d+\.\d s\x1b\[K/);
    assert.match(theta.stdout, /\rtheta\^0 \(loop scheme\) \[[#-]{24}\] +\d+% {2}\d+\.\d s\x1b\[K/);
    // The last bar is erased; the JSON follows on a clean line.
    const json = theta.stdout.slice(theta.stdout.lastIndexOf('\r\x1b[K') + 4).trim();
    assert.equal(JSON.parse(json).nnzStored > 0, true);

    writeFileSync(file('sphere.obj'), mrvol.writeObj(mrvol.subdivide(icosahedron(), { levels: 2 }).toMesh()));
    const remesh = inTerminal('remesh', file('sphere.obj'), '--levels', '1', '-o', file('sphere-remeshed.obj'), '--json');
    assert.equal(remesh.status, 0, remesh.stdout);
    assert.match(remesh.stdout, /\rremeshing \S*sphere\.obj: welding \[/);
    assert.match(remesh.stdout, /\rremeshing \S*sphere\.obj: fitting level 1 of 1 \[/);
    assert.match(remesh.stdout, /\rremeshing \S*sphere\.obj: measuring the Hausdorff distance \[/);
    assert.match(remesh.stdout, /\rremeshing \S*sphere\.obj: building the search tree \[/);

    // The steps that report nothing while they run (opening, the editor, the move, the writing) say
    // what runs; each line erased, the result printed after them.
    const edit = inTerminal('edit', model('spiky-ball'), '--move', '0:0.01,0,0', '-o', file('tty-edit.obj'));
    assert.equal(edit.status, 0, edit.stdout);
    for (const label of [/finding the levels of \S*spiky-ball\.obj/, /making the editor of \S*spiky-ball\.obj \(level 0, 642 vertices\)/,
                         /moving the cage/, /writing \S*tty-edit\.obj/])
      assert.match(edit.stdout, new RegExp(`\\r${label.source} \\[working\\]  \\d+\\.\\d s\x1b\\[K`));
    assert.match(edit.stdout.slice(edit.stdout.lastIndexOf('\r\x1b[K') + 4), /^reference volume/);
    const subdivide = inTerminal('subdivide', model('spiky-ball'), '--levels', '1', '-o', file('tty-sub.obj'));
    assert.equal(subdivide.status, 0, subdivide.stdout);
    assert.match(subdivide.stdout, /\rsubdividing \S*spiky-ball\.obj \(1 level\) \[working\]/);
  });

  test('piped: no progress output, even with no delay', () => {
    const r = spawnSync(process.execPath, [CLI, 'theta', model('spiky-ball'), '-o', file('piped.theta'), '--json'],
                        { encoding: 'utf8', env: { ...process.env, MRVOL_PROGRESS_DELAY_MS: '0' }, timeout: 60000 });
    assert.equal(r.status, 0, r.stderr);
    assert.equal(r.stderr, '');
    assert.equal(r.stdout.split('\n').length, 2);
  });
});
