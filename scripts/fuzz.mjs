#!/usr/bin/env node
// `npm run fuzz [-- --seconds N] [--target NAME] [--parallel] [--coverage]`: builds the libFuzzer targets
// (tests/fuzz/*.cpp) with clang, ASan and UBSan in build/fuzz, replays the saved regression inputs
// (tests/fuzz/regressions/<target>/*), then fuzzes each target for N seconds (default 60) from a
// seeded corpus in build/fuzz/corpus-<target>. Exits non-zero when a target crashes, hangs
// (-timeout=10 s per input), leaks or runs out of memory (-rss_limit_mb=2048), after printing the
// saved input and the command that reproduces it. Offline and bounded: no network beyond
// installing missing Debian packages, and every fuzzer is killed 2 minutes after its time is up.
// --parallel runs the targets at the same time; --coverage ends with llvm-cov's line coverage of
// the core reached by the corpora (build/fuzz-cov).
import { spawn, spawnSync } from 'node:child_process';
import { createHash } from 'node:crypto';
import { existsSync, mkdirSync, readdirSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { basename, join, relative } from 'node:path';
import { ensureDebianPackages, root } from './setup.mjs';

const FUZZ_PACKAGES = ['clang', 'libclang-rt-14-dev'];
const buildDir = join(root, 'build/fuzz');
const fuzzDir = join(root, 'tests/fuzz');
const MAX_SEED_BYTES = 64 * 1024;

function log(message) {
  process.stderr.write(`fuzz: ${message}\n`);
}

function parseArgs(argv) {
  const options = { seconds: 60, targets: [], parallel: false, coverage: false };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const value = () => {
      if (i + 1 >= argv.length) throw new Error(`${a} needs a value`);
      return argv[++i];
    };
    if (a === '--seconds') options.seconds = Number(value());
    else if (a.startsWith('--seconds=')) options.seconds = Number(a.slice(10));
    else if (a === '--target') options.targets.push(value());
    else if (a.startsWith('--target=')) options.targets.push(a.slice(9));
    else if (a === '--parallel') options.parallel = true;
    else if (a === '--coverage') options.coverage = true;
    else if (a === '--help' || a === '-h') {
      process.stdout.write('usage: npm run fuzz [-- --seconds N] [--target NAME]... [--parallel] [--coverage]\n');
      process.exit(0);
    } else throw new Error(`unknown argument ${a}`);
  }
  if (!Number.isFinite(options.seconds) || options.seconds <= 0) throw new Error('--seconds must be a positive number');
  options.seconds = Math.ceil(options.seconds);
  return options;
}

function run(cmd, args, options = {}) {
  const r = spawnSync(cmd, args, { stdio: 'inherit', cwd: root, ...options });
  if (r.error) throw new Error(`${cmd} could not start: ${r.error.message}`);
  if (r.status !== 0) throw new Error(`${cmd} ${args.join(' ')} failed with status ${r.status}`);
}

// ---- build ---------------------------------------------------------------------------------------

// The core must be instrumented too (coverage feedback and ASan checks inside mrvol_core, not only
// in the harness), and UBSan must stop at the first report so libFuzzer sees it as a crash.
const FUZZ_CXX_FLAGS = '-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer';

function build(targets, { dir = buildDir, flags = FUZZ_CXX_FLAGS } = {}) {
  const env = { ...process.env, CC: 'clang', CXX: 'clang++' };
  const cache = join(dir, 'CMakeCache.txt');
  if (existsSync(cache) && !/CMAKE_CXX_COMPILER:\w+=.*clang\+\+/.test(readFileSync(cache, 'utf8'))) {
    log('build/fuzz was configured with another compiler: reconfiguring');
    rmSync(cache);
    rmSync(join(dir, 'CMakeFiles'), { recursive: true, force: true });
  }
  mkdirSync(dir, { recursive: true });
  run('cmake', ['-S', root, '-B', dir, '-G', 'Ninja', '-DMRVOL_FUZZ=ON', '-DMRVOL_TESTS=OFF',
                '-DCMAKE_BUILD_TYPE=RelWithDebInfo', `-DCMAKE_CXX_FLAGS=${flags}`],
      { env, stdio: ['ignore', 'ignore', 'inherit'] });
  run('ninja', ['-C', dir, ...targets], { env, stdio: ['ignore', 'ignore', 'inherit'] });
}

