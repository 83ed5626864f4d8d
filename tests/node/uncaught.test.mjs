// A script that loads mrvol and leaves an error uncaught (or a promise rejected) ends as any Node
// script does: Node's own report (the error and its stack), exit code 1. Not emscripten's
// process-wide handlers rethrowing it from inside the module, which printed the module's whole
// minified line (60-90 KB) and exited 7. Both builds (threads: 1 loads the single-thread one).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { existsSync } from 'node:fs';

const api = new URL('../../lib/node.mjs', import.meta.url).href;
const threaded = existsSync(new URL('../../build/wasm/mrvol-node-mt.mjs', import.meta.url));

function run(code) {
  return spawnSync(process.execPath, ['--input-type=module', '-e', code], { encoding: 'utf8', timeout: 60000 });
}

for (const threads of threaded ? [1, 2] : [1]) {
  test(`threads ${threads}: an uncaught MrvolError is reported by Node, exit code 1`, () => {
    const r = run(`import { createMrvol } from '${api}';
      const mrvol = await createMrvol({ threads: ${threads} });
      mrvol.readObj('v 0 0 0\\nf 1 2 3\\n');`);
    assert.equal(r.status, 1, r.stderr.slice(0, 2000));
    assert.match(r.stderr, /MrvolError: line 2: face refers to vertex 2 but the file has 1 vertices/);
    assert.ok(r.stderr.length < 4000, `stderr of ${r.stderr.length} characters`);
    assert.doesNotMatch(r.stderr, /updateGlobalBufferAndViews|asmLibraryArg/);
  });

  test(`threads ${threads}: an unrelated error thrown after the module loaded, and a rejected promise`, () => {
    const thrown = run(`import { createMrvol } from '${api}';
      await createMrvol({ threads: ${threads} });
      setTimeout(() => { throw new Error('the caller\\'s own bug'); }, 0);`);
    assert.equal(thrown.status, 1, thrown.stderr.slice(0, 2000));
    assert.match(thrown.stderr, /Error: the caller's own bug/);
    assert.ok(thrown.stderr.length < 4000, `stderr of ${thrown.stderr.length} characters`);
    const rejected = run(`import { createMrvol } from '${api}';
      await createMrvol({ threads: ${threads} });
      Promise.reject(new Error('a rejection nobody handles'));`);
    assert.equal(rejected.status, 1, rejected.stderr.slice(0, 2000));
    assert.match(rejected.stderr, /a rejection nobody handles/);
    assert.ok(rejected.stderr.length < 4000, `stderr of ${rejected.stderr.length} characters`);
  });

  test(`threads ${threads}: a script that ends normally exits 0 (the pool's workers do not keep it alive)`, () => {
    const r = run(`import { createMrvol } from '${api}';
      const mrvol = await createMrvol({ threads: ${threads} });
      console.log(mrvol.readObj('v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 3\\n').faces.length);`);
    assert.equal(r.status, 0, r.stderr);
    assert.equal(r.stdout.trim(), '3');
  });
}
