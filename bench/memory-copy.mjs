#!/usr/bin/env node
// What copying a worker's WebAssembly.Memory of hundreds of MB costs in headless Chromium, way by
// way (issue 14: the file worker hands its module's memory to the page; bench/NOTES-transfer.md).
// Each way runs in a fresh worker on a fresh memory filled first (its pages touched, as a module's
// heap is); the page then takes the copy into a fresh, grown WebAssembly.Memory in 16 MB slices,
// once (pages first written) and again (pages already there). Not a results table: a probe.
//   node bench/memory-copy.mjs [--mb 500] [--rounds 2]
import { loadavg } from 'node:os';
import { launchBrowser } from '../tests/browser/harness.mjs';
import { optionReader } from './cli-option.mjs';

const option = optionReader(process.argv.slice(2));
const MB = Number(option('--mb', '500'));
const ROUNDS = Number(option('--rounds', '2'));

// Runs in the worker: { way, mb } -> { times: [[what, ms]], copy?: Uint8Array (transferred) }
const workerSource = `
const SLICE = 16 * 2 ** 20;
const timed = (times, what, fn) => { const t = performance.now(); const r = fn(); times.push([what, performance.now() - t]); return r; };
onmessage = ({ data: { way, mb } }) => {
  const times = [];
  const memory = new WebAssembly.Memory({ initial: 256, maximum: 65536 });
  memory.grow(Math.ceil(mb * 2 ** 20 / 65536) - 256);
  const heap = new Uint8Array(memory.buffer);
  timed(times, 'the memory filled (its pages first written)', () => heap.fill(7));
  let copy = null;
  if (way === 'slice()') copy = timed(times, way, () => heap.slice());
  if (way === 'new Uint8Array + set') copy = timed(times, way, () => { const c = new Uint8Array(heap.length); c.set(heap); return c; });
  if (way === 'buffer.slice()') copy = timed(times, way, () => new Uint8Array(memory.buffer.slice(0)));
  if (way === 'a fresh buffer, only written') timed(times, way, () => new Uint8Array(heap.length).fill(1));
  if (way === '16 MB slices, fresh buffers') timed(times, way, () => { for (let at = 0; at < heap.length; at += SLICE) heap.slice(at, at + SLICE); });
  if (way === '16 MB slices, 3 buffers used again') {
    const ring = [0, 1, 2].map(() => new Uint8Array(SLICE));
    timed(times, way, () => { for (let at = 0, i = 0; at < heap.length; at += SLICE, i++) ring[i % 3].set(heap.subarray(at, at + SLICE)); });
  }
  postMessage({ times, copy }, copy ? [copy.buffer] : []);
};`;

const ways = ['slice()', 'new Uint8Array + set', 'buffer.slice()', 'a fresh buffer, only written', '16 MB slices, fresh buffers', '16 MB slices, 3 buffers used again'];
const browser = await launchBrowser('about:blank');
try {
  const page = await browser.newPage();
  console.log(`${MB} MB, load ${loadavg()[0].toFixed(1)} at the start (${new Date().toISOString()})`);
  for (let round = 0; round < ROUNDS; round++) {
    for (const way of ways) {
      const times = await page.evaluate(async ({ source, way, mb }) => {
        const worker = new Worker(URL.createObjectURL(new Blob([source], { type: 'text/javascript' })));
        const { times, copy } = await new Promise((resolve) => {
          worker.onmessage = ({ data }) => resolve(data);
          worker.postMessage({ way, mb });
        });
        worker.terminate();
        if (copy) {
          // the page's side: into a fresh memory grown to fit, in 16 MB slices; then again
          const memory = new WebAssembly.Memory({ initial: 256, maximum: 65536 });
          memory.grow(Math.ceil(copy.length / 65536) - 256);
          const heap = new Uint8Array(memory.buffer);
          for (const what of ['page: into a fresh grown memory', 'page: the same again (pages there)']) {
            const t = performance.now();
            for (let at = 0; at < copy.length; at += 16 * 2 ** 20) heap.set(copy.subarray(at, at + 16 * 2 ** 20), at);
            times.push([what, performance.now() - t]);
          }
        }
        return times;
      }, { source: workerSource, way, mb: MB });
      console.log(`${way.padEnd(36)} ${times.map(([what, ms]) => `${what} ${Math.round(ms)} ms`).join('; ')}`);
    }
  }
  console.log(`load ${loadavg()[0].toFixed(1)} at the end`);
} finally {
  await browser.close();
}
