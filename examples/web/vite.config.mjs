// Serves the examples with vite (`npx vite --config examples/web/vite.config.mjs`): 'mrvol' and
// 'mrvol/three' resolve to this checkout's lib/ (or the installed package's, run from
// node_modules/mrvol/examples/web), the sample models come from public/ (in the package, from
// examples/models/).
import { existsSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { defineConfig } from 'vite';

const repo = join(dirname(fileURLToPath(import.meta.url)), '../..');

export default defineConfig({
  root: join(repo, 'examples/web'),
  publicDir: existsSync(join(repo, 'public/models')) ? join(repo, 'public') : join(repo, 'examples'),
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
