// Node entry point: loads the Node build of the WASM module (build/wasm, made by `npm test`,
// `npm start` or `npm pack`) and returns the public API.
import { existsSync } from 'node:fs';
import { open, readFile } from 'node:fs/promises';
import { availableParallelism } from 'node:os';
import { wrapModule, MrvolError } from './api.mjs';

export { MrvolError, wrapModule };
export { DEFAULT_SCHEME, chooseGradientPath } from './api.mjs';

/** Whether the threaded build can run here: in Node wherever SharedArrayBuffer exists (always, today). */
export function canUseThreads() {
  return typeof SharedArrayBuffer === 'function';
}

const buildDir = new URL('../build/wasm/', import.meta.url);

// The .wasm bytes: given, or read from wasmUrl / locateFile's answer / the build folder. The Node
// and web builds differ in their JS only: their .wasm are the same bytes (tests/node/entries.test.mjs
// checks), so the package holds the web build's, read here too.
async function wasmBytes({ wasmBinary, wasmUrl, locateFile }, file = 'mrvol-web.wasm') {
  if (wasmBinary !== undefined) {
    if (!(wasmBinary instanceof ArrayBuffer || ArrayBuffer.isView(wasmBinary)))
      throw new MrvolError('wasmBinary must be an ArrayBuffer or a typed array');
    return wasmBinary;
  }
  const where = wasmUrl ?? (locateFile ? locateFile(file, buildDir.href) : new URL(file, buildDir));
  const path = typeof where !== 'string' ? new URL(where.href) : where.startsWith('file:') ? new URL(where) : where;
  try {
    return await readFile(path);
  } catch (e) {
    throw new MrvolError(`cannot read the WASM module ${path}: ${e.code === 'ENOENT' ? 'no such file' : e.message}` +
                         (wasmUrl ?? locateFile ? '' : "; in a checkout, run 'npm test' or 'node scripts/setup.mjs'"));
  }
}

// Threads by default: the cores there are, at most this many (the surface passes are bound by
// memory traffic beyond a few).
const DEFAULT_MAX_THREADS = 8;

function threadsArg(threads) {
  if (threads === undefined) return Math.max(1, Math.min(DEFAULT_MAX_THREADS, availableParallelism()));
  if (!Number.isInteger(threads) || threads < 1 || threads > 16)
    throw new MrvolError(`threads must be an integer from 1 to 16, got ${threads}`);
  return threads;
}

async function importFactory(file) {
  try {
    return (await import(new URL(file, buildDir).href)).default;
  } catch (e) {
    throw new MrvolError(`the WASM module is not built (${e.message}); run 'npm test' or 'node scripts/setup.mjs'`);
  }
}

/**
 * Loads the WASM core and returns the API.
 * @param {{ wasmBinary?: ArrayBuffer | ArrayBufferView, wasmUrl?: string | URL,
 *           locateFile?: (path: string, prefix: string) => string, threads?: number }} [options]
 *   where the .wasm is when not in build/wasm beside lib/ (a path or file: URL), or its bytes
 *   (these name the single-thread module's file); threads: how many threads the core's big loops
 *   run on (the surface passes, the cage basis table): the threaded build (mrvol-node-mt, a pool of
 *   worker_threads) when it is there, else, and with threads: 1, the single-thread one. Default:
 *   the machine's cores, at most DEFAULT_MAX_THREADS; 1 when wasmBinary or wasmUrl is given.
 * @returns {Promise<ReturnType<typeof wrapModule>>}
 */
export async function createMrvol(options = {}) {
  const named = options.wasmBinary !== undefined || options.wasmUrl !== undefined;
  const threads = named && options.threads === undefined ? 1 : threadsArg(options.threads);
  if (threads > 1 && named) throw new MrvolError('threads > 1 loads the threaded build: give locateFile, not wasmBinary or wasmUrl');
  const threaded = threads > 1 && (options.threads !== undefined || existsSync(new URL('mrvol-node-mt.mjs', buildDir)));
  if (!threaded) {
    const factory = await importFactory('mrvol-node.mjs');
    // emscripten 3.1.6 would fetch() the .wasm under Node too: hand it the bytes.
    const module = await factory({ wasmBinary: await wasmBytes(options) });
    return wrapModule(module);
  }
  const factory = await importFactory('mrvol-node-mt.mjs');
  // The pool's workers (threads - 1: the calling thread is one) start with the module; each
  // loads mrvol-node-mt.worker.js beside the .mjs.
  const module = await factory({
    wasmBinary: await wasmBytes(options, 'mrvol-web-mt.wasm'),
    mrvolThreadPool: threads - 1,
    ...(options.locateFile ? { locateFile: (path, prefix) => options.locateFile(path, prefix) } : {}),
  });
  if (module._setThreadCount(threads) !== threads)
    throw new MrvolError(`could not start ${threads} threads: ${module._takeThreadError()}`);
  // The pool's workers must not keep Node running once the caller is done.
  for (const worker of module.PThread?.unusedWorkers ?? []) worker.unref?.();
  for (const worker of module.PThread?.runningWorkers ?? []) worker.unref?.();
  return wrapModule(module);
}

/**
 * Reads an OBJ file from disk in chunks straight into the WASM reader (mrvol.createObjReader):
 * Node never holds the whole file, the WASM heap never holds its text. Returns what
 * mrvol.readObj gives. onProgress(fraction) after each chunk; chunkBytes: the read size.
 * File errors throw MrvolError("cannot read PATH: ..."); bad OBJ lines MrvolError("line L: ...").
 */
export async function readObjFile(mrvol, path, { chunkBytes = 16 << 20, onProgress } = {}) {
  let file;
  try {
    file = await open(path, 'r');
  } catch (e) {
    throw new MrvolError(`cannot read ${path}: ${e.code === 'ENOENT' ? 'no such file' : e.message}`);
  }
  let reader;
  try {
    const size = (await file.stat()).size;
    reader = mrvol.createObjReader({ size });
    const buffer = new Uint8Array(Math.max(1, Math.min(chunkBytes, size)));
    for (let at = 0; ;) {
      let bytesRead;
      try {
        ({ bytesRead } = await file.read(buffer, 0, buffer.length, at));
      } catch (e) {
        throw new MrvolError(`cannot read ${path}: ${e.message}`);
      }
      if (bytesRead === 0) break;
      reader.push(buffer.subarray(0, bytesRead));
      at += bytesRead;
      onProgress?.(size > 0 ? Math.min(1, at / size) : 1);
    }
    const mesh = reader.finish();
    reader = null;
    return mesh;
  } finally {
    reader?.cancel();
    await file.close();
  }
}
