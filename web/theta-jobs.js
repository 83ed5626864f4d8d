// The page's side of the theta worker: one module worker, one job at a time. Cancelling a job
// terminates the worker (the computation is a single call into the core); the next job starts a
// fresh one, handed the page's compiled WebAssembly module.
import { compileMrvolWasm } from './mrvol.js';

export class ThetaJobs {
  #worker = null;
  #sentWasm = false;
  #current = null; // { id, resolve, reject, onProgress }
  #nextId = 1;

  #spawn() {
    const worker = new Worker(new URL('./theta-worker.js', import.meta.url), { type: 'module', name: 'mrvol-theta' });
    worker.onmessage = (event) => this.#receive(event.data);
    worker.onerror = (event) => {
      event.preventDefault?.();
      this.#fail(new Error(`the theta worker failed: ${event.message || 'it could not start'}`));
      this.#kill();
    };
    this.#worker = worker;
    this.#sentWasm = false;
    return worker;
  }

  #kill() {
    this.#worker?.terminate();
    this.#worker = null;
  }

  #fail(error) {
    const job = this.#current;
    this.#current = null;
    job?.reject(error);
  }

  #receive(message) {
    const job = this.#current;
    if (!job || message.id !== job.id) return;
    if (message.type === 'progress') job.onProgress?.(message.fraction);
    else if (message.type === 'done') {
      this.#current = null;
      job.resolve({ bytes: new Uint8Array(message.bytes), info: message.info, ms: message.ms, timings: message.timings });
    } else if (message.type === 'error') {
      this.#current = null;
      job.reject(new Error(message.message));
    }
  }

  get busy() { return this.#current !== null; }

  /** Starts the worker and its core ahead of the first job. */
  async prepare() {
    if (this.#worker) return;
    const wasm = await compileMrvolWasm();
    if (this.#worker) return;
    this.#spawn().postMessage({ type: 'init', wasm });
    this.#sentWasm = true;
  }

  /**
   * Computes theta^e in the worker.
   * job: { meshKey, positions: Float64Array, faces: Uint32Array, level, scheme, alpha, beta }
   * Resolves to { bytes: Uint8Array, info, ms }; rejects with { cancelled: true } when cancelled.
   */
  async compute(job, onProgress) {
    this.cancel();
    const id = this.#nextId++;
    const result = new Promise((resolve, reject) => {
      this.#current = { id, resolve, reject, onProgress };
    });
    let wasm;
    try {
      wasm = await compileMrvolWasm();
    } catch (e) {
      if (this.#current?.id === id) this.#fail(e);
      return result;
    }
    if (this.#current?.id !== id) return result; // cancelled (and rejected) meanwhile
    const worker = this.#worker ?? this.#spawn();
    const message = { type: 'compute', id, ...job };
    if (!this.#sentWasm) message.wasm = wasm;
    this.#sentWasm = true;
    worker.postMessage(message);
    return result;
  }

  /** Stops the running job, if any. */
  cancel() {
    if (!this.#current) return false;
    const error = Object.assign(new Error('cancelled'), { cancelled: true });
    this.#fail(error);
    this.#kill();
    return true;
  }

  dispose() {
    this.cancel();
    this.#kill();
  }
}
