// The package as a user gets it: `npm pack` (its prepack builds the WASM module) into a temporary
// folder, `npm install` of the tarball into a fresh project, then, against the installed package
// only: the Node example (examples/node/edit.mjs), `npx mrvol --version` and `npx mrvol info`,
// mrvol/remesh with its dependencies, the TypeScript example type-checked with
// `tsc --strict --noEmit`, and the three.js example (examples/web/minimal.html: mrvol/three's
// VolumeEditControls) built with vite, served by vite preview on 127.0.0.1 and run in Debian's
// Chromium, where a mouse drag of a cage handle keeps the volume. Every step fails loudly with its command's output.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { cpSync, mkdirSync, mkdtempSync, readFileSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { launchBrowser } from '../browser/harness.mjs';

const ROOT = fileURLToPath(new URL('../../', import.meta.url));
const { version } = JSON.parse(readFileSync(join(ROOT, 'package.json'), 'utf8'));
// At most this size packed (1.14 MB on 2026-11-29): the two .wasm and the JS, no tests, benchmarks, web app or models.
const MAX_TARBALL_BYTES = 1.5 * 1024 * 1024;

let scratch, project, installed;

/** Runs a command; throws with its output if it fails. */
function run(cmd, args, { cwd = project, env = {}, timeout = 120_000 } = {}) {
  const r = spawnSync(cmd, args, { cwd, encoding: 'utf8', timeout, env: { ...process.env, ...env }, maxBuffer: 64 << 20 });
  if (r.error || r.status !== 0) {
    throw new Error(`${cmd} ${args.join(' ')} (in ${cwd}) failed: ${r.error?.message ?? `exit ${r.status}`}\n` +
                    `--- stdout\n${r.stdout}\n--- stderr\n${r.stderr}`);
  }
  return r;
}

const npm = (args, options) => run('npm', [...args, '--no-audit', '--no-fund', '--loglevel=error'], options);

let packed;
before(() => {
  scratch = mkdtempSync(join(tmpdir(), 'mrvol-package-'));
  // npm pack runs prepack (node scripts/setup.mjs --no-native): the tarball always has the WASM.
  const r = npm(['pack', '--json', '--pack-destination', scratch], { cwd: ROOT, timeout: 600_000 });
  [packed] = JSON.parse(r.stdout.slice(r.stdout.indexOf('[')));
  project = join(scratch, 'project');
  mkdirSync(project);
  writeFileSync(join(project, 'package.json'), JSON.stringify({ name: 'mrvol-consumer', private: true, type: 'module' }));
  // The registry is reachable; the local cache makes it quick.
  npm(['install', '--prefer-offline', join(scratch, packed.filename)]);
  installed = join(project, 'node_modules', 'mrvol');
});

after(() => {
  if (scratch) rmSync(scratch, { recursive: true, force: true });
});

test('the tarball: the two WASM files (Node runs the web builds\' bytes), lib, bin, examples, docs, README, LICENSE; nothing else', () => {
  const files = packed.files.map((f) => f.path).sort();
  for (const f of ['build/wasm/mrvol-node.mjs', 'build/wasm/mrvol-web.mjs', 'build/wasm/mrvol-web.wasm', 'lib/api.mjs',
    'lib/node.mjs', 'lib/browser.mjs', 'lib/index.d.ts', 'lib/node.d.ts', 'lib/remesh.mjs', 'lib/remesh.d.ts', 'bin/mrvol.mjs',
    'bin/progress.mjs', 'examples/node/edit.mjs', 'examples/models/spiky-ball.obj', 'README.md', 'LICENSE', 'package.json'])
    assert.ok(files.includes(f), `${f} is in the tarball`);
  // The threaded builds (mrvol-*-mt: Node's pool's .worker.js and build/wasm/package.json that makes
  // it CommonJS; the browser pool's script as the text of a module) beside the single-thread ones.
  for (const f of ['build/wasm/mrvol-node-mt.mjs', 'build/wasm/mrvol-node-mt.worker.js', 'build/wasm/mrvol-web-mt.mjs',
    'build/wasm/mrvol-web-mt.wasm', 'build/wasm/mrvol-web-mt.worker-text.mjs', 'build/wasm/package.json'])
    assert.ok(files.includes(f), `${f} is in the tarball`);
  // The docs the README and `mrvol help` point to.
  for (const f of ['docs/catmull-clark.md', 'docs/limit-volume.md', 'docs/centroid.md']) assert.ok(files.includes(f), `${f} is in the tarball`);
  const allowed = /^(lib\/|bin\/|build\/wasm\/mrvol-(node|web)(-mt)?\.mjs$|build\/wasm\/mrvol-web(-mt)?\.wasm$|build\/wasm\/mrvol-node-mt\.worker\.js$|build\/wasm\/mrvol-web-mt\.worker-text\.mjs$|build\/wasm\/package\.json$|examples\/|docs\/[\w-]+\.md$|README\.md$|LICENSE$|package\.json$)/;
  assert.deepEqual(files.filter((f) => !allowed.test(f)), [], 'only what the package needs');
  assert.ok(packed.size < MAX_TARBALL_BYTES, `tarball ${packed.size} bytes`);
  const pkg = JSON.parse(readFileSync(join(installed, 'package.json'), 'utf8'));
  assert.equal(pkg.private, undefined, 'publishable');
  // The example's sample is the generated model, byte for byte.
  assert.equal(readFileSync(join(installed, 'examples/models/spiky-ball.obj'), 'utf8'),
               readFileSync(join(ROOT, 'public/models/spiky-ball.obj'), 'utf8'));
});

