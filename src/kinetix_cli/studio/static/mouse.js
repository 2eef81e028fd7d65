// The canvas under the mouse: pick, drag, turn and resize bodies; add shapes, joints and thrusters with the tools.

import { VIEW_X, VIEW_Y, bodies, joints, round, say, state, thrusters } from './core.js';
import { HANDLE, canvas, drawScene, handles, scale } from './draw.js';
import { edit, refresh } from './editing.js';
import { selectionForm } from './forms.js';
import { moveGroup, resize, rotateGroup, uniqueName } from './level.js';

export function handleAt(point) {
  const at = handles();
  if (!at) return null;
  const near = (q) => Math.hypot(point[0] - q[0], point[1] - q[1]) < 2 * HANDLE;
  return near(at.rotate) ? { kind: 'rotate', at } : near(at.resize) ? { kind: 'resize', at } : null;
}

export function world(event) {
  const r = canvas.getBoundingClientRect();
  const x = (event.clientX - r.left) * canvas.width / r.width, y = (event.clientY - r.top) * canvas.height / r.height;
  return [x / scale + VIEW_X[0], VIEW_Y[1] - y / scale];
}

export function inside(points, [x, y]) {
  let hit = false;
  for (let i = 0, j = points.length - 1; i < points.length; j = i++) {
    const [xi, yi] = points[i], [xj, yj] = points[j];
    if ((yi > y) !== (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) hit = !hit;
  }
  return hit;
}

export function bodiesAt(point) { // body indices under a point, top-most first
  if (!state.check || !state.check.ok) return [];
  const hits = [];
  for (const shape of [...state.scene.shapes].reverse()) {
    const index = state.check.slots.indexOf(shape.slot);
    if (index < 0) continue;
    const hit = shape.points ? inside(shape.points, point) : Math.hypot(point[0] - shape.centre[0], point[1] - shape.centre[1]) <= shape.radius;
    if (hit) hits.push(index);
  }
  return hits;
}

export function pick(point) {
  if (!state.check || !state.check.ok) return null;
  const near = (list, kind) => {
    const item = list.find((x) => Math.hypot(point[0] - x.anchor[0], point[1] - x.anchor[1]) < 0.1);
    return item && { kind, index: item.index };
  };
  const hit = near(state.scene.thrusters, 'thruster') || near(state.scene.joints, 'joint');
  if (hit) return hit;
  const under = bodiesAt(point);
  return under.length ? { kind: 'body', index: under[0] } : null;
}

export let drag = null;
canvas.addEventListener('mousedown', (event) => {
  canvas.focus();
  if (state.mode !== 'edit') return;
  const p = world(event).map(round);
  const tool = state.tool;
  if (tool === 'box' || tool === 'circle' || tool === 'polygon') {
    const body = { name: uniqueName(tool), shape: tool, position: p };
    if (tool === 'box') body.size = [0.5, 0.5];
    if (tool === 'circle') body.radius = 0.25;
    if (tool === 'polygon') body.vertices = [[-0.3, -0.25], [0.3, -0.25], [0, 0.3]];
    edit((level) => (level.bodies = level.bodies || []).push(body));
    state.selected = { kind: 'body', index: bodies().length - 1 };
    return;
  }
  if (tool === 'joint') {
    const under = bodiesAt(p);
    if (!under.length) return say('a joint needs a body under the click', 'error');
    const a = under.length > 1 ? bodies()[under[1]].name : 'floor';
    edit((level) => (level.joints = level.joints || []).push({ name: uniqueName('joint'), a, b: bodies()[under[0]].name, anchor: p }));
    state.selected = { kind: 'joint', index: joints().length - 1 };
    return;
  }
  if (tool === 'thruster') {
    const under = bodiesAt(p);
    if (!under.length) return say('a thruster needs a body under the click', 'error');
    edit((level) => (level.thrusters = level.thrusters || []).push({ name: uniqueName('thruster'), body: bodies()[under[0]].name, anchor: p, direction_deg: 90, power: 1, binding: 0 }));
    state.selected = { kind: 'thruster', index: thrusters().length - 1 };
    return;
  }
  const handle = handleAt(p);
  if (handle) { // turn or scale the selected body by its handle
    const [cx, cy] = handle.at.centre;
    drag = { handle: handle.kind, index: state.selected.index, centre: handle.at.centre, moved: false,
      angle: Math.atan2(p[1] - cy, p[0] - cx) * 180 / Math.PI, radius: Math.hypot(p[0] - cx, p[1] - cy) };
    return;
  }
  state.selected = pick(p);
  if (state.selected && state.selected.kind === 'body') drag = { start: p, last: p, index: state.selected.index, moved: false };
  drawScene(state.scene);
  selectionForm();
});

canvas.addEventListener('mousemove', (event) => {
  if (!drag) return;
  const p = world(event).map(round);
  const begin = () => { if (!drag.moved) { state.history.push(JSON.stringify(state.level)); state.future = []; drag.moved = true; } };
  if (drag.handle === 'rotate') { // whole degrees, about the body's position, with everything joined to it
    const angle = Math.atan2(p[1] - drag.centre[1], p[0] - drag.centre[0]) * 180 / Math.PI;
    const turn = Math.round(((angle - drag.angle + 540) % 360) - 180);
    if (!turn) return;
    begin();
    rotateGroup(state.level, drag.index, turn);
    drag.angle += turn;
  } else if (drag.handle === 'resize') { // in steps of 2% of the distance to the centre
    const radius = Math.hypot(p[0] - drag.centre[0], p[1] - drag.centre[1]);
    const factor = radius / drag.radius;
    if (Math.abs(factor - 1) < 0.02 || radius < 0.05) return;
    begin();
    resize(state.level, drag.index, factor);
    drag.radius = radius;
  } else {
    const dx = round(p[0] - drag.last[0]), dy = round(p[1] - drag.last[1]);
    if (!dx && !dy) return;
    begin();
    moveGroup(state.level, drag.index, dx, dy);
    drag.last = p;
  }
  state.dirty = true;
  refresh();
});

window.addEventListener('mouseup', () => { drag = null; });
