#!/usr/bin/env node
// Generates the large and long-line files of tests/data/bad deterministically (they are committed
// too; this script documents how they were made and can rebuild them):
//   node tests/data/bad/make-large.mjs
import { writeFileSync } from 'node:fs';

const here = new URL('./', import.meta.url);
const write = (name, text) => writeFileSync(new URL(name, here), text);
const triangle = 'v 0 0 0\nv 1 0 0\nv 0 1 0\n';

// 10^6 copies of one triangle: read linearly, rejected by the duplicate check (a sort), never
// quadratic.
write('duplicate-face-1e6-times.obj', '# one triangle repeated 1,000,000 times\n' + triangle + 'f 1 2 3\n'.repeat(1_000_000));

// A face line of 100,000 vertex indices (about 600 kB on one line).
const indices = Array.from({ length: 100_000 }, (_, i) => String((i % 3) + 1)).join(' ');
write('long-line-face-100000-vertices.obj', '# one polygon with 100,000 corners on one line\n' + triangle + `f ${indices}\n`);

// A statement keyword of 100,000 characters.
write('long-line-unknown-statement.obj', '# one 100,000-character word on line 5\n' + triangle + 'x'.repeat(100_000) + '\nf 1 2 3\n');

// A coordinate token of 100,000 characters.
write('long-line-coordinate.obj', '# a coordinate of 100,000 characters on line 3\nv 0 0 0\nv 1 0 ' + '9'.repeat(100_000) + '\nv 0 1 0\nf 1 2 3\n');
