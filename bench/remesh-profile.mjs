#!/usr/bin/env node
// One remesh (lib/remesh.mjs, the defaults and --repair, as `mrvol remesh FILE --repair`) of one
// corpus model under V8's CPU profiler, then the functions with the most self and inclusive time:
// where the remesher's time goes. Prints the wall and CPU time and the result's distances.
//
//   node bench/remesh-profile.mjs [NAME (default dragon-48k)] [--threads N] [--top N]
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
  const r = await remesh(mrvol, { positions: m.positions, faces: m.faces }, { repair: true });
  const used = process.cpuUsage(cpu);
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
    table(selfOf, 'self time');
    table(inclusiveOf, 'inclusive time');
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}
