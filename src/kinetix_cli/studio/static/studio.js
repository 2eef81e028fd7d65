// kinetix studio: the page (ES modules, served as they are). The level being edited is its kinetix-level/1 JSON value; every edit is checked by the
// server (the project's own parser), which answers with the scene to draw (the same shapes, colours and legend as
// `kinetix render`). Play and watch run on the server's environment; this page only draws and sends keys.
//
// core.js (state, server calls) < draw.js < level.js, editing.js < forms.js, mouse.js, play.js, files.js < studio.js

import { $, KEYS, api, state } from './core.js';
import { canvas, drawScene } from './draw.js';
import { checked, edit, load, restore } from './editing.js';
import { generate, listFiles, mutate, openFile, save, saveAs } from './files.js';
import { levelForm, selectionForm } from './forms.js';
import { newLevel, remove, resize, rotateGroup } from './level.js';
import './mouse.js';
import { evaluate, keepSolution, playStart, schedule, watch } from './play.js';

checked.push(levelForm, selectionForm);

// --- keys ---------------------------------------------------------------------------------------------------
window.addEventListener('keydown', (event) => {
  if (event.target.tagName === 'INPUT' || event.target.tagName === 'SELECT') return;
  const key = event.key.toLowerCase();
  if (state.mode === 'play') {
    if (KEYS[key]) { state.pressed.add(key); event.preventDefault(); }
    return;
  }
  if (state.mode !== 'edit') return;
  if ((event.ctrlKey || event.metaKey) && key === 'z') { restore(state.history, state.future); event.preventDefault(); return; }
  if ((event.ctrlKey || event.metaKey) && key === 'y') { restore(state.future, state.history); event.preventDefault(); return; }
  const tools = { v: 'select', b: 'box', c: 'circle', t: 'polygon', j: 'joint', h: 'thruster' };
  if (tools[key] && !event.ctrlKey && !event.metaKey) return setTool(tools[key]);
  const sel = state.selected;
  if (!sel) return;
  if (key === 'delete' || key === 'backspace') { edit((level) => remove(level, sel)); state.selected = null; selectionForm(); }
  if (sel.kind !== 'body') return;
  if (key === '[' || key === ']') edit((level) => rotateGroup(level, sel.index, key === '[' ? 15 : -15));
  if (key === '+' || key === '=' || key === '-') edit((level) => resize(level, sel.index, key === '-' ? 1 / 1.1 : 1.1));
});
window.addEventListener('keyup', (event) => state.pressed.delete(event.key.toLowerCase()));
window.addEventListener('blur', () => state.pressed.clear());

// --- modes and buttons --------------------------------------------------------------------------------------
function setTool(tool) {
  state.tool = tool;
  for (const b of document.querySelectorAll('#tools [data-tool]')) b.classList.toggle('on', b.dataset.tool === tool);
}

function setMode(mode) {
  state.mode = mode;
  state.playing = false;
  clearInterval(state.timer);
  clearInterval(state.watchTimer);
  for (const b of document.querySelectorAll('#modes button')) b.classList.toggle('on', b.dataset.mode === mode);
  $('tools').hidden = mode !== 'edit';
  $('play-panel').hidden = mode !== 'play';
  $('watch-panel').hidden = mode !== 'watch';
  drawScene(state.scene);
  if (mode === 'play') playStart();
  canvas.focus();
}

for (const b of document.querySelectorAll('#modes button')) b.addEventListener('click', () => setMode(b.dataset.mode));
for (const b of document.querySelectorAll('#tools [data-tool]')) b.addEventListener('click', () => setTool(b.dataset.tool));
$('undo').addEventListener('click', () => restore(state.history, state.future));
$('redo').addEventListener('click', () => restore(state.future, state.history));
$('delete').addEventListener('click', () => { if (state.selected) { const sel = state.selected; edit((level) => remove(level, sel)); state.selected = null; } });
$('new').addEventListener('click', () => { if (!state.dirty || confirm('Discard the unsaved changes?')) { state.choice++; load(newLevel(), null); } });
$('save').addEventListener('click', () => (state.path ? save(state.path, true) : saveAs()));
$('save-as').addEventListener('click', saveAs);
$('random').addEventListener('click', generate);
$('mutate').addEventListener('click', mutate);
$('play-start').addEventListener('click', playStart);
$('play-pause').addEventListener('click', () => {
  state.playing = !state.playing && !!state.play;
  $('play-pause').textContent = state.playing ? 'Pause' : 'Resume';
  if (state.playing) schedule();
  canvas.focus();
});
$('play-keep').addEventListener('click', keepSolution);
$('watch').addEventListener('click', watch);
$('agent').addEventListener('change', () => { state.agentChosen = true; });
$('evaluate').addEventListener('click', evaluate);

api('/api/agents').then((answer) => {
  $('agent').replaceChildren(...answer.agents.map((name) => new Option(name, name)));
  if (state.check && state.check.ok && answer.agents.includes(`general-${state.check.size}`)) $('agent').value = `general-${state.check.size}`;
}).catch(() => {});
listFiles();
const wanted = new URLSearchParams(location.search).get('level');
if (wanted) openFile(wanted); else load(newLevel(), null);
