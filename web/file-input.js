// Files in and out of the page: the hidden file input, mesh files dropped on the window, downloads.
import { fileToOpen } from './gltf-sidecars.js';

const $ = (id) => document.getElementById(id);

/** Opens the file dialog of the hidden input; `onFile(file)` gets the chosen file (a .gltf with its chosen .bin files folded in). */
export function setUpFileInput(onFile) {
  $('open-file').addEventListener('change', async (e) => onFile(await fileToOpen(e.target.files)));
  return () => {
    $('open-file').value = '';
    $('open-file').click();
  };
}

/** A file dropped anywhere on the window goes to onFile (several: a .gltf with its .bin files folded in); the hint shows while one is dragged over. */
export function setUpDrop(onFile) {
  const hint = $('drop-hint');
  let depth = 0;
  const hasFiles = (e) => [...(e.dataTransfer?.types ?? [])].includes('Files');
  window.addEventListener('dragenter', (e) => {
    if (!hasFiles(e)) return;
    depth++;
    hint.hidden = false;
  });
  window.addEventListener('dragleave', () => {
    depth = Math.max(0, depth - 1);
    if (depth === 0) hint.hidden = true;
  });
  window.addEventListener('dragover', (e) => {
    if (hasFiles(e)) e.preventDefault();
  });
  window.addEventListener('drop', (e) => {
    e.preventDefault();
    depth = 0;
    hint.hidden = true;
    fileToOpen(e.dataTransfer?.files).then(onFile);
  });
}

/** Downloads text (or a Blob) as a file through a link carrying `testid` (tests catch the download). */
export function download(text, name, testid, type = 'text/plain') {
  const blob = text instanceof Blob ? text : new Blob([text], { type });
  const link = document.createElement('a');
  link.href = URL.createObjectURL(blob);
  link.download = name;
  link.dataset.testid = testid;
  document.body.appendChild(link);
  link.click();
  setTimeout(() => {
    URL.revokeObjectURL(link.href);
    link.remove();
  }, 1000);
}
