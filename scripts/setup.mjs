#!/usr/bin/env node
// One idempotent set-up for `npm start`, `npm test` and `npm run bench`: installs the Debian
// packages and npm packages that are missing, then builds the native core (tests, benchmarks) and
// the WASM module. A second run checks and returns in about a second.
//
//   node scripts/setup.mjs [--no-native] [--sanitize] [--browser]
import { spawnSync } from 'node:child_process';
import { existsSync, statSync, mkdirSync, openSync, writeSync, closeSync, readFileSync, unlinkSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..');

// Debian packages: the toolchain (emscripten, Eigen, fast_float, acorn for emcc's optimizer), the native test
// build (cmake, ninja, g++, GoogleTest), nlohmann/json for the glTF reader, {fmt} for OBJ export's numbers, clang for the fuzzers, chromium for the
// browser tests.
const CORE_PACKAGES = ['cmake', 'ninja-build', 'g++', 'libgtest-dev', 'libeigen3-dev', 'libfast-float-dev', 'emscripten',
                       'node-acorn', 'nlohmann-json3-dev', 'libfmt-dev'];
const BROWSER_PACKAGES = ['chromium'];
const FUZZ_PACKAGES = ['clang', 'libclang-rt-14-dev'];

function log(message) {
  process.stderr.write(`setup: ${message}\n`);
}

function run(cmd, args, options = {}) {
  const r = spawnSync(cmd, args, { stdio: 'inherit', cwd: root, ...options });
  if (r.error) throw new Error(`${cmd} could not start: ${r.error.message}`);
  if (r.status !== 0) throw new Error(`${cmd} ${args.join(' ')} failed with status ${r.status}`);
}

function missingPackages(packages) {
  return packages.filter((p) => {
    const r = spawnSync('dpkg-query', ['-W', '-f=${Status}', p], { encoding: 'utf8' });
    return r.status !== 0 || !r.stdout.includes('install ok installed');
  });
}

export function ensureDebianPackages(packages) {
  const missing = missingPackages(packages);
  if (missing.length === 0) return;
  if (process.getuid && process.getuid() !== 0)
    throw new Error(`missing Debian packages: ${missing.join(' ')}; run: sudo apt-get install -y ${missing.join(' ')}`);
  log(`installing Debian packages: ${missing.join(' ')}`);
  const env = { ...process.env, DEBIAN_FRONTEND: 'noninteractive' };
  run('apt-get', ['update', '-q'], { env });
  run('apt-get', ['install', '-y', '-q', '--no-install-recommends', ...missing], { env });
}

function mtime(path) {
  return existsSync(path) ? statSync(path).mtimeMs : 0;
}

export function ensureNpmPackages() {
  const lock = join(root, 'package-lock.json');
  const installed = join(root, 'node_modules', '.package-lock.json');
  if (existsSync(installed) && mtime(installed) >= mtime(lock) && mtime(installed) >= mtime(join(root, 'package.json')))
    return;
  log('installing npm packages');
  run('npm', existsSync(lock) ? ['ci', '--no-audit', '--no-fund'] : ['install', '--no-audit', '--no-fund']);
}

// Environment for every emcc call: emscripten's JS optimizer needs Debian's acorn module.
export function emscriptenEnv() {
  const paths = ['/usr/share/nodejs', process.env.NODE_PATH].filter(Boolean);
  return { ...process.env, NODE_PATH: paths.join(':') };
}

export function buildNative({ dir = 'build/native', sanitize = false } = {}) {
  const buildDir = join(root, dir);
  if (!existsSync(join(buildDir, 'build.ninja'))) {
    mkdirSync(buildDir, { recursive: true });
    log(`configuring ${dir}`);
    run('cmake', ['-S', root, '-B', buildDir, '-G', 'Ninja', '-DCMAKE_BUILD_TYPE=Release',
                  `-DMRVOL_SANITIZE=${sanitize ? 'ON' : 'OFF'}`]);
  }
  run('ninja', ['-C', buildDir], { stdio: ['ignore', 'ignore', 'inherit'] });
}

export function buildWasm() {
  const buildDir = join(root, 'build/wasm');
  const env = emscriptenEnv();
  if (!existsSync(join(buildDir, 'build.ninja'))) {
    mkdirSync(buildDir, { recursive: true });
    log('configuring build/wasm (emscripten)');
    run('emcmake', ['cmake', '-S', root, '-B', buildDir, '-G', 'Ninja', '-DCMAKE_BUILD_TYPE=Release'], { env });
  }
  run('ninja', ['-C', buildDir], { env, stdio: ['ignore', 'ignore', 'inherit'] });
}

function alive(pid) {
  try {
    process.kill(pid, 0);
    return true;
  } catch (e) {
    return e.code === 'EPERM';
  }
}

const sleep = (ms) => Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0, ms);

/**
 * Runs fn holding build/.setup.lock, so that two set-ups in one checkout (npm start beside npm
 * test) do not run ninja in the same build directories at once, which can leave a WASM module
 * and its loader from different builds. A lock whose process is gone is taken over; a live one is
 * waited for (at most timeoutMs).
 */
export function withSetupLock(fn, { path = join(root, 'build', '.setup.lock'), timeoutMs = 30 * 60_000, pollMs = 250 } = {}) {
  mkdirSync(dirname(path), { recursive: true });
  const deadline = Date.now() + timeoutMs;
  let told = false;
  for (;;) {
    try {
      const fd = openSync(path, 'wx');
      writeSync(fd, String(process.pid));
      closeSync(fd);
      break;
    } catch (e) {
      if (e.code !== 'EEXIST') throw e;
    }
    let holder;
    try {
      holder = Number(readFileSync(path, 'utf8'));
    } catch {
      continue;  // released meanwhile
    }
    if (!Number.isInteger(holder) || holder <= 0 || !alive(holder)) {
      try {
        unlinkSync(path);  // left by a set-up that is gone
      } catch {}
      continue;
    }
    if (Date.now() > deadline) throw new Error(`another set-up (pid ${holder}) still holds ${path}`);
    if (!told) log(`waiting for another set-up to finish (pid ${holder})`), (told = true);
    sleep(pollMs);
  }
  try {
    return fn();
  } finally {
    try {
      if (Number(readFileSync(path, 'utf8')) === process.pid) unlinkSync(path);
    } catch {}
  }
}

export function setup(options = {}) {
  return withSetupLock(() => setupUnlocked(options));
}

function setupUnlocked({ native = true, sanitize = false, browser = false, fuzz = false } = {}) {
  const started = Date.now();
  ensureDebianPackages([...CORE_PACKAGES, ...(browser ? BROWSER_PACKAGES : []), ...(fuzz ? FUZZ_PACKAGES : [])]);
  ensureNpmPackages();
  if (native) buildNative();
  if (sanitize) buildNative({ dir: 'build/asan', sanitize: true });
  buildWasm();
  log(`ready in ${((Date.now() - started) / 1000).toFixed(1)} s`);
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const args = new Set(process.argv.slice(2));
  try {
    setup({ native: !args.has('--no-native'), sanitize: args.has('--sanitize'), browser: args.has('--browser'),
            fuzz: args.has('--fuzz') });
  } catch (e) {
    log(`error: ${e.message}`);
    process.exit(1);
  }
}
