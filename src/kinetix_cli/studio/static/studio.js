// kinetix studio: the page. The level being edited is its kinetix-level/1 JSON value; every edit is checked by the
// server (the project's own parser), which answers with the scene to draw (the same shapes, colours and legend as
// `kinetix render`). Play and watch run on the server's environment; this page only draws and sends keys.

const TOKEN = document.querySelector('meta[name="studio-token"]').content;
const VIEW_X = [-0.1, 5.1], VIEW_Y = [0.0, 5.1];
const OUTLINE = 0.018, RING = 0.065, FIXED_JOINT = 0.05, NOZZLE_LENGTH = 0.11, NOZZLE_WIDTH = 0.12, FLAME = 0.35;
const ARENA = ['floor', 'left_wall', 'right_wall', 'ceiling'];
const ROLES = ['neutral', 'green', 'blue', 'red'];
const KEYS = { q: [0, 1], a: [0, 2], w: [1, 1], s: [1, 2], e: [2, 1], d: [2, 2], r: [3, 1], f: [3, 2], j: [4, 1], k: [5, 1] };

const $ = (id) => document.getElementById(id);
const canvas = $('canvas');
const ctx = canvas.getContext('2d');
const scale = canvas.width / (VIEW_X[1] - VIEW_X[0]);

const state = {
  level: null, path: null, dirty: false, check: null, scene: null,
  selected: null, // {kind: 'body' | 'joint' | 'thruster', index}
  history: [], future: [], mode: 'edit', tool: 'select',
  play: null, playing: false, pressed: new Set(), inFlight: false, timer: null, watchTimer: null,
  choice: 0, // counts the levels chosen (opened, new, random): an answer for an older choice is dropped
};