// Source-based line coverage of the core reached by the corpora (`--coverage`): a second build
// with clang's profile instrumentation replays every corpus input once, then llvm-cov reports.
function coverageReport(targets) {
  const dir = join(root, 'build/fuzz-cov');
  build(targets, { dir, flags: '-fprofile-instr-generate -fcoverage-mapping -fsanitize=fuzzer-no-link' });
  const profiles = [];
  for (const t of targets) {
    const corpus = join(buildDir, `corpus-${t}`);
    if (!existsSync(corpus)) continue;
    const profile = join(dir, `${t}.profraw`);
    rmSync(profile, { force: true });
    const r = spawnSync(join(dir, t), ['-runs=0', ...fuzzerArgs(t), corpus],
                        { cwd: root, env: { ...process.env, LLVM_PROFILE_FILE: profile }, stdio: 'ignore' });
    if (r.status !== 0) log(`${t}: coverage replay exited with ${r.status ?? r.signal}`);
    if (existsSync(profile)) profiles.push(profile);
  }
  if (profiles.length === 0) return;
  const merged = join(dir, 'merged.profdata');
  run('llvm-profdata', ['merge', '-sparse', ...profiles, '-o', merged]);
  const objects = targets.flatMap((t, i) => (i === 0 ? [join(dir, t)] : ['-object', join(dir, t)]));
  log('line and region coverage of the core by the corpora:');
  run('llvm-cov', ['report', ...objects, `-instr-profile=${merged}`, join(root, 'wasm/core/src'),
                   join(root, 'wasm/core/include')]);
  log(`details: llvm-cov show ${objects.map((o) => relative(root, o)).join(' ')} -instr-profile=${relative(root, merged)} ` +
      '-format=html -output-dir=build/fuzz-cov/html wasm/core/src');
}

// ---- corpora -------------------------------------------------------------------------------------

function listFiles(dir, accept, out = []) {
  if (!existsSync(dir)) return out;
  for (const entry of readdirSync(dir, { withFileTypes: true })) {
    const path = join(dir, entry.name);
    if (entry.isDirectory()) listFiles(path, accept, out);
    else if (entry.isFile() && accept(entry.name)) out.push(path);
  }
  return out;
}

// Files are named by content hash, like libFuzzer's own, so seeding twice adds nothing.
function addSeed(corpus, bytes) {
  const name = createHash('sha1').update(bytes).digest('hex');
  const path = join(corpus, name);
  if (!existsSync(path)) writeFileSync(path, bytes);
}

function seedCorpus(target) {
  const corpus = join(buildDir, `corpus-${target}`);
  mkdirSync(corpus, { recursive: true });
  const short = target.replace(/^fuzz_/, '');
  const seeds = listFiles(join(fuzzDir, 'corpus', short), () => true);
  if (target === 'fuzz_obj_reader') {
    seeds.push(...listFiles(join(fuzzDir, 'corpus', 'obj'), (n) => n.endsWith('.obj')));
    seeds.push(...listFiles(join(root, 'tests/data'), (n) => n.toLowerCase().endsWith('.obj')));
    seeds.push(...listFiles(join(root, 'public/models'), (n) => n.toLowerCase().endsWith('.obj')));
  }
  // The mesh file readers: the format test files of tests/data (good and hostile).
  const extensions = { fuzz_stl: ['.stl'], fuzz_ply: ['.ply'], fuzz_off: ['.off', '.coff', '.noff'], fuzz_gltf: ['.gltf', '.glb'] };
  if (extensions[target])
    seeds.push(...listFiles(join(root, 'tests/data'), (n) => extensions[target].some((e) => n.toLowerCase().endsWith(e))));
  let added = 0;
  for (const path of seeds) {
    if (statSync(path).size > MAX_SEED_BYTES) continue;
    addSeed(corpus, readFileSync(path));
    ++added;
  }
  if (target === 'fuzz_hierarchy') {
    // Every base mesh at every level, uncorrupted and with one corruption of each kind.
    for (let base = 0; base < 7; ++base)
      for (let levels = 0; levels < 4; ++levels) {
        addSeed(corpus, Buffer.from([base, levels, 0, 0]));
        for (let kind = 0; kind < 6; ++kind) addSeed(corpus, Buffer.from([base, levels, 1, kind, 7, 3, 1, 2, 5]));
        added += 7;
      }
  }
  return { corpus, seeds: added };
}

