// The sample models in public/models are exactly what their generating scripts make (with the
// same README text): scripts/make-models.mjs --check, which also runs make-remeshed-models.mjs
// --check, regenerates every model in memory and compares bytes.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { join } from 'node:path';
import { ROOT } from './helpers.mjs';

test('public/models is up to date with scripts/make-models.mjs and make-remeshed-models.mjs', () => {
  const r = spawnSync(process.execPath, [join(ROOT, 'scripts/make-models.mjs'), '--check'], { cwd: ROOT, encoding: 'utf8' });
  assert.equal(r.status, 0, r.stderr);
  assert.match(r.stderr, /models: models up to date/);
  assert.match(r.stderr, /models: remeshed models up to date/);
});
