// A worker's module memory handed to the page a slice at a time (lib/api.mjs transferable with
// memory: false, copyMemory, adoptTransferredInSlices). The worker copies each slice into one of a
// few buffers that travel to the page and back, instead of copying its whole memory into one new
// buffer: a new buffer of hundreds of MB costs a page fault for each 4 KB page first written (most
// of the copy's time on the test machine, bench/NOTES-transfer.md), and the page takes slice i
// while the worker copies slice i + 1.
// Messages: page -> worker { type: 'memory-slice', buffer?: ArrayBuffer } (the next slice, into this buffer)
//           worker -> page { type: 'memory-slice', bytes: Uint8Array, ms (the worker's copying so far) }
export const SLICE_BYTES = 16 * 2 ** 20;
// slices asked for at once: one being taken by the page, the next ones being copied or on their way
const AHEAD = 3;

/**
 * Worker side: returns the handler of the page's 'memory-slice' asks, which sends the next slice
 * of the first `memoryBytes` of `mrvol`'s memory. Nothing may run in that instance meanwhile.
 */
export function memorySliceServer(mrvol, memoryBytes, post = (message, transfer) => self.postMessage(message, transfer)) {
  let sent = 0, ms = 0;
  return ({ buffer }) => {
    if (sent >= memoryBytes) return;
    const started = performance.now();
    const into = buffer instanceof ArrayBuffer && buffer.byteLength === SLICE_BYTES ? new Uint8Array(buffer) : new Uint8Array(SLICE_BYTES);
    const copied = mrvol.copyMemory(sent, into.subarray(0, Math.min(SLICE_BYTES, memoryBytes - sent)));
    if (copied === 0) throw new Error(`the worker's memory ends before the ${memoryBytes} bytes in use`);
    sent += copied;
    ms += performance.now() - started;
    post({ type: 'memory-slice', bytes: into.subarray(0, copied), ms }, [into.buffer]);
  };
}

/**
 * Page side: the slices of `worker`'s memory (`memoryBytes` in all) as an async iterable for
 * adoptTransferredInSlices. The caller routes the worker's 'memory-slice' messages to receive(data)
 * and its failures to fail(error); `workerMs` is then the worker's copying time.
 */
export function memorySlicesFrom(worker, memoryBytes) {
  const arrived = [];
  let wake = null, failure = null;
  const state = {
    workerMs: 0,
    receive({ bytes, ms }) {
      arrived.push(bytes);
      state.workerMs = ms;
      wake?.();
    },
    fail(error) {
      failure ??= error;
      wake?.();
    },
    slices: {
      async *[Symbol.asyncIterator]() {
        for (let i = 0; i < AHEAD; i++) worker.postMessage({ type: 'memory-slice' });
        for (let taken = 0; taken < memoryBytes;) {
          while (arrived.length === 0) {
            if (failure) throw failure;
            await new Promise((resolve) => (wake = resolve));
            wake = null;
          }
          if (failure) throw failure;
          const bytes = arrived.shift();
          yield bytes; // resumed once the page has copied it: its buffer goes back for another slice
          taken += bytes.byteLength;
          if (taken < memoryBytes) worker.postMessage({ type: 'memory-slice', buffer: bytes.buffer }, [bytes.buffer]);
        }
      },
    },
  };
  return state;
}