// ---- running -------------------------------------------------------------------------------------

const ARTIFACT = /^(crash|leak|timeout|oom|slow-unit)-/;

function artifactsIn(dir) {
  return existsSync(dir) ? readdirSync(dir).filter((n) => ARTIFACT.test(n)).map((n) => join(dir, n)) : [];
}

function sanitizerEnv() {
  return {
    ...process.env,
    ASAN_OPTIONS: ['detect_leaks=1', 'abort_on_error=1', 'symbolize=1', process.env.ASAN_OPTIONS].filter(Boolean).join(':'),
    UBSAN_OPTIONS: ['print_stacktrace=1', 'halt_on_error=1', process.env.UBSAN_OPTIONS].filter(Boolean).join(':'),
  };
}

function fuzzerArgs(target) {
  const dict = join(fuzzDir, `${target.replace(/^fuzz_/, '')}.dict`);
  const objDict = join(fuzzDir, 'obj.dict');
  const args = ['-rss_limit_mb=2048', '-timeout=10'];
  if (existsSync(dict)) args.push(`-dict=${dict}`);
  else if (target === 'fuzz_obj_reader' && existsSync(objDict)) args.push(`-dict=${objDict}`);
  return args;
}

// Saved inputs of fixed bugs: each must run clean.
function replayRegressions(target, binary) {
  const files = listFiles(join(fuzzDir, 'regressions', target), (n) => !n.startsWith('.') && !n.endsWith('.md'));
  if (files.length === 0) return true;
  log(`${target}: replaying ${files.length} regression input(s)`);
  const r = spawnSync(binary, [...fuzzerArgs(target), ...files], { cwd: root, env: sanitizerEnv(), encoding: 'utf8',
                                                                    maxBuffer: 64 * 1024 * 1024 });
  if (r.status === 0) return true;
  process.stderr.write(r.stderr ?? '');
  log(`${target}: a regression input fails again`);
  return false;
}

