#!/usr/bin/env node
// Generates the binary files of tests/data/bad with fixed bytes (committed too):
//   node tests/data/bad/make-binary.mjs
import { writeFileSync } from 'node:fs';

const here = new URL('./', import.meta.url);
const write = (name, bytes) => writeFileSync(new URL(name, here), bytes);

// Deterministic pseudo-random bytes: a 32-bit linear congruential generator (Numerical Recipes).
function lcgBytes(count, seed) {
  const out = new Uint8Array(count);
  let s = seed >>> 0;
  for (let i = 0; i < count; ++i) {
    s = (Math.imul(s, 1664525) + 1013904223) >>> 0;
    out[i] = s >>> 24;
  }
  return out;
}
const concat = (...parts) => Buffer.concat(parts.map((p) => Buffer.from(p)));

// 4096 random bytes (NULs among them), starting with NUL as a zero-filled file would.
write('binary-random-bytes.obj', concat([0], lcgBytes(4095, 20240611)));
// An executable passed by mistake: ELF header (0x7f 'E' 'L' 'F' 0x02 ...) then random bytes.
write('binary-elf-header.obj', concat([0x7f, 0x45, 0x4c, 0x46, 0x02, 0x01, 0x01, 0x00], lcgBytes(248, 7)));
// A PNG image: 0x89 'P' 'N' 'G' CR LF 0x1a LF ...; the first line is text-like, the second is not.
write('binary-png-header.obj', concat([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a], lcgBytes(248, 11)));
// A text mesh with one NUL byte inside (a corrupted or zero-filled write): line 5, column 3.
write('nul-byte-in-text.obj', 'v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv \0 0 1\nv 0 0 -1\n' +
      'f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n');
