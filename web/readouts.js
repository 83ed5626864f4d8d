// The readouts beside the view: volumes and the relative error, the last step (iterations, time,
// gradient path), the free set and the parts' volumes, the layers, where theta came from and its
// progress, the model line, the notice and the error box. They follow the editing session's events.
const $ = (id) => document.getElementById(id);

const SUPERSCRIPT = '⁰¹²³⁴⁵⁶⁷⁸⁹';
/** θ with its level as a superscript: θ⁰, θ¹² */
export function thetaName(level) {
  return 'θ' + String(level).replace(/\d/g, (d) => SUPERSCRIPT[d]);
}

function formatVolume(v) {
  return Number.isFinite(v) ? v.toPrecision(12) : '–';
}

export function showError(message) {
  $('error-text').textContent = message;
  $('error').hidden = false;
}

export function clearError() {
  $('error').hidden = true;
  $('error-text').textContent = '';
}

export function errorText() {
  return $('error-text').textContent;
}

/**
 * Shows `message` in the readouts. reveal: the answer to a button of the panel, scrolled into the
 * view when the panel is scrolled away from it (a phone's sheet showed the share link's answer
 * 500-1000 px above what was on screen). action ({ label, run, testid }): a link-like button after
 * the message that runs it (once: the notice is cleared first).
 */
export function notice(message, { reveal = false, action = null } = {}) {
  const box = $('notice');
  box.textContent = message ?? '';
  if (message && action) {
    const button = document.createElement('button');
    button.type = 'button';
    button.className = 'notice-action';
    button.textContent = action.label;
    if (action.testid) button.dataset.testid = action.testid;
    button.addEventListener('click', () => {
      box.textContent = '';
      action.run();
    });
    box.append(' ', button);
  }
  if (reveal && message) box.scrollIntoView({ block: 'nearest', inline: 'nearest' });
}

export function noticeText() {
  return $('notice').textContent;
}

// Rows of the readout table made here, after the relative error, in this order.
const EXTRA_ROWS = [['free-set-info', 'handles that move (free set)'], ['part-volumes', 'part volumes'], ['layer-info', 'layers']];

function readoutRow(id) {
  if (!$(id)) {
    let previous = $('volume-error').closest('tr');
    for (const [rowId, label] of EXTRA_ROWS) {
      if (!$(rowId)) {
        const row = document.createElement('tr');
        const th = document.createElement('th');
        th.textContent = label;
        const cell = document.createElement('td');
        cell.id = rowId;
        cell.dataset.testid = rowId;
        row.append(th, cell);
        row.hidden = rowId !== 'free-set-info';
        previous.after(row);
      }
      previous = $(rowId).closest('tr');
    }
  }
  return $(id);
}

function set(id, text, value) {
  const element = $(id);
  element.textContent = text;
  if (value !== undefined) element.dataset.value = String(value);
}

/** Volumes, the last step, the free set and parts: from the session, on each of its changes. */
export function showVolumes(session) {
  const editor = session.editor;
  if (!editor) return;
  const reference = editor.referenceVolume();
  // (during a drag the step's own volume, the mesh's once it ends: session.volumeNow)
  const current = session.volumeNow();
  const error = Math.abs(current - reference) / Math.max(Math.abs(reference), 1e-300);
  set('volume-reference', formatVolume(reference), reference);
  set('volume-current', formatVolume(current), current);
  set('volume-error', error.toExponential(2), error);
  const report = session.lastReport;
  set('step-iterations', report ? String(report.iterations) : '–');
  set('step-iterations-word', report?.iterations === 1 ? 'iteration' : 'iterations');
  set('step-ms', session.lastStepMs === null ? '–' : session.lastStepMs.toFixed(2));
  set('step-path', report ? report.path : editor.path());
  showFreeSet(session);
  if (report && !report.converged) notice(`The last step did not converge: ${report.message}`);
  else if (report && noticeText().startsWith('The last step did not converge')) notice('');
}

function showFreeSet(session) {
  const { mode, painted } = session.freeSet;
  const parts = session.parts;
  readoutRow('free-set-info').textContent = mode === 'painted' ? `painted region: ${painted.length} handle${painted.length === 1 ? '' : 's'}`
    : mode === 'parts' ? `cage minus held; ${parts.length} part${parts.length === 1 ? '' : 's'} keep their volumes`
    : mode === 'all' ? 'all cage' : 'cage minus held';
  const cell = readoutRow('part-volumes');
  const volumes = session.partVolumes();
  cell.closest('tr').hidden = !volumes;
  if (!volumes) {
    cell.textContent = '';
    delete cell.dataset.value;
    return;
  }
  const lines = parts.map((number, p) => {
    const reference = session.partReferences[p];
    const error = Math.abs(volumes[p] - reference) / Math.max(Math.abs(reference), 1e-300);
    if (reference === 0 && volumes[p] === 0) return `${number}: no triangle (assign neighbouring handles)`;
    return `${number}: ${volumes[p].toPrecision(8)} / ${reference.toPrecision(8)} (${error.toExponential(1)})`;
  });
  cell.textContent = lines.join('\n');
  cell.style.whiteSpace = 'pre';
  cell.dataset.value = JSON.stringify({ parts, volumes, references: session.partReferences });
}

/** The layers row: shown, level l, last cost; `deferred` when they follow only finished drags. */
export function showLayers({ shown, level, lastMs, deferred }) {
  const cell = readoutRow('layer-info');
  cell.closest('tr').hidden = !shown || level === null;
  cell.textContent = shown && level !== null ? `level ${level} approximation, ${lastMs.toFixed(2)} ms` +
    (deferred ? ' (after each drag)' : '') : '';
}

/** Where theta came from ('computed', 'cache', or none/pending) and what is going on. */
export function showTheta({ source, pending, status }) {
  $('theta-source').textContent = source ?? (pending ? 'pending' : 'none');
  $('theta-status').textContent = status;
}

/** The theta progress bar: fraction 0..1 with a label, or null to hide it. */
export function showProgress(fraction, label) {
  const box = $('theta-progress');
  if (fraction === null) {
    box.hidden = true;
    return;
  }
  box.hidden = false;
  $('theta-progress-bar').value = fraction;
  $('theta-progress-label').textContent = label;
}

/** A storage failure in plain words under the readouts, or null to clear it (the failure is over). */
export function showStorageProblem(text) {
  $('storage-problem').textContent = text ?? '';
}

export function showCacheStatus(text) {
  $('cache-status').textContent = text;
}

/** The model line: name, counts, the cage's size. */
export function showModel(session) {
  const { name, info, quads } = session.model;
  $('model-name').textContent = name;
  $('model-info').textContent = `${info.vertices} vertices, ${info.faces} ${quads ? 'quads' : 'faces'}, ${info.levels} levels` +
    `${quads ? ' (Catmull-Clark)' : ''}, cage ${session.cageSize} vertices` +
    (info.closed ? '' : ' (open: the volume is that of the cone to the boundary centroid)');
  // A quad mesh's volume: each quad counts as the bilinear patch through its corners (docs/catmull-clark.md).
  const kind = $('volume-kind');
  if (kind) {
    kind.textContent = quads ? '(bilinear patches)' : '';
    kind.title = quads ? 'Each quad counts as the bilinear patch through its four corners' : '';
  }
}

/** Subscribes the readouts to a session: volumes on every change, the model line on model and editor. */
export function followSession(session) {
  session.addEventListener('change', () => showVolumes(session));
  session.addEventListener('dragend', () => showVolumes(session));
  const model = () => showModel(session);
  session.addEventListener('model', model);
  session.addEventListener('editor', model);
}