test('Node: examples/node/edit.mjs against the installed package keeps the volume and writes the OBJ', () => {
  cpSync(join(installed, 'examples/node/edit.mjs'), join(project, 'edit.mjs'));
  const r = run(process.execPath, ['edit.mjs', join(installed, 'examples/models/spiky-ball.obj'), 'edited.obj']);
  assert.match(r.stdout, /^opened .*spiky-ball\.obj: 642 vertices, 3 levels/m);
  assert.match(r.stdout, /^moved cage vertex \d+ by \(0\.25, 0, 0\): .*relative change \d\.\d\de-\d+/m);
  assert.match(r.stdout, /^wrote edited\.obj$/m);
  // Checked anew through the package's bare name: same hierarchy, vertex moved, volume kept.
  const check = run(process.execPath, ['--input-type=module', '-e', `
    import { readFileSync } from 'node:fs';
    import { createMrvol } from 'mrvol';
    const mrvol = await createMrvol();
    const read = (f) => mrvol.openMesh(mrvol.readObj(readFileSync(f, 'utf8')));
    const before = read(${JSON.stringify(join(installed, 'examples/models/spiky-ball.obj'))}), after = read('edited.obj');
    const moved = Math.max(...after.positions().map((x, i) => Math.abs(x - before.positions()[i])));
    console.log(JSON.stringify({ levels: after.levels, before: before.info().volume, after: after.info().volume, moved }));`]);
  const v = JSON.parse(check.stdout);
  assert.equal(v.levels, 3);
  // The cage vertex moved by 0.25; the fine surface (Loop: approximating) follows by less.
  assert.ok(v.moved > 0.05 && v.moved < 0.25, `the surface moved by ${v.moved}`);
  assert.ok(Math.abs(v.after - v.before) <= 1e-5 * v.before, `volume ${v.before} -> ${v.after}`);
});

test('CLI: npx mrvol --version and npx mrvol info', () => {
  assert.equal(run('npx', ['--no-install', 'mrvol', '--version']).stdout, `mrvol ${version}\n`);
  const info = JSON.parse(run('npx', ['--no-install', 'mrvol', 'info', join(installed, 'examples/models/spiky-ball.obj'), '--json']).stdout);
  assert.equal(info.vertices, 642);
  assert.equal(info.levels, 3);
  assert.equal(info.genus, 0);
  assert.ok(Math.abs(info.volume - 3.6227887) < 1e-7);
});

test('mrvol/remesh: the remesher loads with its dependencies from the installed package', () => {
  const r = run(process.execPath, ['--input-type=module', '-e', `
    import { createMrvol } from 'mrvol';
    import { remesh } from 'mrvol/remesh';
    const mrvol = await createMrvol();
    // An icosphere with its vertices moved off the sphere: closed, but not semi-regular once welded anew.
    const sphere = mrvol.subdivide(mrvol.readObj(${JSON.stringify(readFileSync(join(ROOT, 'public/models/icosahedron.obj'), 'utf8'))}), { levels: 2 });
    const r = await remesh(mrvol, sphere.toMesh(), { levels: 1 });
    console.log(JSON.stringify({ levels: mrvol.openMesh(r.mesh).levels, hausdorff: r.hausdorff, flipped: r.flippedTriangles }));`]);
  const result = JSON.parse(r.stdout);
  assert.equal(result.levels, 1);
  assert.equal(result.flipped, 0);
  assert.ok(result.hausdorff < 0.05, `Hausdorff ${result.hausdorff}`);
});

