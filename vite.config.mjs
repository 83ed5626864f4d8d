// Vite configuration of the web editor: root web/, sample models from public/ (/models/NAME.obj),
// the WASM build read from build/wasm/ (made by `node scripts/setup.mjs`).
// Used by `vite` on the command line and by scripts/serve.mjs (startServer).
import { readdirSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { defineConfig } from 'vite';

const repo = dirname(fileURLToPath(import.meta.url));

// `import { sampleModels } from 'virtual:mrvol-models'`: the names of public/models/*.obj, so that a
// model added there (a bunny) shows up in the panel without a code change.
function sampleModelsPlugin() {
  const id = 'virtual:mrvol-models';
  const resolved = '\0' + id;
  const modelsDir = join(repo, 'public/models');
  return {
    name: 'mrvol-sample-models',
    resolveId(source) {
      return source === id ? resolved : null;
    },
    load(source) {
      if (source !== resolved) return null;
      const names = readdirSync(modelsDir).filter((f) => f.endsWith('.obj')).map((f) => f.slice(0, -4)).sort();
      return `export const sampleModels = ${JSON.stringify(names)};`;
    },
  };
}

// emscripten 3.1.6 compiles the module with instantiateStreaming, which insists on this type.
function wasmMimePlugin() {
  const setType = (req, res, next) => {
    if (req.url && /\.wasm(\?|$)/.test(req.url)) res.setHeader('Content-Type', 'application/wasm');
    next();
  };
  return {
    name: 'mrvol-wasm-mime',
    configureServer(server) { server.middlewares.use(setType); },
    configurePreviewServer(server) { server.middlewares.use(setType); },
  };
}

// Cross-origin isolation (SharedArrayBuffer): the threaded WASM module (lib/browser.mjs) runs its
// pool of workers only on an isolated page. Every resource of the app is same-origin.
const isolationHeaders = {
  'Cross-Origin-Opener-Policy': 'same-origin',
  'Cross-Origin-Embedder-Policy': 'require-corp',
};

export default defineConfig({
  root: join(repo, 'web'),
  publicDir: join(repo, 'public'),
  // A missing file is a 404 (the sample list and OBJ fetches rely on it), not index.html.
  appType: 'mpa',
  plugins: [sampleModelsPlugin(), wasmMimePlugin()],
  server: {
    host: '127.0.0.1',
    port: 5173,
    fs: { allow: [repo] },
    headers: isolationHeaders,
  },
  preview: { host: '127.0.0.1', port: 5173, headers: isolationHeaders },
  optimizeDeps: {
    // Pre-bundled at start-up, so that the first page load never triggers a re-optimization reload.
    include: ['three', 'three/addons/controls/OrbitControls.js', 'lil-gui', 'idb'],
  },
  worker: { format: 'es' },
  build: {
    outDir: join(repo, 'build/web'),
    emptyOutDir: true,
    target: 'es2022',
    chunkSizeWarningLimit: 1024, // three.js is most of the 660 kB bundle
  },
});
