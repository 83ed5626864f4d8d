// Loads the browser build of the WASM core (build/wasm/mrvol-web.{mjs,wasm}) and wraps it in the
// public JS API (lib/api.mjs). Used by the page and by the theta worker: the page compiles the
// WebAssembly module once and hands the compiled module to the worker.
import createMrvolModule from '../build/wasm/mrvol-web.mjs';
import wasmUrl from '../build/wasm/mrvol-web.wasm?url';
import { wrapModule } from '../lib/api.mjs';

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
  const wasmModule = compiled ?? (await compileMrvolWasm());
  let failed;
  const failure = new Promise((_, reject) => (failed = reject));
  const raw = await Promise.race([
    createMrvolModule({
      // emscripten calls this instead of fetching the file itself (its fetch path has no branch
      // for module workers).
      instantiateWasm(imports, receiveInstance) {
        WebAssembly.instantiate(wasmModule, imports).then((instance) => receiveInstance(instance, wasmModule), failed);
        return {};
      },
    }),
    failure,
  ]);
  return wrapModule(raw);
}