function fuzzTarget(target, seconds, { echo }) {
  const binary = join(buildDir, target);
  const { corpus, seeds } = seedCorpus(target);
  const artifactDir = join(buildDir, 'artifacts', target);
  mkdirSync(artifactDir, { recursive: true });
  const before = new Set(artifactsIn(artifactDir));
  const args = [...fuzzerArgs(target), `-max_total_time=${seconds}`, '-print_final_stats=1',
                `-artifact_prefix=${artifactDir}/`, corpus];
  log(`${target}: ${seconds} s from ${readdirSync(corpus).length} corpus inputs (${seeds} seeds)`);
  return new Promise((resolve) => {
    const started = Date.now();
    const child = spawn(binary, args, { cwd: root, env: sanitizerEnv(), stdio: ['ignore', 'pipe', 'pipe'] });
    let output = '', pending = '';
    const interesting = /pulse|DONE|INITED|ERROR|SUMMARY|==\d+==|#\d+ 0x|runtime error|Test unit written/;
    const collect = (chunk) => {
      const text = chunk.toString();
      output += text;
      if (output.length > 4 * 1024 * 1024) output = output.slice(-2 * 1024 * 1024);
      if (!echo) return;
      const lines = (pending + text).split('\n');
      pending = lines.pop();
      for (const line of lines) if (interesting.test(line)) process.stderr.write(`[${target}] ${line}\n`);
    };
    child.stdout.on('data', collect);
    child.stderr.on('data', collect);
    // Hard bound: libFuzzer stops itself after max_total_time, but a hang inside one input lasts
    // up to -timeout and a wedged process forever.
    const killer = setTimeout(() => child.kill('SIGKILL'), (seconds + 120) * 1000);
    child.on('close', (code, signal) => {
      clearTimeout(killer);
      const stat = (name) => {
        const m = output.match(new RegExp(`stat::${name}:\\s+(\\d+)`));
        return m ? Number(m[1]) : undefined;
      };
      const last = [...output.matchAll(/^#(\d+)\s+(?:DONE|pulse|NEW|REDUCE|INITED)\s+cov: (\d+) ft: (\d+) corp: (\d+)\/(\S+).*?exec\/s: (\d+)/gm)].pop();
      const artifacts = artifactsIn(artifactDir).filter((a) => !before.has(a));
      resolve({
        target, binary, code, signal, artifacts, output,
        seconds: (Date.now() - started) / 1000,
        runs: stat('number_of_executed_units') ?? (last ? Number(last[1]) : undefined),
        execPerSec: stat('average_exec_per_sec') ?? (last ? Number(last[6]) : undefined),
        cov: last ? Number(last[2]) : undefined,
        ft: last ? Number(last[3]) : undefined,
        corpus: last ? `${last[4]} inputs / ${last[5]}` : undefined,
        peakRss: stat('peak_rss_mb'),
      });
    });
  });
}

function report(r) {
  const ok = r.code === 0 && r.artifacts.length === 0;
  log(`${r.target}: ${ok ? 'ok' : 'FAILED'} after ${r.seconds.toFixed(0)} s: ${r.runs ?? '?'} runs, ` +
      `${r.execPerSec ?? '?'} exec/s, cov ${r.cov ?? '?'} edges, ft ${r.ft ?? '?'}, corpus ${r.corpus ?? '?'}, ` +
      `peak RSS ${r.peakRss ?? '?'} MB`);
  if (ok) return true;
  const summary = r.output.match(/^SUMMARY: .*$/m);
  if (summary) log(`${r.target}: ${summary[0]}`);
  if (r.signal) log(`${r.target}: killed by ${r.signal}`);
  if (r.artifacts.length === 0) {
    process.stderr.write(r.output.slice(-8000));
    log(`${r.target}: exited with status ${r.code} and saved no input`);
  }
  for (const a of r.artifacts) {
    log(`${r.target}: saved input ${relative(root, a)} (${statSync(a).size} bytes)`);
    log(`  reproduce: ${relative(root, r.binary)} ${relative(root, a)}`);
    log(`  minimize:  ${relative(root, r.binary)} -minimize_crash=1 -runs=100000 -exact_artifact_path=${relative(root, a)}.min ${relative(root, a)}`);
  }
  // The first report, for the log.
  const start = r.output.search(/^==\d+==ERROR|^.*runtime error|^==\d+== ERROR: libFuzzer/m);
  if (start >= 0) process.stderr.write(`${r.output.slice(start, start + 6000)}\n`);
  return false;
}

async function main() {
  const options = parseArgs(process.argv.slice(2));
  const available = readdirSync(fuzzDir).filter((n) => n.endsWith('.cpp')).map((n) => basename(n, '.cpp')).sort();
  const targets = options.targets.length ? options.targets : available;
  for (const t of targets) if (!available.includes(t)) throw new Error(`no fuzz target ${t} (have: ${available.join(', ')})`);
  ensureDebianPackages(FUZZ_PACKAGES);
  build(targets);
  let ok = true;
  for (const t of targets) ok = replayRegressions(t, join(buildDir, t)) && ok;
  const results = [];
  if (options.parallel) {
    results.push(...await Promise.all(targets.map((t) => fuzzTarget(t, options.seconds, { echo: false }))));
  } else {
    for (const t of targets) results.push(await fuzzTarget(t, options.seconds, { echo: true }));
  }
  for (const r of results) ok = report(r) && ok;
  if (options.coverage) coverageReport(targets);
  log(ok ? 'no crash, hang, leak or OOM found' : 'failures found (inputs above)');
  process.exit(ok ? 0 : 1);
}

main().catch((e) => {
  log(`error: ${e.message}`);
  process.exit(2);
});
