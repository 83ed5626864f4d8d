#!/usr/bin/env node
// Writes the remeshing corpus (scripts/corpus.mjs) into .cache/corpus (not committed):
//   node scripts/make-corpus.mjs [--no-big] [--force] [NAME...]
import { statSync } from 'node:fs';
import { CORPUS_DIR, makeCorpus } from './corpus.mjs';

const args = process.argv.slice(2);
const names = args.filter((a) => !a.startsWith('--'));
const entries = await makeCorpus({ big: !args.includes('--no-big'), force: args.includes('--force'), names: names.length ? names : null });
for (const e of entries) process.stdout.write(`${e.name.padEnd(24)} ${e.kind.padEnd(7)} ${(statSync(e.file).size / 1024).toFixed(0).padStart(7)} KiB  ${e.file}\n`);
process.stdout.write(`${entries.length} models in ${CORPUS_DIR}\n`);
