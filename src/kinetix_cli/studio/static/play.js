// Play (the page's keys drive the level on the server's environment), watch an agent play live, evaluate it.

import { $, KEYS, api, say, state } from './core.js';
import { drawScene } from './draw.js';
import { edit } from './editing.js';

export function currentAction() {
  const action = [0, 0, 0, 0, 0, 0];
  for (const key of state.pressed) { const [entry, value] = KEYS[key]; action[entry] = value; }
  return action;
}

// --- play ---------------------------------------------------------------------------------------------------
export async function playStart() {
  if (!state.check || !state.check.ok) return say('fix the level before playing it: ' + (state.check ? state.check.error : ''), 'error');
  try {
    const frame = await api('/api/play/start', { level: state.level });
    state.play = frame.play;
    state.playing = true;
    $('play-pause').textContent = 'Pause';
    showFrame(frame);
    schedule();
  } catch (error) { say(error.message, 'error'); }
}

export function schedule() {
  clearInterval(state.timer);
  state.timer = setInterval(playTick, 1000 / 30);
}

export async function playTick() {
  if (!state.playing || state.inFlight || !state.play) return;
  state.inFlight = true;
  try {
    const frame = await api('/api/play/step', { play: state.play, action: currentAction() });
    showFrame(frame);
    if (frame.ending) { state.playing = false; clearInterval(state.timer); }
  } catch (error) {
    state.playing = false;
    clearInterval(state.timer);
    say(error.message, 'error');
  } finally {
    state.inFlight = false;
  }
}

export function showFrame(frame) {
  drawScene(frame.scene);
  const ending = frame.ending ? ` — ${frame.ending}` : '';
  $('play-readout').textContent = `t = ${frame.seconds.toFixed(2)} s  step ${frame.step}  reward ${frame.reward.toFixed(3)}  return ${frame.return.toFixed(3)}${ending}`;
  $('play-keep').disabled = frame.ending !== 'solved';
  if (frame.ending) say(`episode ${frame.ending} after ${frame.step} steps`, frame.ending === 'solved' ? 'ok' : 'error');
}

export async function keepSolution() {
  try {
    const answer = await api('/api/play/solution', { play: state.play, level: state.level });
    await edit((level) => { level.solution = answer.level.solution; });
    say('the played episode is now the level\'s solution; save to write it', 'ok');
  } catch (error) { say(error.message, 'error'); }
}

// --- watch --------------------------------------------------------------------------------------------------
// The agent plays live on the server: one request per step, at the pace of its environment's step.
export async function watch() {
  if (!state.check || !state.check.ok) return say('fix the level first', 'error');
  clearInterval(state.watchTimer);
  $('watch-readout').textContent = 'loading the agent...';
  try {
    const frame = await api('/api/watch/start', { level: state.level, agent: $('agent').value, seed: Math.floor(Math.random() * 1e6) });
    const episode = frame.play;
    watchFrame(frame);
    let inFlight = false;
    state.watchTimer = setInterval(async () => {
      if (inFlight) return;
      inFlight = true;
      try {
        const next = await api('/api/play/step', { play: episode });
        watchFrame(next);
        if (next.ending) clearInterval(state.watchTimer);
      } catch (error) { clearInterval(state.watchTimer); say(error.message, 'error'); }
      inFlight = false;
    }, 1000 * frame.step_seconds);
  } catch (error) { say(error.message, 'error'); $('watch-readout').textContent = ''; }
}

export function watchFrame(frame) {
  drawScene(frame.scene);
  const ending = frame.ending ? ` — ${frame.ending}` : '';
  $('watch-readout').textContent = `t = ${frame.seconds.toFixed(2)} s  step ${frame.step}  return ${frame.return.toFixed(3)}${ending}`;
}

export async function evaluate() {
  if (!state.check || !state.check.ok) return say('fix the level first', 'error');
  $('eval-readout').textContent = 'evaluating...';
  try {
    const result = await api('/api/evaluate', { level: state.level, agent: $('agent').value, attempts: Number($('attempts').value), path: state.path });
    $('eval-readout').textContent = `${$('agent').value}: solved ${(100 * result.solve_rate).toFixed(0)}% of ${result.attempts} attempts (mean return ${result.mean_return.toFixed(2)})`;
    $('command').hidden = false;
    $('command').textContent = 'fine-tune it on this level:\n' + result.finetune;
  } catch (error) { say(error.message, 'error'); $('eval-readout').textContent = ''; }
}
