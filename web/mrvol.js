// Loads the browser build of the WASM core through the package's browser entry (lib/browser.mjs).
// Used by the page and by the workers: the page compiles the WebAssembly module once and hands the
// compiled module to the workers.
import wasmUrl from '../build/wasm/mrvol-web.wasm?url';
import { createMrvol } from '../lib/browser.mjs';

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
