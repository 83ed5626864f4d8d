// Browser (and worker) entry point of the package: loads the web build of the WASM module
// (build/wasm/mrvol-web.{mjs,wasm}) and returns the public API (lib/api.mjs).
//
// The .wasm is referenced as `new URL('../build/wasm/mrvol-web.wasm', import.meta.url)`, which
// bundlers (vite, webpack 5, rollup plugins) follow to copy the file and rewrite the URL. Hosts
// that move assets elsewhere say where it is: `wasmUrl`, `locateFile` (emscripten's hook, as
// manifold-3d takes it), or the bytes or compiled module themselves.
import createMrvolModule from '../build/wasm/mrvol-web.mjs';
import poolWorkerText from '../build/wasm/mrvol-web-mt.worker-text.mjs';
import { wrapModule, MrvolError } from './api.mjs';

export { MrvolError, wrapModule };
export { DEFAULT_SCHEME, chooseGradientPath } from './api.mjs';

const WASM_FILE = 'mrvol-web.wasm';
const defaultWasmUrl = () => new URL('../build/wasm/mrvol-web.wasm', import.meta.url).href;

// Where the .wasm is: wasmUrl, else what locateFile says, else next to this file (bundled or not).
function wasmLocation({ wasmUrl, locateFile }) {
  if (wasmUrl !== undefined) return typeof wasmUrl === 'string' ? wasmUrl : wasmUrl.href;
  if (locateFile) return locateFile(WASM_FILE, '');
  return defaultWasmUrl();
}

async function compile(options) {
  if (options.wasmModule !== undefined) {
    if (!(options.wasmModule instanceof WebAssembly.Module)) throw new MrvolError('wasmModule must be a WebAssembly.Module');
    return options.wasmModule;
  }
  if (options.wasmBinary !== undefined) {
    const bytes = options.wasmBinary;
    if (!(bytes instanceof ArrayBuffer || ArrayBuffer.isView(bytes)))
      throw new MrvolError('wasmBinary must be an ArrayBuffer or a typed array');
    return WebAssembly.compile(bytes);
  }
  const url = wasmLocation(options);
  let response;
  try {
    response = await fetch(url, { credentials: 'same-origin' });
  } catch (e) {
    throw new MrvolError(`could not fetch the WASM module from ${url}: ${e.message}`);
  }
  if (!response.ok) throw new MrvolError(`could not load the WASM module from ${url} (HTTP ${response.status})`);
  // Streaming compilation needs the server to send application/wasm; otherwise compile the bytes.
  if (response.headers.get('content-type')?.startsWith('application/wasm') && WebAssembly.compileStreaming) {
    try {
      return await WebAssembly.compileStreaming(response.clone());
    } catch {
      // fall through to the bytes
    }
  }
  try {
    return await WebAssembly.compile(await response.arrayBuffer());
  } catch (e) {
    throw new MrvolError(`${url} is not a loadable WASM module: ${e.message}`);
  }
}

// The threaded build's files, found as the single-thread ones are (bundlers copy them for these
// URLs); its pool's worker script from a blob: URL of its text (of this page's origin, so that it
// may import the module under COEP; a file would be inlined as a data: URL by bundlers, or turned
// into a module by their dev servers), made once.
let poolWorkerUrl = null;
const threadedUrls = () => ({
  factory: new URL('../build/wasm/mrvol-web-mt.mjs', import.meta.url).href,
  wasm: new URL('../build/wasm/mrvol-web-mt.wasm', import.meta.url).href,
  worker: (poolWorkerUrl ??= URL.createObjectURL(new Blob([poolWorkerText], { type: 'text/javascript' }))),
});

/** Whether this page or worker can run the threaded module (SharedArrayBuffer: cross-origin isolated). */
export function canUseThreads() {
  return globalThis.crossOriginIsolated === true && typeof SharedArrayBuffer === 'function';
}

function threadsArg(options) {
  const { threads } = options;
  if (threads !== undefined && (!Number.isInteger(threads) || threads < 1 || threads > 16))
    throw new MrvolError(`threads must be an integer from 1 to 16, got ${threads}`);
  // The .wasm given (bytes, compiled module, URL) is the single-thread one's.
  const named = options.wasmModule !== undefined || options.wasmBinary !== undefined || options.wasmUrl !== undefined;
  if (threads === 1 || (named && threads === undefined) || !canUseThreads()) return 1;
  if (named) throw new MrvolError('threads > 1 loads the threaded build: give threadedUrls, not wasmModule, wasmBinary or wasmUrl');
  return threads ?? Math.max(1, Math.min(8, globalThis.navigator?.hardwareConcurrency ?? 1));
}

