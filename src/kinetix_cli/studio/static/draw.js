// Drawing: the scene the server computed (shapes, joints, thrusters, legend, as `kinetix render` draws them), the
// selection and its handles. World coordinates in metres; the canvas shows x in [-0.1, 5.1], y in [0, 5.1].

import { $, VIEW_X, VIEW_Y, bodies, shapeOfBody, state } from './core.js';

const OUTLINE = 0.018, RING = 0.065, FIXED_JOINT = 0.05, NOZZLE_LENGTH = 0.11, NOZZLE_WIDTH = 0.12, FLAME = 0.35;
export const canvas = $('canvas');
export const ctx = canvas.getContext('2d');
export const scale = canvas.width / (VIEW_X[1] - VIEW_X[0]);

export const px = ([x, y]) => [(x - VIEW_X[0]) * scale, (VIEW_Y[1] - y) * scale];
export const rgb = (c, f = 1) => `rgb(${c.map((v) => Math.min(255, Math.round(v * f))).join(',')})`;
export const mix = (a, b, t) => a.map((v, i) => Math.round((1 - t) * v + t * b[i]));

export function polygon(points, fill, line, width) {
  ctx.beginPath();
  points.forEach((p, i) => (i ? ctx.lineTo(...px(p)) : ctx.moveTo(...px(p))));
  ctx.closePath();
  if (fill) { ctx.fillStyle = rgb(fill); ctx.fill(); }
  if (line) { ctx.strokeStyle = rgb(line); ctx.lineWidth = Math.max(1, width * scale); ctx.lineJoin = 'round'; ctx.stroke(); }
}

export function disc(centre, radius, fill, line, width) {
  ctx.beginPath();
  ctx.arc(...px(centre), radius * scale, 0, 2 * Math.PI);
  if (fill) { ctx.fillStyle = rgb(fill); ctx.fill(); }
  if (line) { ctx.strokeStyle = rgb(line); ctx.lineWidth = Math.max(1, width * scale); ctx.stroke(); }
}

export function segment(a, b, colour, width) {
  ctx.beginPath();
  ctx.moveTo(...px(a));
  ctx.lineTo(...px(b));
  ctx.strokeStyle = rgb(colour);
  ctx.lineWidth = Math.max(1, width * scale);
  ctx.stroke();
}

export function drawScene(scene) {
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

export function drawSelection() {
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

export const HANDLE = 0.07; // radius of the rotate and resize handles [m]

export function handles() { // the selected body's centre, rotate handle (above it) and resize handle (lower right corner)
  const sel = state.selected;
  if (!sel || sel.kind !== 'body' || state.mode !== 'edit') return null;
  const shape = shapeOfBody(sel.index);
  if (!shape) return null;
  const corners = shape.points || [-1, 1].map((d) => shape.centre.map((v) => v + d * shape.radius));
  const xs = corners.map((p) => p[0]), ys = corners.map((p) => p[1]);
  const centre = bodies()[sel.index].position;
  return { centre, rotate: [centre[0], Math.max(...ys) + 0.3], resize: [Math.max(...xs) + 0.12, Math.min(...ys) - 0.12] };
}
