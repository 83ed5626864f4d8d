// scripts/setup.mjs's lock: two set-ups in one checkout (npm start beside npm test) must not run
// ninja in the same build directories at once. A lock left by a process that is gone is taken
// over; one held by a live process is waited for, and a wait that runs out says who holds it.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { withSetupLock } from '../../scripts/setup.mjs';

const lockIn = () => join(mkdtempSync(join(tmpdir(), 'mrvol-lock-')), 'build', '.setup.lock');

// A process that is not our child (so that it is reaped when it ends), alive for `seconds`.
function holder(seconds) {
  return Number(spawnSync('sh', ['-c', `sleep ${seconds} >/dev/null 2>&1 & echo $!`], { encoding: 'utf8' }).stdout.trim());
}

test('the lock is held while the set-up runs and released after it, also when it throws', () => {
  const path = lockIn();
  const seen = withSetupLock(() => readFileSync(path, 'utf8'), { path });
  assert.equal(seen, String(process.pid));
  assert.equal(existsSync(path), false);
  assert.throws(() => withSetupLock(() => { throw new Error('build failed'); }, { path }), /build failed/);
  assert.equal(existsSync(path), false);
});

test('a lock whose process is gone is taken over at once', () => {
  const path = lockIn();
  withSetupLock(() => {}, { path });  // creates the folder
  const gone = holder(0);
  spawnSync('sleep', ['0.2']);
  writeFileSync(path, String(gone));
  assert.equal(withSetupLock(() => 'ran', { path, timeoutMs: 5000 }), 'ran');
  writeFileSync(path, 'not a pid');
  assert.equal(withSetupLock(() => 'ran', { path, timeoutMs: 5000 }), 'ran');
});

test('a live holder is waited for; a wait that runs out names it', () => {
  const path = lockIn();
  withSetupLock(() => {}, { path });
  const pid = holder(1);
  writeFileSync(path, String(pid));
  let ranWhileHeld = null;
  withSetupLock(() => {
    ranWhileHeld = spawnSync('kill', ['-0', String(pid)]).status === 0;
  }, { path, pollMs: 50, timeoutMs: 30_000 });
  assert.equal(ranWhileHeld, false, 'it ran only after the holder had gone');
  const long = holder(30);
  writeFileSync(path, String(long));
  assert.throws(() => withSetupLock(() => {}, { path, pollMs: 50, timeoutMs: 300 }),
    new RegExp(`another set-up \\(pid ${long}\\) still holds`));
  spawnSync('kill', [String(long)]);
});
