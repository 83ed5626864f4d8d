// Serves the examples with vite (`npx vite --config examples/web/vite.config.mjs`): 'mrvol' and
// 'mrvol/three' resolve to this checkout's lib/ (an installed package resolves them itself), the
// sample models come from public/.
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { defineConfig } from 'vite';

const repo = join(dirname(fileURLToPath(import.meta.url)), '../..');

export default defineConfig({
  root: join(repo, 'examples/web'),
  publicDir: join(repo, 'public'),
  appType: 'mpa',
  resolve: {
    alias: [
      { find: /^mrvol\/three$/, replacement: join(repo, 'lib/three/index.mjs') },
      { find: /^mrvol$/, replacement: join(repo, 'lib/browser.mjs') },
    ],
  },
  server: { host: '127.0.0.1', fs: { allow: [repo] } },
  optimizeDeps: { include: ['three', 'three/addons/controls/OrbitControls.js'] },
});
