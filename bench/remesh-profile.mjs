#!/usr/bin/env node
// One remesh (lib/remesh.mjs, the defaults and --repair, as `mrvol remesh FILE --repair`) of one
// corpus model under V8's CPU profiler, then the functions with the most self and inclusive time:
// where the remesher's time goes. Prints the wall and CPU time and the result's distances; the time
// per stage (each sample given to the innermost pipeline function on its stack: repair, pieces,
// features, base, fit levels, relaxation, pull, feature snap, flip checks, untangling, drag, measure;
// the parametrised fallback's second run counts with the first: after its first await its stack no
// longer shows the outer remesh); and the progress timeline (wall and CPU time between the
// remesher's progress reports: each fit, level and measure in turn, the fallback's prefixed).
//
//   node bench/remesh-profile.mjs [NAME (default dragon-48k)] [--threads N] [--top N] [--no-timeline]
import { spawnSync } from 'node:child_process';
import { mkdtempSync, readdirSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';

const args = process.argv.slice(2);
const option = (name, fallback) => (args.includes(name) ? args[args.indexOf(name) + 1] : fallback);
const name = args.find((a, i) => !a.startsWith('--') && !args[i - 1]?.startsWith('--')) ?? 'dragon-48k';
const top = Number(option('--top', 25));

if (process.env.MRVOL_PROFILE_CHILD) {
  // The profiled run.
  const { createMrvol } = await import('../lib/node.mjs');
  const { remesh } = await import('../lib/remesh.mjs');
  const { CORPUS, makeCorpus } = await import('../scripts/corpus.mjs');
  const mrvol = await createMrvol(option('--threads') ? { threads: Number(option('--threads')) } : {});
  await makeCorpus({ big: true, names: [name] });
  const c = CORPUS.find((k) => k.name === name);
  if (!c) throw new Error(`no corpus model named ${name}`);
  const m = mrvol.readMesh(readFileSync(c.file), { name: c.file });
  const started = performance.now(), cpu = process.cpuUsage();
  // The progress reports with the wall and CPU time at each (ms since the start).
  const timeline = [];
  const onProgress = (fraction, stage) => {
    const c = process.cpuUsage(cpu);
    timeline.push({ stage, wall: performance.now() - started, cpu: (c.user + c.system) / 1000 });
  };
  const r = await remesh(mrvol, { positions: m.positions, faces: m.faces }, { repair: true, onProgress });
  const used = process.cpuUsage(cpu);
  if (!args.includes('--no-timeline')) {
    timeline.push({ stage: 'end', wall: performance.now() - started, cpu: (used.user + used.system) / 1000 });
    console.log('\nprogress timeline (wall s, CPU s until the next report; consecutive reports of one stage merged):');
    for (let i = 0; i + 1 < timeline.length;) {
      let j = i + 1;
      while (j + 1 < timeline.length && timeline[j].stage === timeline[i].stage) j++;
      console.log(`${((timeline[j].wall - timeline[i].wall) / 1000).toFixed(2).padStart(8)} ${((timeline[j].cpu - timeline[i].cpu) / 1000).toFixed(2).padStart(8)}  ${timeline[i].stage}`);
      i = j;
    }
    console.log(`fits: ${r.fits.map((f) => `${f.levels} levels on ${f.baseFaces} base faces -> ${(100 * f.hausdorff).toFixed(3)}%`).join('; ')}`);
    console.log(`parametrised fallback: ${JSON.stringify(r.parametrisedFallback)}`);
  }
  console.log(`${name}: ${m.faces.length / 3} triangles, wall ${((performance.now() - started) / 1000).toFixed(2)} s, ` +
              `CPU ${((used.user + used.system) / 1e6).toFixed(2)} s, threads ${mrvol.threads}; Hausdorff ${(100 * r.hausdorff).toFixed(3)}% ` +
              `(result->input ${(100 * r.hausdorffToInput).toFixed(3)}%, input->result ${(100 * r.hausdorffFromInput).toFixed(3)}%), ` +
              `${r.vertices} vertices, flipped ${r.flippedTriangles}, levels tried ${r.levelsTried.join(',')}`);
} else {
  const dir = mkdtempSync(join(tmpdir(), 'mrvol-remesh-profile-'));
  try {
    const run = spawnSync(process.execPath, ['--cpu-prof', `--cpu-prof-dir=${dir}`, fileURLToPath(import.meta.url), ...args],
                          { stdio: 'inherit', env: { ...process.env, MRVOL_PROFILE_CHILD: '1' } });
    if (run.status !== 0) process.exit(run.status ?? 1);
    const file = readdirSync(dir).find((f) => f.endsWith('.cpuprofile'));
    const { nodes, samples, timeDeltas } = JSON.parse(readFileSync(join(dir, file), 'utf8'));
    // Self time per node from the samples, then per function (name and place) self and inclusive.
    const byId = new Map(nodes.map((n) => [n.id, n])), self = new Map();
    for (let i = 0; i < samples.length; i++) self.set(samples[i], (self.get(samples[i]) ?? 0) + (timeDeltas[i] ?? 0));
    const parent = new Map();
    for (const n of nodes) for (const c of n.children ?? []) parent.set(c, n.id);
    const key = (n) => `${n.callFrame.functionName || '(anonymous)'} ${n.callFrame.url.split('/').slice(-1)[0]}:${n.callFrame.lineNumber + 1}`;
    const selfOf = new Map(), inclusiveOf = new Map();
    for (const [id, us] of self) {
      const n = byId.get(id);
      selfOf.set(key(n), (selfOf.get(key(n)) ?? 0) + us);
      // Inclusive: once per function on the sample's stack (recursion counted once).
      const seen = new Set();
      for (let at = id; at !== undefined; at = parent.get(at)) {
        const k = key(byId.get(at));
        if (seen.has(k)) continue;
        seen.add(k);
        inclusiveOf.set(k, (inclusiveOf.get(k) ?? 0) + us);
      }
    }
    const total = [...self.values()].reduce((a, b) => a + b, 0);
    const table = (map, title) => {
      console.log(`\n${title} (of ${(total / 1e6).toFixed(2)} s sampled):`);
      for (const [k, us] of [...map].sort((a, b) => b[1] - a[1]).slice(0, top)) console.log(`${(us / 1e6).toFixed(2).padStart(8)} s  ${k}`);
    };
    // Per stage: each sample to the innermost pipeline function on its stack (within a remesh).
    const STAGES = ['repair', 'weld', 'inputPieces', 'findFeatures', 'Surface', 'simplifyToBase', 'parametrisedBase',
                    'collapseToTarget', 'fitLevels', 'relaxTangentially', 'snapToFeatures', 'attractToInput', 'resultFlipped',
                    'flippedFaces', 'untangle', 'dragToTips', 'measure', 'addTips', 'farPieces'];
    const stageOf = new Map();
    for (const [id, us] of self) {
      let stage = null, inRemesh = false;
      for (let at = id; at !== undefined; at = parent.get(at)) {
        const { functionName, url } = byId.get(at).callFrame;
        if (!url.includes('/lib/')) continue;
        if (functionName === 'remesh') inRemesh = true;
        else if (!stage && STAGES.includes(functionName)) stage = functionName;
      }
      if (!inRemesh) continue;
      const k = stage ?? 'remesh (rest)';
      stageOf.set(k, (stageOf.get(k) ?? 0) + us);
    }
    table(stageOf, 'per stage, innermost pipeline function (main thread)');
    table(selfOf, 'self time');
    table(inclusiveOf, 'inclusive time');
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}
