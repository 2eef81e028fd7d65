// The folder's level files (thumbnails, open, save), random levels from the generator and ACCEL's mutations.

import { $, api, say, state } from './core.js';
import { edit, load } from './editing.js';

export async function listFiles() {
  let listing;
  try { listing = await api('/api/files'); } catch (error) { return say(error.message, 'error'); }
  const items = listing.files.map((file) => {
    const li = document.createElement('li');
    li.dataset.path = file.path;
    li.className = (file.valid ? '' : 'invalid') + (file.path === state.path ? ' on' : '');
    li.title = file.error || file.path;
    const img = document.createElement('img');
    img.alt = '';
    const label = document.createElement('span');
    label.textContent = file.path;
    li.append(img, label);
    li.addEventListener('click', () => openFile(file.path));
    if (file.valid) api('/api/thumbnail?path=' + encodeURIComponent(file.path)).then((blob) => { img.src = URL.createObjectURL(blob); }).catch(() => {});
    return li;
  });
  $('file-list').replaceChildren(...items);
}

export async function openFile(path) {
  if (state.dirty && !confirm('Discard the unsaved changes?')) return;
  const choice = ++state.choice;
  say(`opening ${path}...`);
  try {
    const answer = await api('/api/level?path=' + encodeURIComponent(path));
    if (choice !== state.choice) return; // another level was chosen meanwhile
    await load(answer.level, path);
    if (answer.notes.length) say('imported: ' + answer.notes.join('; '));
  } catch (error) { if (choice === state.choice) say(error.message, 'error'); }
}

export async function save(path, overwrite) {
  try {
    const answer = await api('/api/save', { path, level: state.level, overwrite });
    state.path = answer.path;
    state.dirty = false;
    say(answer.valid ? `saved ${answer.path}` : `saved ${answer.path} as a draft (invalid: ${answer.error})`, answer.valid ? 'ok' : 'error');
    $('file-name').textContent = answer.path;
    $('dirty').hidden = true;
    listFiles();
  } catch (error) {
    if (error.status === 409 && error.message.includes('confirm') && confirm(`${path} exists. Overwrite it?`)) return save(path, true);
    say(error.message, 'error');
  }
}

export function saveAs() {
  const path = prompt('Save as (a path inside the studio\'s folder):', state.path || 'new-level.json');
  if (path) save(path, false);
}

export async function generate() {
  if (state.dirty && !confirm('Discard the unsaved changes?')) return;
  const choice = ++state.choice, size = $('random-size').value, start = performance.now();
  const waiting = () => { // after a second, the wait is the generator's first compile for this size
    const seconds = Math.round((performance.now() - start) / 1000);
    say(seconds < 1 ? `generating a random level of size ${size}...`
      : `compiling the generator for size ${size} (once per size and studio, 15-25 s): ${seconds} s`);
  };
  waiting();
  const ticker = setInterval(() => { if (choice === state.choice) waiting(); }, 1000);
  try {
    const answer = await api('/api/generate', { size, seed: Math.floor(Math.random() * 2 ** 31) });
    if (choice === state.choice) await load(answer.level, null, true);
  } catch (error) {
    if (choice === state.choice) say(error.message, 'error');
  } finally {
    clearInterval(ticker);
  }
}

export async function mutate() {
  const choice = state.choice, before = JSON.stringify(state.level);
  try {
    const answer = await api('/api/mutate', { level: state.level, seed: Math.floor(Math.random() * 2 ** 31), edits: 1 });
    if (choice !== state.choice || before !== JSON.stringify(state.level)) return; // the level changed meanwhile
    edit((level) => { for (const key of Object.keys(level)) delete level[key]; Object.assign(level, answer.level); });
  } catch (error) { say(error.message, 'error'); }
}
