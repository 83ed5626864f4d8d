#!/usr/bin/env node
// `npm test`: set-up, then every test: native C++ (GoogleTest through ctest, plain and under
// ASan+UBSan), Node tests of the WASM module and the CLI, browser tests, the package as a user
// installs it (tests/package), and lint (eslint, counted as one test).
// Ends with one line `tests: N passed, N failed`.
import { spawnSync } from 'node:child_process';
import { existsSync, readdirSync } from 'node:fs';
import { availableParallelism } from 'node:os';
import { join } from 'node:path';
import { root, setup } from './setup.mjs';

const browserTests = existsSync(join(root, 'tests/browser')) &&
  readdirSync(join(root, 'tests/browser')).some((f) => f.endsWith('.test.mjs'));
setup({ sanitize: true, browser: browserTests });

let passed = 0, failed = 0;
const failures = [];

function runSuite(name, cmd, args, parse, options = {}) {
  process.stderr.write(`\n== ${name}\n`);
  const started = Date.now();
  const r = spawnSync(cmd, args, { cwd: root, encoding: 'utf8', maxBuffer: 256 * 1024 * 1024, ...options });
  process.stdout.write(r.stdout ?? '');
  process.stderr.write(r.stderr ?? '');
  const counts = parse(r.stdout ?? '');
  if (!counts || r.status !== 0) {
    failures.push(name);
    if (counts) passed += counts.passed, failed += Math.max(counts.failed, 1);
    else failed += 1;
  } else {
    passed += counts.passed;
    failed += counts.failed;
  }
  process.stderr.write(`== ${name}: ${counts ? `${counts.passed} passed, ${counts.failed} failed` : 'no result'}` +
                       ` (${((Date.now() - started) / 1000).toFixed(1)} s)\n`);
}

function parseCtest(out) {
  const m = out.match(/(\d+)% tests passed, (\d+) tests? failed out of (\d+)/);
  if (!m) return null;
  return { passed: Number(m[3]) - Number(m[2]), failed: Number(m[2]) };
}

function parseNodeTest(out) {
  const pass = out.match(/^# pass (\d+)/m), fail = out.match(/^# fail (\d+)/m);
  if (!pass || !fail) return null;
  return { passed: Number(pass[1]), failed: Number(fail[1]) };
}

// A check counted as one test (lint: eslint over every JS folder reports nothing).
function runCheck(name, cmd, args) {
  process.stderr.write(`\n== ${name}\n`);
  const started = Date.now();
  const r = spawnSync(cmd, args, { cwd: root, encoding: 'utf8', maxBuffer: 64 * 1024 * 1024 });
  process.stdout.write(r.stdout ?? '');
  process.stderr.write(r.stderr ?? '');
  const ok = r.status === 0;
  if (ok) passed += 1;
  else failed += 1, failures.push(name);
  process.stderr.write(`== ${name}: ${ok ? 'passed' : `failed (${r.error?.message ?? `exit ${r.status}`})`}` +
                       ` (${((Date.now() - started) / 1000).toFixed(1)} s)\n`);
}

const ctestArgs = (dir) => ['--test-dir', dir, '--output-on-failure', '-j', '2'];
runSuite('native tests', 'ctest', ctestArgs('build/native'), parseCtest);
runSuite('native tests (ASan + UBSan)', 'ctest', ctestArgs('build/asan'), parseCtest,
         { env: { ...process.env, ASAN_OPTIONS: 'detect_leaks=1', UBSAN_OPTIONS: 'print_stacktrace=1' } });
const nodeTests = readdirSync(join(root, 'tests/node')).filter((f) => f.endsWith('.test.mjs')).map((f) => join('tests/node', f));
// Two files at a time at least (node's default is one fewer than the cores: one on a 2-core machine):
// 236 -> 166 s on 2 cores. They assert no timings.
const nodeConcurrency = Math.max(2, availableParallelism() - 1);
runSuite('node tests (WASM module, CLI)', process.execPath,
         ['--test', `--test-concurrency=${nodeConcurrency}`, '--test-reporter=tap', ...nodeTests], parseNodeTest);
if (browserTests) {
  const files = readdirSync(join(root, 'tests/browser')).filter((f) => f.endsWith('.test.mjs')).map((f) => join('tests/browser', f));
  runSuite('browser tests (headless Chromium)', process.execPath, ['--test', '--test-concurrency=1', '--test-reporter=tap', ...files], parseNodeTest);
}

runSuite('package tests (npm pack, install, Node, CLI, TypeScript, vite + Chromium)', process.execPath,
         ['--test', '--test-reporter=tap', 'tests/package/package.test.mjs'], parseNodeTest);

// npm run lint
runCheck('lint (eslint)', process.execPath, [join(root, 'node_modules/eslint/bin/eslint.js'),
                                             'lib', 'bin', 'web', 'scripts', 'tests', 'bench', 'examples']);

if (failures.length) process.stderr.write(`\nfailed suites: ${failures.join(', ')}\n`);
process.stdout.write(`\ntests: ${passed} passed, ${failed} failed\n`);
process.exit(failures.length ? 1 : 0);