// Resolves with emscripten's module once instantiated, or rejects with why. extra: more of the
// module's settings, or a function of `failed` (reject with an error) that makes them.
async function instantiate(factory, wasmModule, extra = {}) {
  let failed;
  const failure = new Promise((_, reject) => (failed = reject));
  const settings = {
    ...(typeof extra === 'function' ? extra(failed) : extra),
    // emscripten calls this instead of fetching the file itself: the module is compiled above.
    instantiateWasm(imports, receiveInstance) {
      WebAssembly.instantiate(wasmModule, imports).then((instance) => receiveInstance(instance, wasmModule), failed);
      return {};
    },
  };
  return Promise.race([factory(settings), failure]).catch((e) => {
    // A threaded module that failed to start: its pool's workers (emscripten's PThread, which it
    // puts on the settings object) stopped, not left running in the page.
    settings.PThread?.terminateAllThreads?.();
    throw e;
  });
}

/**
 * Loads the WASM core and returns the API.
 * @param {{ wasmUrl?: string | URL, locateFile?: (path: string, prefix: string) => string,
 *           wasmBinary?: ArrayBuffer | ArrayBufferView, wasmModule?: WebAssembly.Module,
 *           threads?: number, threadedUrls?: { factory: string, wasm: string, worker?: string } }} [options]
 *   threads: how many threads the core's big loops run on. Where the page is cross-origin isolated
 *   (COOP: same-origin and COEP: require-corp; SharedArrayBuffer exists) the threaded build
 *   (mrvol-web-mt: its .mjs and .wasm at threadedUrls or beside this file; its pool's worker
 *   script from a blob: URL, or the classic script at threadedUrls.worker) runs them on that many
 *   (default: the cores, at most 8); elsewhere, with threads: 1, and when the single-thread
 *   module's .wasm is given, the single-thread build. Threads not asked for: if the threaded build
 *   does not start, a console warning says why and the single-thread build runs.
 *   threadStartTimeout: ms the threaded build's pool may take to start (default 30000) before a
 *   MrvolError says its files were not served as they are.
 */
export async function createMrvol(options = {}) {
  const threads = threadsArg(options);
  const singleThread = async () => wrapModule(await instantiate(createMrvolModule, await compile(options)));
  if (threads === 1) return singleThread();
  try {
    return await createThreaded(options, threads);
  } catch (e) {
    // Threads by default, not asked for: one thread rather than no module (the page works, slower).
    if (options.threads !== undefined || !(e instanceof MrvolError)) throw e;
    console.warn(`mrvol: running on one thread: ${e.message}`);
    return singleThread();
  }
}

async function createThreaded(options, threads) {
  const urls = { ...threadedUrls(), ...options.threadedUrls };
  let factory;
  try {
    ({ default: factory } = await import(/* @vite-ignore */ urls.factory));
  } catch (e) {
    throw new MrvolError(`could not load the threaded WASM module from ${urls.factory}: ${e.message}`);
  }
  const wasmModule = await compile({ wasmUrl: urls.wasm });
  // The pool's workers report that they loaded, or the module waits for them for ever (a worker
  // whose import of the module's file fails, say a build that did not emit it, only logs that in
  // the worker): past this long, a MrvolError says so.
  const timeout = options.threadStartTimeout ?? 30_000;
  let timer;
  const raw = await instantiate(factory, wasmModule, (failed) => {
    timer = setTimeout(() => failed(new MrvolError(`the threaded module's workers did not start within ${timeout / 1000} s ` +
      `(${named(urls.worker)} importing ${named(urls.factory)}): serve both as they are (see the README: cross-origin isolated pages), ` +
      'or use createMrvol({ threads: 1 })')), timeout);
    return threadedSettings(threads, urls, failed);
  }).finally(() => clearTimeout(timer));
  if (raw._setThreadCount(threads) !== threads)
    throw new MrvolError(`could not start ${threads} threads: ${raw._takeThreadError()}`);
  return wrapModule(raw);
}

// A file's URL for a message: a data: URL (a bundler inlined the file) not spelt out, nor our blob: one.
const named = (url) => (String(url).startsWith('data:') ? 'a data: URL (the file inlined by a bundler)'
  : url === poolWorkerUrl ? 'the pool worker (from mrvol-web-mt.worker-text.mjs)' : url);

// The threaded module's settings: its pool, where the pool's files are, and a pool worker that
// cannot start turned into `failed(error)`.
function threadedSettings(threads, urls, failed) {
  return {
    mrvolThreadPool: threads - 1,  // the pool's workers (the calling thread is one)
    // The pool's workers run the classic script beside the module and import the module's own file.
    locateFile: (path, prefix) => (path.endsWith('.worker.js') ? urls.worker : prefix + path),
    mainScriptUrlOrBlob: urls.factory,
    // A pool worker that fails to start (its script served as a module: a bundler's dev server
    // transforms it) left the module waiting for it for ever: emscripten only logs it. Rejected here.
    printErr(text) {
      console.warn(text);
      if (String(text).startsWith('worker sent an error!'))
        failed(new MrvolError(`the threaded module's worker ${named(urls.worker)} could not start (${String(text).slice(22)}): serve it ` +
                              'as a classic script, untransformed (see the README: cross-origin isolated pages), or use createMrvol({ threads: 1 })'));
    },
  };
}