test('TypeScript: examples/typescript (core, remesh; mrvol/three with @types/three) type-check with tsc --strict --noEmit', () => {
  const dir = join(project, 'ts');
  mkdirSync(join(dir, 'three'), { recursive: true });
  for (const f of ['tsconfig.json', 'edit.ts', 'three/tsconfig.json', 'three/editor.ts'])
    cpSync(join(installed, 'examples/typescript', f), join(dir, f));
  const tsc = join(ROOT, 'node_modules/typescript/bin/tsc');
  run(process.execPath, [tsc, '--strict', '--noEmit', '-p', dir], { cwd: dir });
  // The component's types stand on three's: a TypeScript user of mrvol/three installs @types/three.
  const threeVersion = JSON.parse(readFileSync(join(project, 'node_modules/three/package.json'), 'utf8')).version;
  npm(['install', '--prefer-offline', `@types/three@~${threeVersion}`]);
  run(process.execPath, [tsc, '--strict', '--noEmit', '-p', join(dir, 'three')], { cwd: dir });
  // The check can fail: a wrong option is refused.
  writeFileSync(join(dir, 'wrong.ts'), "import { createMrvol } from 'mrvol';\nexport const m = createMrvol({ wasmUrl: 42 });\n");
  const wrong = spawnSync(process.execPath, [tsc, '--strict', '--noEmit', '-p', dir], { cwd: dir, encoding: 'utf8' });
  assert.notEqual(wrong.status, 0);
  assert.match(wrong.stdout, /wrong\.ts\(2,\d+\): error TS\d+: .*number/);
  rmSync(join(dir, 'wrong.ts'));
  // Each entry's types are its own: Node's have readObjFile and the helpers, and they run; a
  // bundler's (the browser entry) have no readObjFile.
  const entryCode = "import { readObjFile, DEFAULT_SCHEME, chooseGradientPath, canUseThreads } from 'mrvol';\n" +
                    'export const seen = [typeof readObjFile, DEFAULT_SCHEME.scheme, typeof chooseGradientPath, canUseThreads()];\n';
  writeFileSync(join(dir, 'entry.ts'), entryCode);
  run(process.execPath, [tsc, '--strict', '--noEmit', '-p', dir], { cwd: dir });
  const ran = run(process.execPath, ['--input-type=module', '-e', `${entryCode}console.log(seen.join(' '));`], { cwd: project });
  assert.equal(ran.stdout, 'function loop function true\n');
  mkdirSync(join(dir, 'bundler'));
  writeFileSync(join(dir, 'bundler/tsconfig.json'), JSON.stringify({ compilerOptions: { target: 'ES2022', module: 'esnext',
    moduleResolution: 'bundler', lib: ['ES2022', 'DOM'], types: [], strict: true, noEmit: true }, include: ['*.ts'] }));
  writeFileSync(join(dir, 'bundler/page.ts'), "import { createMrvol, readObjFile } from 'mrvol';\nexport const p = [createMrvol, readObjFile];\n");
  const browserTypes = spawnSync(process.execPath, [tsc, '-p', join(dir, 'bundler')], { cwd: dir, encoding: 'utf8' });
  assert.notEqual(browserTypes.status, 0);
  assert.match(browserTypes.stdout, /page\.ts\(1,\d+\): error TS\d+: .*readObjFile/);
  assert.doesNotMatch(browserTypes.stdout, /createMrvol/);
  writeFileSync(join(dir, 'three/wrong.ts'),
                "import { VolumeEditControls } from 'mrvol/three';\nexport const level = (c: VolumeEditControls) => c.setLevel('one');\n");
  const wrongThree = spawnSync(process.execPath, [tsc, '--strict', '--noEmit', '-p', join(dir, 'three')], { cwd: dir, encoding: 'utf8' });
  assert.notEqual(wrongThree.status, 0);
  assert.match(wrongThree.stdout, /wrong\.ts\(2,\d+\): error TS\d+: .*string/);
});

/** The README's three.js example (the js block under "In a three.js scene"), as a user pastes it. */
function readmeThreeExample(readme) {
  const section = readme.slice(readme.indexOf('### In a three.js scene'));
  return section.slice(section.indexOf('```js\n') + 6, section.indexOf('```\n', section.indexOf('```js\n') + 6));
}

