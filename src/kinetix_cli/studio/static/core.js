// The page's shared ground: the session token, constants, the page's state, the server call and the message line.

export const TOKEN = document.querySelector('meta[name="studio-token"]').content;
export const VIEW_X = [-0.1, 5.1], VIEW_Y = [0.0, 5.1];
export const ARENA = ['floor', 'left_wall', 'right_wall', 'ceiling'];
export const ROLES = ['neutral', 'green', 'blue', 'red'];
export const KEYS = { q: [0, 1], a: [0, 2], w: [1, 1], s: [1, 2], e: [2, 1], d: [2, 2], r: [3, 1], f: [3, 2], j: [4, 1], k: [5, 1] };

export const $ = (id) => document.getElementById(id);

export const state = {
  level: null, path: null, dirty: false, check: null, scene: null,
  selected: null, // {kind: 'body' | 'joint' | 'thruster', index}
  history: [], future: [], mode: 'edit', tool: 'select',
  play: null, playing: false, pressed: new Set(), inFlight: false, timer: null, watchTimer: null,
  choice: 0, // counts the levels chosen (opened, new, random): an answer for an older choice is dropped
};

export async function api(path, body) {
  const init = { method: body === undefined ? 'GET' : 'POST', headers: { 'X-Studio-Token': TOKEN } };
  if (body !== undefined) {
    init.headers['Content-Type'] = 'application/json';
    init.body = JSON.stringify(body);
  }
  const response = await fetch(path, init);
  const isJson = (response.headers.get('content-type') || '').includes('json');
  const data = isJson ? await response.json() : await response.blob();
  if (!response.ok) {
    const error = new Error(isJson ? data.error : response.statusText);
    error.status = response.status;
    throw error;
  }
  return data;
}

export function say(text, kind = '') {
  $('message').textContent = text;
  $('message').className = kind;
}

export const bodies = () => state.level.bodies || [];
export const joints = () => state.level.joints || [];
export const thrusters = () => state.level.thrusters || [];
export const shapeOfBody = (i) => state.check && state.check.ok && state.scene.shapes.find((s) => s.slot === state.check.slots[i]);
export const round = (v) => Math.round(v * 1000) / 1000;
