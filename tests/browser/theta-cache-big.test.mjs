// The largest sample's volume tensor from the cache after a reload (issue 13): the dragon's θ⁰
// (hundreds of MB, over Chromium's ~133 MB limit for one IndexedDB value) is computed once in the
// worker, stored in 32 MB chunks (web/chunked-store.js) and read back after a reload instead of
// being computed again; no storage problem is shown at any point. Both times θ is read from
// IndexedDB and handed to the editor in the editor worker (web/editor-worker.js), the page's
// thread only taking the editor over in slices (issue 13: no long hand-off on the main thread).
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { startTestServer, launchBrowser, waitReady, waitTheta, visibleHandles, dragHandle, settle, RESULTS_DIR } from './harness.mjs';
import { traceTasks, tasksSince } from './trace-tasks.mjs';

// The page's longest task from θ's arrival to the editor swapped in, in CPU time of the page's
// thread (from a trace): generous for a loaded 2-core machine, several times what the hand-off
// takes (tens of ms a task), and far under what the page did before (a 335 MB θ written to
// IndexedDB in one task: seconds). Wall time is logged: it also counts the waits for software
// WebGL's frames, which a loaded machine stretches to seconds (docs/issue-13-audit.md).
const LONGEST_TASK_CPU_MS = 750;

let server;

/**
 * The stages of the last θ hand-off: θ read from the cache and the editor made with it in the
 * worker, the memory taken over in slices on the page; the page's long tasks meanwhile logged
 * (PerformanceObserver 'longtask', recorded from the page's start).
 */
async function thetaHandOff(page, trace, fromMark) {
  const { what, stages, longest, during } = await page.evaluate(() => {
    const s = window.mrvolDebug.openStages();
    const from = performance.now() - s.since;
    const during = window.longTasks.filter((t) => t.start >= from);
    return { ...s, longest: Math.max(0, ...during.map((t) => t.ms)), during: during.map((t) => [Math.round(t.start - from), Math.round(t.ms)]) };
  });
  assert.match(what, /θ from the cache/, `the last rebuild: ${what}`);
  for (const [name, thread] of [['θ read from the cache (IndexedDB)', 'worker'], ['θ read (readTheta)', 'worker'],
    ['editor made with θ (useTheta)', 'worker'], ['memory taken over (in slices)', 'page'], ['editor swapped in (cage, view)', 'page']])
    assert.ok(stages.some((s) => s.stage === name && s.thread === thread), `"${name}" in the ${thread}: ${JSON.stringify(stages)}`);
  assert.ok(!stages.some((s) => /θ/.test(s.stage) && s.thread === 'page'), 'no θ stage on the page');
  const read = stages.find((s) => s.stage === 'θ read from the cache (IndexedDB)');
  assert.ok(read.bytes > 133 * 2 ** 20, `the worker read the whole θ: ${read.bytes} bytes`);
  const thetaWork = stages.filter((s) => /θ/.test(s.stage)).reduce((sum, s) => sum + s.ms, 0);
  console.log(`θ hand-off: worker ${Math.round(thetaWork)} ms of θ work, longest page task ${Math.round(longest)} ms (long tasks [start, ms]: ${JSON.stringify(during)}); ${JSON.stringify(stages)}`);
  // The page's own steps (not the wall-time ones, which span many tasks) are each shorter than the θ
  // work the worker did. The page's long tasks meanwhile are logged, not bounded: on this shared
  // machine some took seconds while the worker ran (see docs/issue-13-audit.md).
  for (const s of stages.filter((x) => x.thread === 'page' && !/wall time|in slices|waited for/.test(x.stage)))
    assert.ok(s.ms < thetaWork, `page stage "${s.stage}" ${s.ms} ms, the θ work in the worker ${thetaWork} ms`);
  assert.match(await page.locator('[data-testid="theta-status"]').textContent(), /handed to the editor in a worker/);
  const traced = tasksSince(await trace.stop(), fromMark);
  const over = (ms) => traced.tasks.filter((t) => t.ms > ms).map((t) => [Math.round(t.ms), Math.round(t.cpuMs)]);
  console.log(`from "${fromMark}": ${traced.tasks.length} tasks on the page's thread, longest ${Math.round(traced.longest)} ms wall, ` +
    `${Math.round(traced.longestCpu)} ms CPU; over 50 ms [wall, CPU]: ${JSON.stringify(over(50))}`);
  assert.ok(traced.longestCpu < LONGEST_TASK_CPU_MS,
    `the page's longest task from "${fromMark}" to the editor swapped in: ${Math.round(traced.longestCpu)} ms of CPU (bound ${LONGEST_TASK_CPU_MS})`);
}

describe('web editor: the largest sample\'s θ in the cache', { timeout: 1_200_000 }, () => {
  before(async () => {
    server = await startTestServer();
  });

  after(async () => {
    await server?.close();
  });

  test('the dragon\'s θ⁰ (over 133 MB) is cached in chunks and comes from the cache after a reload', { timeout: 1_100_000 }, async () => {
    const browser = await launchBrowser(server.url, { viewport: { width: 1280, height: 800 } });
    try {
      const page = await browser.newPage();
      await page.addInitScript(() => {
        window.longTasks = [];
        new PerformanceObserver((list) => {
          for (const e of list.getEntries()) window.longTasks.push({ start: e.startTime, ms: e.duration });
        }).observe({ type: 'longtask', buffered: true });
      });
      const url = `${server.url}?model=dragon-remeshed&gradient=tensor`;
      let trace = await traceTasks(page);
      await page.goto(url);
      await waitReady(page, 240_000);
      assert.equal(await page.evaluate(() => window.mrvolDebug.settings().level), 0);
      await waitTheta(page, 900_000);
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'computed');
      await thetaHandOff(page, trace, 'mrvol: θ received'); // computed in the θ worker, stored, read back in the editor worker
      const key = await page.evaluate(() => window.mrvolDebug.thetaKey());
      // written: the panel's cache list shows the entry with its size
      await page.waitForFunction(() => /dragon-remeshed loop e=0 +[\d.]+ MB/.test(document.querySelector('[data-testid="cache-list"]').textContent), null, { timeout: 300_000 });
      const listed = await page.locator('[data-testid="cache-list"]').textContent();
      const mb = Number(/dragon-remeshed loop e=0 +([\d.]+) MB/.exec(listed)[1]);
      assert.ok(mb > 133, `θ⁰ of the dragon is ${mb} MB: more than one IndexedDB value takes`);
      assert.equal(await page.locator('[data-testid="notice"]').textContent(), '', 'no storage notice');
      assert.equal(await page.locator('[data-testid="storage-problem"]').textContent(), '');

      trace = await traceTasks(page);
      await page.goto(url);
      await waitReady(page, 240_000);
      await waitTheta(page, 600_000);
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'cache', 'read back, not computed again');
      await thetaHandOff(page, trace, 'mrvol: stages begin');
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaKey()), key);
      const { index } = (await visibleHandles(page))[0];
      await dragHandle(page, index, 30, -20, { steps: 4 });
      const report = await page.evaluate(() => window.mrvolDebug.lastReport());
      assert.equal(report.path, 'tensor');
      assert.ok(report.relativeError <= 1e-5, `volume kept with the cached θ: ${report.relativeError}`);
      await settle(page);
      await page.screenshot({ path: join(RESULTS_DIR, 'theta-cache-big-dragon.png') });
      assert.equal(await page.locator('[data-testid="notice"]').textContent(), '');
      assert.deepEqual(page.problems, []);
    } finally {
      await browser.close();
    }
  });
});
