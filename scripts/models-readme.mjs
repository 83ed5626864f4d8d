// public/models/README.md has one part per generator: scripts/make-models.mjs owns the text before
// the first marker line (an HTML comment); each later generator owns the text from its own marker
// line to the next marker or the end. Both generators write and check their part through this
// module, so that either one leaves the other's part as it is and `--check` compares the same text
// that a run writes.
import { existsSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname } from 'node:path';

export const REMESHED_MARKER = '<!-- Remeshed models: the section below is written by scripts/make-remeshed-models.mjs. -->';

/** Splits README text into the head and the marked parts: { head, parts: Map(marker -> text) }. */
function split(text) {
  const starts = [...text.matchAll(/^<!-- .*-->$/gm)].map((m) => m.index);
  const head = starts.length ? text.slice(0, starts[0]) : text;
  const parts = new Map();
  starts.forEach((at, i) => {
    const end = i + 1 < starts.length ? starts[i + 1] : text.length;
    const marker = text.slice(at, text.indexOf('\n', at) >= 0 ? text.indexOf('\n', at) : end);
    parts.set(marker, text.slice(at, end));
  });
  return { head, parts };
}

/** The README text with the part of `marker` (null: the head) replaced by `body`. */
export function withPart(current, marker, body) {
  const { head, parts } = split(current);
  const trimmed = (s) => s.replace(/\n*$/, '\n');
  if (marker === null) return [trimmed(body), ...[...parts.values()].map(trimmed)].join('\n');
  parts.set(marker, `${marker}\n\n${body}`);
  return [trimmed(head), ...[...parts.values()].map(trimmed)].filter((s) => s.trim()).join('\n');
}

/**
 * Writes (or with `checkOnly`, compares) the part of `marker` of the README at `path`. Returns
 * true when the file is (or was) out of date.
 */
export function updateReadme(path, marker, body, checkOnly) {
  const current = existsSync(path) ? readFileSync(path, 'utf8') : '';
  const next = withPart(current, marker, body);
  if (!checkOnly && next !== current) writeFileSync(path, next);
  return next !== current;
}

/**
 * The end of a generator run: writes (or with `checkOnly`, checks) its README part and reports on
 * stderr. `changed` counts the model files found out of date (check) or written; `what` names the
 * generator's models ("models", "remeshed models"). Returns the exit status a check should give.
 */
export function finishReadme(path, marker, body, { checkOnly, changed, what, written }) {
  const stale = updateReadme(path, marker, body, checkOnly);
  if (!checkOnly) {
    process.stderr.write(`models: wrote ${written}\n`);
    return 0;
  }
  if (stale) process.stderr.write(`models: the ${what} part of README.md differs from the generator's output\n`);
  const out = changed + (stale ? 1 : 0);
  process.stderr.write(out ? `models: ${out} file(s) out of date (${what})\n` : `models: ${what} up to date\n`);
  return out ? 1 : 0;
}

/**
 * Writes a model file, or with `checkOnly` compares it with `text` (saying so on stderr when it
 * differs). Returns 1 when the file is out of date (check), else 0.
 */
export function writeOrCheckModel(path, name, text, checkOnly) {
  if (!checkOnly) {
    mkdirSync(dirname(path), { recursive: true });
    writeFileSync(path, text);
    return 0;
  }
  if (existsSync(path) && readFileSync(path, 'utf8') === text) return 0;
  process.stderr.write(`models: ${name}.obj differs from the generator's output\n`);
  return 1;
}
