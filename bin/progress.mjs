// The command line's progress bar: one line on stderr, redrawn in place, for a step that has run
// longer than about a second (theta, remeshing, reading a big file). Only when stderr is a
// terminal: piped or redirected output stays exactly what the command prints.
import { writeSync } from 'node:fs';

const BAR_WIDTH = 24;
// Redraws at most this often (a progress callback may come thousands of times a second), except
// for a new label: a new stage always shows.
const REDRAW_MS = 100;

/**
 * One progress line: `LABEL [#########---------------]  38%  1.2 s` (without a fraction, when
 * only the elapsed time is known: `LABEL [working]  1.2 s`).
 * @param {string} label
 * @param {number | null} fraction 0..1, or null when unknown
 * @param {number} elapsedMs
 * @param {number} [columns] terminal width: the label is shortened to fit
 */
export function renderProgress(label, fraction, elapsedMs, columns = 80) {
  const seconds = `${(elapsedMs / 1000).toFixed(1)} s`;
  let bar;
  if (fraction === null || !Number.isFinite(fraction)) {
    bar = '[working]';
  } else {
    const f = Math.min(1, Math.max(0, fraction));
    const filled = Math.floor(f * BAR_WIDTH);
    bar = `[${'#'.repeat(filled)}${'-'.repeat(BAR_WIDTH - filled)}] ${String(Math.floor(f * 100)).padStart(3)}%`;
  }
  const tail = ` ${bar}  ${seconds}`;
  const room = Math.max(0, columns - 1 - tail.length);
  const name = label.length > room ? label.slice(0, Math.max(0, room - 1)) + (room > 0 ? '…' : '') : label;
  return name + tail;
}

/**
 * A progress reporter for one step. Draws nothing for the first `delayMs` (steps that end sooner
 * leave no trace) nor when `enabled` is false; `update` redraws, `done` erases the line.
 */
export class Progress {
  #label;
  #started;
  #fraction = null;
  #drawnAt = -Infinity;
  #drawnLabel = null;
  #shown = false;

  /**
   * @param {string} label what the step does
   * @param {{ enabled?: boolean, delayMs?: number, fd?: number, columns?: number, now?: () => number }} [options]
   */
  constructor(label, { enabled = process.stderr.isTTY === true, delayMs = 1000, fd = 2,
                       columns = process.stderr.columns || 80, now = () => performance.now() } = {}) {
    this.#label = label;
    this.enabled = enabled;
    this.delayMs = delayMs;
    this.fd = fd;
    this.columns = columns;
    this.now = now;
    this.#started = now();
  }

  /** Sets the fraction done (0..1, or null) and, past the delay, redraws (throttled but for a new label). */
  update(fraction = this.#fraction, label = this.#label) {
    this.#fraction = fraction;
    this.#label = label;
    if (!this.enabled) return;
    const t = this.now();
    if (t - this.#started < this.delayMs) return;
    if (this.#label === this.#drawnLabel && t - this.#drawnAt < REDRAW_MS) return;
    this.#drawnAt = t;
    this.#drawnLabel = this.#label;
    this.#shown = true;
    writeSync(this.fd, `\r${renderProgress(this.#label, this.#fraction, t - this.#started, this.columns)}\x1b[K`);
  }

  /** Erases the line if it was drawn. */
  done() {
    if (this.#shown) writeSync(this.fd, '\r\x1b[K');
    this.#shown = false;
  }
}
