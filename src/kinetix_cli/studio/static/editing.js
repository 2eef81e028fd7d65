// The level on the page: every edit is recorded for undo and checked by the server (the project's own parser);
// what it answers is drawn, and the callbacks in `checked` (the forms) run after each check.

import { $, api, say, state } from './core.js';
import { drawScene } from './draw.js';

export const checked = []; // called after every check of the level

export function edit(change) { // record the level for undo, change it, check it again (a promise of the check)
  state.history.push(JSON.stringify(state.level));
  if (state.history.length > 200) state.history.shift();
  state.future = [];
  change(state.level);
  state.dirty = true;
  return refresh();
}

export function restore(from, to) {
  if (!from.length) return;
  to.push(JSON.stringify(state.level));
  state.level = JSON.parse(from.pop());
  state.selected = null;
  state.dirty = true;
  refresh();
}

export let checking = null;
export async function refresh() { // check the level; draw what the server says it is
  const level = JSON.stringify(state.level);
  checking = level;
  $('file-name').textContent = state.path || 'untitled';
  $('dirty').hidden = !state.dirty;
  let check;
  try {
    check = await api('/api/check', { level: state.level });
  } catch (error) {
    say(error.message, 'error');
    return;
  }
  if (checking !== level) return; // a newer edit is being checked
  state.check = check;
  if (check.ok) {
    state.scene = check.scene;
    const agent = $('agent');
    if (!state.agentChosen && [...agent.options].some((o) => o.value === `general-${check.size}`)) agent.value = `general-${check.size}`;
    say(`valid level of size ${check.size}` + (state.level.solution ? ' (has a solution)' : ''), 'ok');
  } else {
    say(check.error, 'error');
  }
  if (state.mode !== 'play' || !state.playing) drawScene(state.scene);
  for (const callback of checked) callback();
}

export function load(level, path, dirty = false) { // the level on the page from now on (a promise of its check)
  state.level = level;
  state.path = path;
  state.history = [];
  state.future = [];
  state.selected = null;
  state.dirty = dirty;
  state.check = null;
  state.scene = null; // nothing of the previous level stays drawn
  drawScene(null);
  for (const li of $('file-list').children) li.classList.toggle('on', li.dataset.path === path);
  return refresh();
}
