// The head's solids at the current move: the worker's `head` op poses the machine's head parts
// at the preview point's machine axes with the collision check's own code (the core's
// `head_pose`; the page keeps no copy of the head's sizes), and this module draws them,
// translucent, one colour per part (red: in collision on that move's file line, from the
// check's findings), named in a legend. In the machine-coordinates view the solids go through
// the same rigid map as the bed: q ↦ mpos_i + R_i (q − p_i).
import * as THREE from '../vendor/three.module.js';
import { state } from './state.js';
import { $, el } from './dom.js';
import { call } from './worker-client.js';
import { clearGroup } from './view.js';

/** Part colours in the head's order (the core's `head.parts`); a part past the list wraps. */
const PART_COLORS = [0x4fc3f7, 0xffb74d, 0xba68c8, 0x81c784, 0xf06292, 0xa1887f];
/** A part in collision on the move shown. */
const HIT_COLOR = 0xff0000;
/** Opacity of the drawn solids (the toolpath shows through). */
const OPACITY = 0.45;
/** Segments of a drawn frustum's circle. */
const ROUND = 32;

const view = state.view;
/** The newest request (older answers are dropped). */
let seq = 0;

/** The group the head is drawn in (a child of the toolpath group: hidden with it). */
function headGroup() {
  if (!view.headGroup || view.headGroup.parent !== view.pathGroup) {
    view.headGroup = new THREE.Group();
    view.pathGroup.add(view.headGroup);
  }
  return view.headGroup;
}

/** Forget the drawn head and its legend (no preview, or a preview without machine axes). */
export function clearHead(why = '') {
  const vp = $('canvas-wrap');
  vp.dataset.headAsked = vp.dataset.headDone = String(++seq);
  if (view.headGroup) clearGroup(view.headGroup);
  $('head-legend').replaceChildren();
  delete vp.dataset.head;
  delete vp.dataset.headPoint;
  if (why) $('head-legend').append(el('p', { className: 'muted', textContent: why }));
  // (clearGroup asks for a frame only when it removed something: a frame of the big model
  // holds the main thread for seconds under software GL)
}

/**
 * Draw the head at preview point `i` of `d` (its machine axes `d.maxes`); `map` (machine view):
 * `{ p, m, R }` for q ↦ m + R (q − p), else null. The viewport's `data-head-asked` is this
 * request's number, `data-head-done` the number of the one drawn (tests wait for them to meet).
 */
export async function showHead(d, i, map) {
  if (!d?.headMachine || !d.axisCount) {
    clearHead(d?.headError ? `head not drawn: ${d.headError}` : '');
    return;
  }
  const mine = ++seq;
  $('canvas-wrap').dataset.headAsked = String(mine);
  const axes = Array.from(d.maxes.subarray(i * d.axisCount, (i + 1) * d.axisCount));
  let head;
  try {
    ({ head } = await call('head', { machine: d.headMachine, axes }));
  } catch (e) {
    if (mine === seq) clearHead(`head not drawn: ${e.message}`);
    return;
  }
  if (mine !== seq) return;
  const hit = new Set(d.hitSets?.[(d.hit?.[i] ?? 0) - 1] ?? []);
  draw(head, hit, map, i);
  $('canvas-wrap').dataset.headDone = String(mine);
}

/** A point and a direction of the part frame in the frame drawn. */
function placer(map) {
  if (!map) return { at: (v) => new THREE.Vector3(...v), dir: (v) => new THREE.Vector3(...v) };
  return {
    at: (v) => new THREE.Vector3(...v).sub(map.p).applyMatrix3(map.R).add(map.m),
    dir: (v) => new THREE.Vector3(...v).applyMatrix3(map.R),
  };
}

function draw(head, hit, map, i) {
  const g = headGroup();
  clearGroup(g);
  const place = placer(map);
  const drawn = [];
  const legend = $('head-legend');
  legend.replaceChildren(el('p', { className: 'muted', textContent: 'head' }));
  head.parts.forEach((part, k) => {
    const red = hit.has(part.name);
    const color = red ? HIT_COLOR : PART_COLORS[k % PART_COLORS.length];
    const material = new THREE.MeshLambertMaterial({ color, transparent: true, opacity: OPACITY, depthWrite: false, side: THREE.DoubleSide });
    let mesh;
    if (part.kind === 'frustum') {
      const base = place.at(part.base), top = place.at(part.top);
      const along = top.clone().sub(base);
      const h = along.length();
      mesh = new THREE.Mesh(new THREE.CylinderGeometry(part.top_radius, part.base_radius, h, ROUND), material);
      mesh.position.copy(base).addScaledVector(along, 0.5);
      mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), along.normalize());
    } else {
      const [hx, hy, hz] = part.half;
      mesh = new THREE.Mesh(new THREE.BoxGeometry(2 * hx, 2 * hy, 2 * hz), material);
      const [ax, ay, az] = part.axes.map((a) => place.dir(a));
      mesh.quaternion.setFromRotationMatrix(new THREE.Matrix4().makeBasis(ax, ay, az));
      mesh.position.copy(place.at(part.center));
    }
    g.add(mesh);
    drawn.push(describeDrawn(part, mesh, color, red));
    const sw = el('span', { className: 'sw' });
    sw.style.background = `#${new THREE.Color(color).getHexString()}`;
    sw.style.opacity = String(Math.max(OPACITY, 0.7));
    legend.append(el('div', { dataset: { part: part.name, hit: red ? '1' : '0' } }, sw, part.name.replace(/-/g, ' ') + (red ? ' (collision)' : '')));
  });
  // what is drawn, read back from the meshes (a hook for tests and a11y readers)
  const vp = $('canvas-wrap');
  vp.dataset.head = JSON.stringify(drawn);
  vp.dataset.headPoint = String(i);
  view.dirty = true;
}

/**
 * A drawn mesh as numbers, from its own transform: a frustum's end centres (the cylinder's
 * local ±h/2 on y), a box's centre and axes.
 */
function describeDrawn(part, mesh, color, red) {
  mesh.updateMatrix();
  const out = { name: part.name, kind: part.kind, color: `#${new THREE.Color(color).getHexString()}`, hit: red };
  const round = (v) => [v.x, v.y, v.z].map((x) => Number(x.toFixed(5)));
  if (part.kind === 'frustum') {
    const h = mesh.geometry.parameters.height;
    out.base = round(new THREE.Vector3(0, -h / 2, 0).applyMatrix4(mesh.matrix));
    out.top = round(new THREE.Vector3(0, h / 2, 0).applyMatrix4(mesh.matrix));
    out.base_radius = mesh.geometry.parameters.radiusBottom;
    out.top_radius = mesh.geometry.parameters.radiusTop;
  } else {
    out.center = round(mesh.position);
    out.axes = [0, 1, 2].map((k) => round(new THREE.Vector3().setComponent(k, 1).applyQuaternion(mesh.quaternion)));
  }
  return out;
}
