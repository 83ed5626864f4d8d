// Loads the browser build of the WASM core through the package's browser entry (lib/browser.mjs).
// Used by the page and by the workers: the page compiles the WebAssembly module once and hands the
// compiled module to the workers. The page's own instance is the threaded build where the page is
// cross-origin isolated (loadPageMrvol).
import wasmUrl from '../build/wasm/mrvol-web.wasm?url';
import { canUseThreads, createMrvol } from '../lib/browser.mjs';

let compiling = null;

/** Compiles mrvol-web.wasm once (streaming when the server sends application/wasm). */
export function compileMrvolWasm() {
  compiling ??= (async () => {
    try {
      return await WebAssembly.compileStreaming(fetch(wasmUrl));
    } catch {
      const response = await fetch(wasmUrl);
      if (!response.ok) throw new Error(`could not load ${wasmUrl} (HTTP ${response.status})`);
      return WebAssembly.compile(await response.arrayBuffer());
    }
  })();
  return compiling;
}

/**
 * Instantiates the module and returns the API.
 * @param {WebAssembly.Module} [compiled] a module compiled elsewhere (the page's, in the worker)
 */
export async function loadMrvol(compiled) {
  return createMrvol({ wasmModule: compiled ?? (await compileMrvolWasm()) });
}

/**
 * The page's own instance (samples and files opened on the page are edited in it): the threaded
 * module (the surface passes and the correction's sweeps on the cores) where the page is
 * cross-origin isolated, else, and if it fails to load, the single-thread one. Only for this
 * instance: the workers' instances and the fresh instance that takes over a worker's editor
 * (adoptTransferredInSlices: a copy of another instance's whole memory) stay single-thread, as a
 * threaded instance's memory also holds its threads' state, which a copy from elsewhere would overwrite.
 */
export async function loadPageMrvol() {
  if (!canUseThreads()) return loadMrvol();
  try {
    // A pool that does not start rejects (lib/browser.mjs: a worker that fails, or 30 s without word).
    return await createMrvol();
  } catch (e) {
    console.warn(`the threaded core did not load (${e.message}): the single-thread one instead`);
    return loadMrvol();
  }
}