/** Drags a handle well inside the canvas of the page's editor (window[name]); the start and end states. */
async function dragAHandle(page, name) {
  const state = () => page.evaluate((n) => {
    const editor = window[n];
    return { volume: editor.volume(), reference: editor.referenceVolume(), cage: Array.from(editor.cagePositions()),
             threads: editor.session.mrvol.threads };
  }, name);
  const handle = await page.evaluate((n) => {
    const editor = window[n];
    const rect = editor.domElement.getBoundingClientRect();
    const s = editor.handleScreenPositions();
    const i = [...Array(s.length / 2).keys()].find((k) =>
      s[2 * k] > 100 && s[2 * k] < rect.width - 100 && s[2 * k + 1] > 100 && s[2 * k + 1] < rect.height - 100);
    return { index: i ?? -1, x: rect.left + s[2 * i], y: rect.top + s[2 * i + 1] };
  }, name);
  assert.ok(handle.index >= 0, `${name}: a handle inside the canvas`);
  const start = await state();
  await page.mouse.move(handle.x, handle.y);
  await page.mouse.down();
  for (let i = 1; i <= 10; i++) await page.mouse.move(handle.x + 6 * i, handle.y - 4 * i);
  await page.mouse.up();
  const end = await state();
  const moved = Math.hypot(...[0, 1, 2].map((k) => end.cage[3 * handle.index + k] - start.cage[3 * handle.index + k]));
  assert.ok(moved > 0.05, `${name}: the handle moved (${moved})`);
  assert.ok(Math.abs(start.reference - 3.6227887) < 1e-6, `${name}: reference ${start.reference}`);
  assert.ok(Math.abs(end.volume - end.reference) <= 1e-5 * end.reference, `${name}: volume ${end.volume}, reference ${end.reference}`);
  return end;
}

test('browser: examples/web/minimal.html and the README\'s example built by vite (no configuration) against the installed package, dragged in Chromium, keep the volume; served cross-origin isolated, on 2 threads', async () => {
  // The example as a user copies it: 'mrvol', 'mrvol/three' and 'three' come from node_modules.
  const app = join(project, 'app');
  mkdirSync(join(app, 'public/models'), { recursive: true });
  cpSync(join(installed, 'examples/web/minimal.html'), join(app, 'index.html'));
  cpSync(join(installed, 'examples/models/spiky-ball.obj'), join(app, 'public/models/spiky-ball.obj'));
  const readmeCode = readmeThreeExample(readFileSync(join(installed, 'README.md'), 'utf8'));
  assert.match(readmeCode, /new VolumeEditControls/);
  writeFileSync(join(app, 'readme.html'), '<!doctype html><html><head><link rel="icon" href="data:,"></head><body style="margin:0">\n<script type="module">\n' +
                `${readmeCode}\nwindow.readmeEditor = editor;\n</script>\n</body></html>\n`);
  const { build, preview } = await import('vite');
  const common = { root: app, configFile: false, logLevel: 'warn', clearScreen: false, cacheDir: join(scratch, 'vite-cache') };
  await build({ ...common, build: { outDir: join(app, 'dist'), emptyOutDir: true, target: 'es2022',
                                     rollupOptions: { input: { index: join(app, 'index.html'), readme: join(app, 'readme.html') } } } });
  const assets = readdirSync(join(app, 'dist/assets'));
  assert.ok(assets.some((f) => f.endsWith('.wasm')), `vite copied the .wasm: ${assets.join(', ')}`);
  const isolation = { 'Cross-Origin-Opener-Policy': 'same-origin', 'Cross-Origin-Embedder-Policy': 'require-corp' };
  for (const isolated of [false, true]) {
    const server = await preview({ ...common, build: { outDir: join(app, 'dist') },
                                   preview: { host: '127.0.0.1', port: 0, ...(isolated ? { headers: isolation } : {}) } });
    const browser = await launchBrowser(null, { viewport: { width: 900, height: 700 } }).catch(async (e) => {
      await server.close();
      throw e;
    });
    try {
      const address = server.httpServer.address();
      for (const [path, name] of [['/', 'minimalEditor'], ['/readme.html', 'readmeEditor']]) {
        const page = await browser.newPage();
        const wasmTypes = [], failed = [], warnings = [];
        page.on('response', (r) => {
          if (r.url().endsWith('.wasm')) wasmTypes.push(r.headers()['content-type']);
          if (r.status() >= 400) failed.push(`${r.status()} ${r.url()}`);
        });
        page.on('console', (m) => m.type() === 'warning' && warnings.push(m.text()));
        await page.goto(`http://127.0.0.1:${address.port}${path}`);
        await page.waitForFunction((n) => window[n] !== undefined, name, { timeout: 60_000 });
        const end = await dragAHandle(page, name);
        const cores = await page.evaluate(() => navigator.hardwareConcurrency);
        assert.equal(end.threads, isolated ? Math.min(8, cores) : 1, `${name}, isolated ${isolated}: threads`);
        assert.deepEqual(wasmTypes, ['application/wasm'], 'one .wasm fetched, served as application/wasm');
        assert.deepEqual(failed, [], 'every request served');
        assert.deepEqual(warnings.filter((w) => /mrvol/.test(w)), [], 'no fall-back to one thread');
        assert.deepEqual(page.problems, []);
        await page.close();
      }
    } finally {
      await browser.close();
      await server.close();
    }
  }
});