// --- server --------------------------------------------------------------------------------------------------
async function api(path, body) {
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

function say(text, kind = '') {
  $('message').textContent = text;
  $('message').className = kind;
}

// --- drawing -------------------------------------------------------------------------------------------------
const px = ([x, y]) => [(x - VIEW_X[0]) * scale, (VIEW_Y[1] - y) * scale];
const rgb = (c, f = 1) => `rgb(${c.map((v) => Math.min(255, Math.round(v * f))).join(',')})`;
const mix = (a, b, t) => a.map((v, i) => Math.round((1 - t) * v + t * b[i]));

function polygon(points, fill, line, width) {
  ctx.beginPath();
  points.forEach((p, i) => (i ? ctx.lineTo(...px(p)) : ctx.moveTo(...px(p))));
  ctx.closePath();
  if (fill) { ctx.fillStyle = rgb(fill); ctx.fill(); }
  if (line) { ctx.strokeStyle = rgb(line); ctx.lineWidth = Math.max(1, width * scale); ctx.lineJoin = 'round'; ctx.stroke(); }
}

function disc(centre, radius, fill, line, width) {
  ctx.beginPath();
  ctx.arc(...px(centre), radius * scale, 0, 2 * Math.PI);
  if (fill) { ctx.fillStyle = rgb(fill); ctx.fill(); }
  if (line) { ctx.strokeStyle = rgb(line); ctx.lineWidth = Math.max(1, width * scale); ctx.stroke(); }
}

function segment(a, b, colour, width) {
  ctx.beginPath();
  ctx.moveTo(...px(a));
  ctx.lineTo(...px(b));
  ctx.strokeStyle = rgb(colour);
  ctx.lineWidth = Math.max(1, width * scale);
  ctx.stroke();
}

function drawScene(scene) {
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (!scene) return;
  for (const w of scene.walls) {
    polygon(w.strip, w.fill, null, 0);
    segment(w.face[0], w.face[1], w.line, 0.02);
  }
  for (const s of scene.shapes) {
    if (s.points) polygon(s.points, s.fill, s.line, OUTLINE);
    else {
      disc(s.centre, s.radius, s.fill, s.line, OUTLINE);
      const r = s.radius - OUTLINE / 2;
      segment(s.centre, [s.centre[0] + r * Math.cos(s.angle), s.centre[1] + r * Math.sin(s.angle)], s.line, OUTLINE);
    }
  }
  const labels = [];
  for (const j of scene.joints) {
    const a = j.anchor;
    if (j.fixed) {
      const h = FIXED_JOINT;
      const sq = [[a[0] - h, a[1] - h], [a[0] + h, a[1] - h], [a[0] + h, a[1] + h], [a[0] - h, a[1] + h]];
      polygon(sq, [255, 255, 255], [20, 20, 20], 0.012);
      segment(sq[0], sq[2], [20, 20, 20], 0.012);
      segment(sq[1], sq[3], [20, 20, 20], 0.012);
      continue;
    }
    if (j.colour && j.action !== undefined && Math.abs(j.action) > 0.05) disc(a, RING * 1.9, mix(j.colour, [255, 255, 255], 0.55), null, 0);
    disc(a, RING, j.colour || [255, 255, 255], [20, 20, 20], 0.014);
    disc(a, RING * 0.35, [255, 255, 255], [20, 20, 20], 0.01);
    if (j.label) labels.push([a, j.label, j.colour]);
  }
  for (const t of scene.thrusters) {
    const f = [Math.cos(t.push), Math.sin(t.push)], side = [-f[1], f[0]], a = t.anchor;
    const at = (k, s) => [a[0] - k * f[0] + s * side[0], a[1] - k * f[1] + s * side[1]];
    if (t.action !== undefined && t.action > 0.05) {
      const length = NOZZLE_LENGTH + FLAME * t.action;
      polygon([at(0, 0.8 * NOZZLE_WIDTH), at(length, 0), at(0, -0.8 * NOZZLE_WIDTH)], mix(t.colour, [255, 60, 0], 0.3), null, 0);
      polygon([at(0, 0.4 * NOZZLE_WIDTH), at(0.6 * length, 0), at(0, -0.4 * NOZZLE_WIDTH)], [255, 245, 170], null, 0);
    }
    const half = NOZZLE_WIDTH / 2;
    polygon([at(0, 0.35 * half), at(NOZZLE_LENGTH, half), at(NOZZLE_LENGTH, -half), at(0, -0.35 * half)], t.colour, [20, 20, 20], 0.012);
    labels.push([at(NOZZLE_LENGTH + 0.04, 0), t.label, t.colour]);
  }
  ctx.font = '12px system-ui, sans-serif';
  for (const [point, text, colour] of labels) {
    const [x, y] = px(point);
    const offset = RING * scale + 1;
    ctx.lineWidth = 3;
    ctx.strokeStyle = '#fff';
    ctx.strokeText(text, x + offset, y - offset);
    ctx.fillStyle = rgb(colour, 0.6);
    ctx.fillText(text, x + offset, y - offset);
  }
  drawSelection();
  $('legend').replaceChildren(...scene.legend.map(([text, colour]) => {
    const item = document.createElement('span');
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = rgb(colour);
    item.append(swatch, text);
    return item;
  }));
}

function drawSelection() {
  const sel = state.selected;
  if (!sel || state.mode !== 'edit' || !state.scene) return;
  ctx.save();
  ctx.setLineDash([5, 4]);
  ctx.strokeStyle = '#2b6cb0';
  ctx.lineWidth = 2;
  if (sel.kind === 'body') {
    const shape = shapeOfBody(sel.index);
    if (shape && shape.points) { ctx.beginPath(); shape.points.forEach((p, i) => (i ? ctx.lineTo(...px(p)) : ctx.moveTo(...px(p)))); ctx.closePath(); ctx.stroke(); }
    if (shape && shape.centre) { ctx.beginPath(); ctx.arc(...px(shape.centre), shape.radius * scale + 3, 0, 2 * Math.PI); ctx.stroke(); }
    const at = handles();
    if (at) {
      ctx.setLineDash([]);
      ctx.fillStyle = '#2b6cb0';
      ctx.beginPath(); ctx.moveTo(...px(at.centre)); ctx.lineTo(...px(at.rotate)); ctx.stroke();
      ctx.beginPath(); ctx.arc(...px(at.rotate), HANDLE * scale, 0, 2 * Math.PI); ctx.fill();
      const [x, y] = px(at.resize), r = HANDLE * scale;
      ctx.fillRect(x - r, y - r, 2 * r, 2 * r);
    }
  } else {
    const list = sel.kind === 'joint' ? state.scene.joints : state.scene.thrusters;
    const item = list.find((x) => x.index === sel.index);
    if (item) { ctx.beginPath(); ctx.arc(...px(item.anchor), 0.12 * scale, 0, 2 * Math.PI); ctx.stroke(); }
  }
  ctx.restore();
}

// --- the level ----------------------------------------------------------------------------------------------
function newLevel() {
  return {
    format: 'kinetix-level/1', name: 'untitled', description: 'make green touch blue', size: 's',
    bodies: [{ name: 'ball', shape: 'circle', radius: 0.25, position: [2.5, 2.5], role: 'green' }],
  };
}

const bodies = () => state.level.bodies || [];
const joints = () => state.level.joints || [];
const thrusters = () => state.level.thrusters || [];
const shapeOfBody = (i) => state.check && state.check.ok && state.scene.shapes.find((s) => s.slot === state.check.slots[i]);
const round = (v) => Math.round(v * 1000) / 1000;

function edit(change) { // record the level for undo, change it, check it again (a promise of the check)
  state.history.push(JSON.stringify(state.level));
  if (state.history.length > 200) state.history.shift();
  state.future = [];
  change(state.level);
  state.dirty = true;
  return refresh();
}

function restore(from, to) {
  if (!from.length) return;
  to.push(JSON.stringify(state.level));
  state.level = JSON.parse(from.pop());
  state.selected = null;
  state.dirty = true;
  refresh();
}

let checking = null;
async function refresh() { // check the level; draw what the server says it is
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
  levelForm();
  selectionForm();
}

function uniqueName(prefix) {
  const used = new Set([...bodies(), ...joints(), ...thrusters()].map((x) => x.name));
  for (let k = 0; ; k++) if (!used.has(`${prefix}-${k}`)) return `${prefix}-${k}`;
}

function group(index) { // the bodies joined to body `index`, directly or through a chain (arena not included)
  const names = new Set([bodies()[index].name]);
  for (let grew = true; grew;) {
    grew = false;
    for (const j of joints()) {
      for (const [x, y] of [[j.a, j.b], [j.b, j.a]]) {
        if (names.has(x) && !ARENA.includes(y) && !names.has(y)) { names.add(y); grew = true; }
      }
    }
  }
  return names;
}

function moveGroup(level, index, dx, dy) {
  const names = group(index);
  const shift = (p) => [round(p[0] + dx), round(p[1] + dy)];
  for (const b of level.bodies) if (names.has(b.name)) b.position = shift(b.position);
  for (const j of level.joints || []) if (names.has(j.a) || names.has(j.b)) j.anchor = shift(j.anchor);
  for (const t of level.thrusters || []) if (names.has(t.body) && t.anchor) t.anchor = shift(t.anchor);
}

function rotateGroup(level, index, degrees) {
  const names = group(index), pivot = level.bodies[index].position;
  const c = Math.cos(degrees * Math.PI / 180), s = Math.sin(degrees * Math.PI / 180);
  const turn = (p) => { const x = p[0] - pivot[0], y = p[1] - pivot[1]; return [round(pivot[0] + c * x - s * y), round(pivot[1] + s * x + c * y)]; };
  for (const b of level.bodies) if (names.has(b.name)) { b.position = turn(b.position); b.angle_deg = round((b.angle_deg || 0) + degrees); }
  for (const j of level.joints || []) if (names.has(j.a) || names.has(j.b)) j.anchor = turn(j.anchor);
  for (const t of level.thrusters || []) if (names.has(t.body)) { if (t.anchor) t.anchor = turn(t.anchor); t.direction_deg = round(t.direction_deg + degrees); }
}

function resize(level, index, factor) {
  const b = level.bodies[index];
  if (b.shape === 'circle') b.radius = round(b.radius * factor);
  else if (b.shape === 'box') b.size = b.size.map((v) => round(v * factor));
  else b.vertices = b.vertices.map((p) => p.map((v) => round(v * factor)));
}

function remove(level, sel) {
  if (sel.kind === 'joint') level.joints.splice(sel.index, 1);
  else if (sel.kind === 'thruster') level.thrusters.splice(sel.index, 1);
  else {
    const name = level.bodies[sel.index].name;
    level.bodies.splice(sel.index, 1);
    level.joints = (level.joints || []).filter((j) => j.a !== name && j.b !== name);
    level.thrusters = (level.thrusters || []).filter((t) => t.body !== name);
  }
  for (const key of ['joints', 'thrusters']) if (level[key] && !level[key].length) delete level[key];
}

// --- picking ------------------------------------------------------------------------------------------------
const HANDLE = 0.07; // radius of the rotate and resize handles [m]

function handles() { // the selected body's centre, rotate handle (above it) and resize handle (lower right corner)
  const sel = state.selected;
  if (!sel || sel.kind !== 'body' || state.mode !== 'edit') return null;
  const shape = shapeOfBody(sel.index);
  if (!shape) return null;
  const corners = shape.points || [-1, 1].map((d) => shape.centre.map((v) => v + d * shape.radius));
  const xs = corners.map((p) => p[0]), ys = corners.map((p) => p[1]);
  const centre = bodies()[sel.index].position;
  return { centre, rotate: [centre[0], Math.max(...ys) + 0.3], resize: [Math.max(...xs) + 0.12, Math.min(...ys) - 0.12] };
}

function handleAt(point) {
  const at = handles();
  if (!at) return null;
  const near = (q) => Math.hypot(point[0] - q[0], point[1] - q[1]) < 2 * HANDLE;
  return near(at.rotate) ? { kind: 'rotate', at } : near(at.resize) ? { kind: 'resize', at } : null;
}

function world(event) {
  const r = canvas.getBoundingClientRect();
  const x = (event.clientX - r.left) * canvas.width / r.width, y = (event.clientY - r.top) * canvas.height / r.height;
  return [x / scale + VIEW_X[0], VIEW_Y[1] - y / scale];
}

function inside(points, [x, y]) {
  let hit = false;
  for (let i = 0, j = points.length - 1; i < points.length; j = i++) {
    const [xi, yi] = points[i], [xj, yj] = points[j];
    if ((yi > y) !== (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) hit = !hit;
  }
  return hit;
}

function bodiesAt(point) { // body indices under a point, top-most first
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

function pick(point) {
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

let drag = null;
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

// --- forms --------------------------------------------------------------------------------------------------
function field(label, input, bad = false) {
  const row = document.createElement('div');
  row.className = 'field' + (bad ? ' bad' : '');
  const l = document.createElement('label');
  l.textContent = label;
  row.append(l, input);
  return row;
}

function number(value, onChange, step = 0.05) {
  const input = document.createElement('input');
  input.type = 'number';
  input.step = step;
  input.value = value;
  input.addEventListener('change', () => { const v = Number(input.value); if (input.value !== '' && Number.isFinite(v)) onChange(v); });
  return input;
}

function text(value, onChange) {
  const input = document.createElement('input');
  input.type = 'text';
  input.value = value ?? '';
  input.addEventListener('change', () => onChange(input.value));
  return input;
}

function choice(value, options, onChange) {
  const select = document.createElement('select');
  for (const option of options) select.add(new Option(String(option), String(option)));
  select.value = String(value);
  select.addEventListener('change', () => onChange(select.value));
  return select;
}

function check(value, onChange) {
  const input = document.createElement('input');
  input.type = 'checkbox';
  input.checked = !!value;
  input.addEventListener('change', () => onChange(input.checked));
  return input;
}

const pair = (value, onChange, step) => {
  const span = document.createElement('span');
  const v = value || [0, 0];
  span.append(number(v[0], (x) => onChange([x, v[1]]), step), number(v[1], (y) => onChange([v[0], y]), step));
  return span;
};

function isBad(entity, name) { // the check's error is about this field (a duplicate name: on both bodies)
  const c = state.check;
  return !!(c && !c.ok && c.field === name && (c.entity === entity || (c.also || []).includes(entity)));
}

function levelForm() {
  const L = state.level, form = $('level-form');
  const set = (key) => (v) => edit((level) => { if (v === '' || v === 'auto') delete level[key]; else level[key] = v; });
  const rows = [
    field('name', text(L.name, set('name')), isBad('level', 'name')),
    field('description', text(L.description, set('description'))),
    field('size', choice(L.size || 'auto', ['auto', 's', 'm', 'l'], set('size')), isBad('level', 'size')),
    field('gravity', pair(L.gravity || [0, -9.81], (g) => edit((level) => (level.gravity = g)), 0.5)),
  ];
  for (const wall of ARENA) {
    const entry = (L.arena && L.arena[wall]) || {};
    const setWall = (key, value, fallback) => edit((level) => {
      level.arena = level.arena || {};
      const w = level.arena[wall] = level.arena[wall] || {};
      if (value === fallback) delete w[key]; else w[key] = value;
      if (!Object.keys(w).length) delete level.arena[wall];
    });
    const span = document.createElement('span');
    span.append(check(entry.enabled !== false, (on) => setWall('enabled', on, true)), choice(entry.role || 'neutral', ROLES, (r) => setWall('role', r, 'neutral')));
    rows.push(field(wall.replace('_', ' '), span));
  }
  form.replaceChildren(...rows);
}

function selectionForm() {
  const sel = state.selected, form = $('selection-form');
  const names = bodies().map((b) => b.name);
  if (!sel || (sel.kind === 'body' && !bodies()[sel.index]) || (sel.kind === 'joint' && !joints()[sel.index]) || (sel.kind === 'thruster' && !thrusters()[sel.index])) {
    $('selection-title').textContent = 'Selection';
    form.replaceChildren();
    return;
  }
  const list = { body: bodies(), joint: joints(), thruster: thrusters() }[sel.kind];
  const item = list[sel.index];
  const entity = `${{ body: 'bodies', joint: 'joints', thruster: 'thrusters' }[sel.kind]}[${sel.index}]`;
  const set = (key, fallback) => (v) => edit(() => { const it = list[sel.index]; if (v === fallback) delete it[key]; else it[key] = v; });
  const f = (label, key, input) => field(label, input, isBad(entity, key));
  $('selection-title').textContent = `${sel.kind} ${item.name || sel.index}`;
  const rows = [];
  if (sel.kind === 'body') {
    rows.push(f('name', 'name', text(item.name, set('name'))), f('position', 'position', pair(item.position, set('position'))));
    rows.push(f('angle_deg', 'angle_deg', number(item.angle_deg || 0, set('angle_deg', 0), 5)));
    if (item.shape === 'box') rows.push(f('size', 'size', pair(item.size, set('size'))));
    if (item.shape === 'circle') rows.push(f('radius', 'radius', number(item.radius, set('radius'))));
    if (item.shape === 'polygon') rows.push(f('vertices', 'vertices', text(JSON.stringify(item.vertices), (v) => { try { set('vertices')(JSON.parse(v)); } catch { say('vertices: not JSON', 'error'); } })));
    rows.push(f('role', 'role', choice(item.role || 'neutral', ROLES, set('role', 'neutral'))));
    rows.push(f('fixed', 'fixed', check(item.fixed, set('fixed', false))));
    rows.push(f('density', 'density', number(item.density ?? 1, set('density', 1), 0.1)));
    rows.push(f('friction', 'friction', number(item.friction ?? 1, set('friction', 1), 0.1)));
    rows.push(f('restitution', 'restitution', number(item.restitution ?? 0, set('restitution', 0), 0.1)));
    rows.push(f('collision_mode', 'collision_mode', choice(item.collision_mode ?? 1, [0, 1, 2], (v) => set('collision_mode', 1)(Number(v)))));
  } else if (sel.kind === 'joint') {
    const motor = item.motor;
    rows.push(f('name', 'name', text(item.name, set('name'))));
    rows.push(f('type', 'type', choice(item.type || 'revolute', ['revolute', 'fixed'], set('type', 'revolute'))));
    rows.push(f('a', 'a', choice(item.a, [...ARENA, ...names], set('a'))), f('b', 'b', choice(item.b, [...ARENA, ...names], set('b'))));
    rows.push(f('anchor', 'anchor', pair(item.anchor, set('anchor'))));
    rows.push(f('motor', 'motor', choice(motor ? motor.binding : 'none', ['none', 0, 1, 2, 3, 'auto'], (v) => set('motor')(v === 'none' ? undefined : { ...(motor || {}), binding: v === 'auto' ? 'auto' : Number(v) }))));
    if (motor) {
      rows.push(f('speed', 'speed', number(motor.speed ?? 1, (v) => set('motor')({ ...motor, speed: v }), 0.1)));
      rows.push(f('power', 'power', number(motor.power ?? 1, (v) => set('motor')({ ...motor, power: v }), 0.1)));
    }
    const limits = item.limits_deg;
    rows.push(f('limits', 'limits_deg', check(!!limits, (on) => set('limits_deg')(on ? [-45, 45] : undefined))));
    if (limits) rows.push(f('limits_deg', 'limits_deg', pair(limits, set('limits_deg'), 5)));
  } else {
    rows.push(f('name', 'name', text(item.name, set('name'))));
    rows.push(f('body', 'body', choice(item.body, names, set('body'))));
    rows.push(f('anchor', 'anchor', pair(item.anchor, set('anchor'))));
    rows.push(f('direction_deg', 'direction_deg', number(item.direction_deg, set('direction_deg'), 15)));
    rows.push(f('power', 'power', number(item.power ?? 1, set('power', 1), 0.1)));
    rows.push(f('binding', 'binding', choice(item.binding ?? 0, [0, 1], (v) => set('binding', 0)(Number(v)))));
  }
  form.replaceChildren(...rows);
}

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

function currentAction() {
  const action = [0, 0, 0, 0, 0, 0];
  for (const key of state.pressed) { const [entry, value] = KEYS[key]; action[entry] = value; }
  return action;
}

// --- play ---------------------------------------------------------------------------------------------------
async function playStart() {
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

function schedule() {
  clearInterval(state.timer);
  state.timer = setInterval(playTick, 1000 / 30);
}

async function playTick() {
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

function showFrame(frame) {
  drawScene(frame.scene);
  const ending = frame.ending ? ` — ${frame.ending}` : '';
  $('play-readout').textContent = `t = ${frame.seconds.toFixed(2)} s  step ${frame.step}  reward ${frame.reward.toFixed(3)}  return ${frame.return.toFixed(3)}${ending}`;
  $('play-keep').disabled = frame.ending !== 'solved';
  if (frame.ending) say(`episode ${frame.ending} after ${frame.step} steps`, frame.ending === 'solved' ? 'ok' : 'error');
}

async function keepSolution() {
  try {
    const answer = await api('/api/play/solution', { play: state.play, level: state.level });
    await edit((level) => { level.solution = answer.level.solution; });
    say('the played episode is now the level\'s solution; save to write it', 'ok');
  } catch (error) { say(error.message, 'error'); }
}

// --- watch --------------------------------------------------------------------------------------------------
// The agent plays live on the server: one request per step, at the pace of its environment's step.
async function watch() {
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

function watchFrame(frame) {
  drawScene(frame.scene);
  const ending = frame.ending ? ` — ${frame.ending}` : '';
  $('watch-readout').textContent = `t = ${frame.seconds.toFixed(2)} s  step ${frame.step}  return ${frame.return.toFixed(3)}${ending}`;
}

async function evaluate() {
  if (!state.check || !state.check.ok) return say('fix the level first', 'error');
  $('eval-readout').textContent = 'evaluating...';
  try {
    const result = await api('/api/evaluate', { level: state.level, agent: $('agent').value, attempts: Number($('attempts').value), path: state.path });
    $('eval-readout').textContent = `${$('agent').value}: solved ${(100 * result.solve_rate).toFixed(0)}% of ${result.attempts} attempts (mean return ${result.mean_return.toFixed(2)})`;
    $('command').hidden = false;
    $('command').textContent = 'fine-tune it on this level:\n' + result.finetune;
  } catch (error) { say(error.message, 'error'); $('eval-readout').textContent = ''; }
}

// --- files --------------------------------------------------------------------------------------------------
async function listFiles() {
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

async function openFile(path) {
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

function load(level, path, dirty = false) { // the level on the page from now on (a promise of its check)
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

async function save(path, overwrite) {
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

function saveAs() {
  const path = prompt('Save as (a path inside the studio\'s folder):', state.path || 'new-level.json');
  if (path) save(path, false);
}

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

async function generate() {
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

async function mutate() {
  const choice = state.choice, before = JSON.stringify(state.level);
  try {
    const answer = await api('/api/mutate', { level: state.level, seed: Math.floor(Math.random() * 2 ** 31), edits: 1 });
    if (choice !== state.choice || before !== JSON.stringify(state.level)) return; // the level changed meanwhile
    edit((level) => { for (const key of Object.keys(level)) delete level[key]; Object.assign(level, answer.level); });
  } catch (error) { say(error.message, 'error'); }
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
