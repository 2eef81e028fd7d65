// Edits of a level's JSON value: new levels, unique names, moving, turning and resizing a body with everything
// joined to it, removing an entity with what hangs on it.

import { ARENA, bodies, joints, round, thrusters } from './core.js';

export function newLevel() {
  return {
    format: 'kinetix-level/1', name: 'untitled', description: 'make green touch blue', size: 's',
    bodies: [{ name: 'ball', shape: 'circle', radius: 0.25, position: [2.5, 2.5], role: 'green' }],
  };
}

export function uniqueName(prefix) {
  const used = new Set([...bodies(), ...joints(), ...thrusters()].map((x) => x.name));
  for (let k = 0; ; k++) if (!used.has(`${prefix}-${k}`)) return `${prefix}-${k}`;
}

export function group(index) { // the bodies joined to body `index`, directly or through a chain (arena not included)
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

export function moveGroup(level, index, dx, dy) {
  const names = group(index);
  const shift = (p) => [round(p[0] + dx), round(p[1] + dy)];
  for (const b of level.bodies) if (names.has(b.name)) b.position = shift(b.position);
  for (const j of level.joints || []) if (names.has(j.a) || names.has(j.b)) j.anchor = shift(j.anchor);
  for (const t of level.thrusters || []) if (names.has(t.body) && t.anchor) t.anchor = shift(t.anchor);
}

export function rotateGroup(level, index, degrees) {
  const names = group(index), pivot = level.bodies[index].position;
  const c = Math.cos(degrees * Math.PI / 180), s = Math.sin(degrees * Math.PI / 180);
  const turn = (p) => { const x = p[0] - pivot[0], y = p[1] - pivot[1]; return [round(pivot[0] + c * x - s * y), round(pivot[1] + s * x + c * y)]; };
  for (const b of level.bodies) if (names.has(b.name)) { b.position = turn(b.position); b.angle_deg = round((b.angle_deg || 0) + degrees); }
  for (const j of level.joints || []) if (names.has(j.a) || names.has(j.b)) j.anchor = turn(j.anchor);
  for (const t of level.thrusters || []) if (names.has(t.body)) { if (t.anchor) t.anchor = turn(t.anchor); t.direction_deg = round(t.direction_deg + degrees); }
}

export function resize(level, index, factor) {
  const b = level.bodies[index];
  if (b.shape === 'circle') b.radius = round(b.radius * factor);
  else if (b.shape === 'box') b.size = b.size.map((v) => round(v * factor));
  else b.vertices = b.vertices.map((p) => p.map((v) => round(v * factor)));
}

export function remove(level, sel) {
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
