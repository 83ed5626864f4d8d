#!/usr/bin/env node
// Serves the web editor with vite's dev server on 127.0.0.1 (port $PORT or 5173): root web/,
// sample models from public/, the WASM module from build/wasm/ (`npm start` builds it first).
//
//   node scripts/serve.mjs            # or: npm start
//   node scripts/serve.mjs --preview  # production build (build/web/) served by vite preview
//
// Tests and benchmarks import startServer() and run it on a free port of their own.
import { existsSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..');

/**
 * Starts the dev server. Resolves to { url, port, close() } once it listens.
 * @param {object} [options]
 * @param {number} [options.port] 5173 by default; 0 asks the system for a free port
 * @param {string} [options.host] '127.0.0.1'
 * @param {boolean} [options.strictPort] fail instead of trying the next port (default: true when a port is given)
 * @param {string} [options.cacheDir] vite's dependency cache (a private one keeps concurrent servers apart)
 * @param {boolean} [options.watch] watch web/ for changes (default true; tests turn it off)
 * @param {'info'|'warn'|'error'|'silent'} [options.logLevel]
 * @param {'dev'|'preview'} [options.mode] 'preview' builds the app (into options.outDir, default
 *   build/web) and serves the bundle instead of the modules
 * @param {string} [options.outDir]
 */
export async function startServer(options = {}) {
  for (const f of ['build/wasm/mrvol-web.mjs', 'build/wasm/mrvol-web.wasm'])
    if (!existsSync(join(root, f)))
      throw new Error(`${f} is missing: run 'node scripts/setup.mjs --no-native' (or npm start) first`);
  if (options.mode === 'preview') return startPreview(options);
  const { createServer } = await import('vite');
  const port = options.port ?? 5173;
  const server = await createServer({
    configFile: join(root, 'vite.config.mjs'),
    logLevel: options.logLevel ?? 'info',
    clearScreen: false,
    ...(options.cacheDir ? { cacheDir: options.cacheDir } : {}),
    server: {
      host: options.host ?? '127.0.0.1',
      port,
      strictPort: options.strictPort ?? options.port !== undefined,
      ...(options.watch === false ? { watch: null, hmr: false } : {}),
    },
  });
  await server.listen();
  const address = server.httpServer.address();
  const host = typeof address === 'object' && address ? address.address : (options.host ?? '127.0.0.1');
  const actualPort = typeof address === 'object' && address ? address.port : port;
  return {
    url: `http://${host}:${actualPort}/`,
    port: actualPort,
    server,
    close: () => server.close(),
  };
}

async function startPreview(options) {
  const { build, preview } = await import('vite');
  const port = options.port ?? 5173;
  const common = {
    configFile: join(root, 'vite.config.mjs'),
    logLevel: options.logLevel ?? 'info',
    clearScreen: false,
    ...(options.cacheDir ? { cacheDir: options.cacheDir } : {}),
  };
  const outDir = options.outDir ?? join(root, 'build/web');
  await build({ ...common, build: { outDir, emptyOutDir: true } });
  const server = await preview({
    ...common,
    build: { outDir },
    preview: { host: options.host ?? '127.0.0.1', port, strictPort: options.strictPort ?? options.port !== undefined },
  });
  const address = server.httpServer.address();
  const actualPort = typeof address === 'object' && address ? address.port : port;
  const host = typeof address === 'object' && address ? address.address : (options.host ?? '127.0.0.1');
  return {
    url: `http://${host}:${actualPort}/`,
    port: actualPort,
    server,
    close: () => server.close(),
  };
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const port = process.env.PORT ? Number(process.env.PORT) : 5173;
  if (!Number.isInteger(port) || port < 0 || port > 65535) {
    process.stderr.write(`serve: PORT must be a port number, got '${process.env.PORT}'\n`);
    process.exit(2);
  }
  try {
    const mode = process.argv.includes('--preview') ? 'preview' : 'dev';
    const { url, close } = await startServer({ port, strictPort: false, mode });
    process.stdout.write(`mrvol editor: ${url}  (models: ${url}?model=spiky-ball, Ctrl+C stops)\n`);
    const stop = async () => {
      await close();
      process.exit(0);
    };
    process.on('SIGINT', stop);
    process.on('SIGTERM', stop);
  } catch (e) {
    process.stderr.write(`serve: ${e.message}\n`);
    process.exit(1);
  }
}
