// The property forms of the level and of the selected body, joint or thruster; a field the server's check names is
// outlined.

import { $, ARENA, ROLES, bodies, joints, say, state, thrusters } from './core.js';
import { edit } from './editing.js';

export function field(label, input, bad = false) {
  const row = document.createElement('div');
  row.className = 'field' + (bad ? ' bad' : '');
  const l = document.createElement('label');
  l.textContent = label;
  row.append(l, input);
  return row;
}

export function number(value, onChange, step = 0.05) {
  const input = document.createElement('input');
  input.type = 'number';
  input.step = step;
  input.value = value;
  input.addEventListener('change', () => { const v = Number(input.value); if (input.value !== '' && Number.isFinite(v)) onChange(v); });
  return input;
}

export function text(value, onChange) {
  const input = document.createElement('input');
  input.type = 'text';
  input.value = value ?? '';
  input.addEventListener('change', () => onChange(input.value));
  return input;
}

export function choice(value, options, onChange) {
  const select = document.createElement('select');
  for (const option of options) select.add(new Option(String(option), String(option)));
  select.value = String(value);
  select.addEventListener('change', () => onChange(select.value));
  return select;
}

export function check(value, onChange) {
  const input = document.createElement('input');
  input.type = 'checkbox';
  input.checked = !!value;
  input.addEventListener('change', () => onChange(input.checked));
  return input;
}

export const pair = (value, onChange, step) => {
  const span = document.createElement('span');
  const v = value || [0, 0];
  span.append(number(v[0], (x) => onChange([x, v[1]]), step), number(v[1], (y) => onChange([v[0], y]), step));
  return span;
};

export function isBad(entity, name) { // the check's error is about this field (a duplicate name: on both bodies)
  const c = state.check;
  return !!(c && !c.ok && c.field === name && (c.entity === entity || (c.also || []).includes(entity)));
}

export function levelForm() {
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

export function selectionForm() {
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
