// The toolpath preview: the worker's decimated toolpath as line segments coloured by feature,
// tilt or layer; layer and move sliders; the tool axis and the head's solids (head.js) at the
// current move; and, for machines that move their bed, the head path in the machine's own X Y Z
// with the bed at its pose.
import * as THREE from '../vendor/three.module.js';
import { state } from './state.js';
import { $ } from './dom.js';
import { clearGroup, frame, legendTilt, showModel, tiltColor } from './view.js';
import { currentMachine } from './machines.js';
import { showHead } from './head.js';

const view = state.view;
const tp = state.tp;

/**
 * Colours of the features by name (the names, and their numbers in the toolpath buffer, are
 * the core's `describe().features`); a feature without a colour here gets one from its name.
 */
const FEATURE_COLORS = {
  unknown: 0xc8c8c8, 'outer-wall': 0xff7f0e, 'inner-wall': 0xffd166, 'overhang-wall': 0x0000ff, infill: 0xb03030,
  'solid-infill': 0xa040c0, 'top-solid-infill': 0xff3060, 'bottom-solid-infill': 0x8060ff, bridge: 0x5080ff,
  'gap-fill': 0xffffff, ironing: 0xff90ff, support: 0x40c040, 'support-interface': 0x80ff80, skirt: 0x00c0c0,
  brim: 0x00a0a0, 'wipe-tower': 0x808000, custom: 0x707070,
};
const TRAVEL_COLOR = new THREE.Color(0x3a8cff);
/** A move with a collision finding (`warpslice check`), drawn over every colour mode. */
const COLLISION_COLOR = new THREE.Color(0xff0000);

/** The name of feature number `f` (the core's list). */
export function featureName(f) {
  return state.schema?.features[f] ?? `feature ${f}`;
}

/** The colour of feature number `f`. */
function featureColor(f, c = new THREE.Color()) {
  const name = featureName(f);
  if (FEATURE_COLORS[name] !== undefined) return c.setHex(FEATURE_COLORS[name]);
  let h = 0;
  for (const ch of name) h = (h * 31 + ch.charCodeAt(0)) >>> 0;
  return c.setHSL((h % 360) / 360, 0.7, 0.6);
}


/** Build the segment geometry (segment i = points i-1 → i of the same or the next layer). */
export function buildToolpath() {
  const d = tp.data;
  if (!d) return;
  const t0 = performance.now();
  const showTravel = $('show-travel').checked;
  const mode = $('color-mode').value;
  const n = d.count;
  let layerMin = Infinity, layerMax = -Infinity;
  for (let i = 0; i < n; i++) {
    const l = d.layer[i];
    if (l < layerMin) layerMin = l;
    if (l > layerMax) layerMax = l;
  }
  const machine = machineFrameOn();
  const src = machine ? d.mpos : d.pos;
  $('canvas-wrap').dataset.frame = machine ? 'machine' : 'part';
  if (!machine) delete $('canvas-wrap').dataset.bed;
  const pos = new Float32Array(Math.max(0, n - 1) * 6), col = new Float32Array(Math.max(0, n - 1) * 6);
  const segPoint = new Uint32Array(Math.max(0, n - 1));
  const c = new THREE.Color();
  let s = 0;
  let maxTilt = 0;
  for (let i = 0; i < n; i++) if (d.tilt[i] > maxTilt) maxTilt = d.tilt[i];
  const palette = new Float32Array(128 * 3);
  for (let k = 0; k < 128; k++) featureColor(k, c).toArray(palette, k * 3);
  const travelRgb = TRAVEL_COLOR.toArray([]);
  const hitRgb = COLLISION_COLOR.toArray([]);
  let hits = 0;
  const rgb = [0, 0, 0];
  for (let i = 1; i < n; i++) {
    const travel = (d.flags[i] & 0x80) !== 0;
    // a move with a collision is drawn (red) even when travels are hidden
    if (travel && !showTravel && !d.hit?.[i]) continue;
    if (d.hit?.[i]) {
      rgb[0] = hitRgb[0]; rgb[1] = hitRgb[1]; rgb[2] = hitRgb[2];
      hits++;
    } else if (travel) {
      rgb[0] = travelRgb[0]; rgb[1] = travelRgb[1]; rgb[2] = travelRgb[2];
    } else if (mode === 'feature') {
      const k = (d.flags[i] & 0x7f) * 3;
      rgb[0] = palette[k]; rgb[1] = palette[k + 1]; rgb[2] = palette[k + 2];
    } else {
      if (mode === 'tilt') tiltColor(d.tilt[i], Math.max(1, maxTilt), c);
      else c.setHSL(((d.layer[i] - layerMin) / Math.max(1, layerMax - layerMin)) * 0.8, 0.8, 0.55);
      rgb[0] = c.r; rgb[1] = c.g; rgb[2] = c.b;
    }
    const o = s * 6, a = (i - 1) * 3, b = i * 3;
    pos[o] = src[a]; pos[o + 1] = src[a + 1]; pos[o + 2] = src[a + 2];
    pos[o + 3] = src[b]; pos[o + 4] = src[b + 1]; pos[o + 5] = src[b + 2];
    col[o] = col[o + 3] = rgb[0]; col[o + 1] = col[o + 4] = rgb[1]; col[o + 2] = col[o + 5] = rgb[2];
    segPoint[s] = i;
    s++;
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(pos.subarray(0, s * 6), 3));
  g.setAttribute('color', new THREE.BufferAttribute(col.subarray(0, s * 6), 3));
  // Segments per layer (the slicer's layer index, in file order).
  const layerFirst = new Map();
  const layerCount = new Map();
  for (let k = 0; k < s; k++) {
    const l = d.layer[segPoint[k]];
    if (!layerFirst.has(l)) layerFirst.set(l, k);
    layerCount.set(l, (layerCount.get(l) ?? 0) + 1);
  }
  const layers = [...layerFirst.keys()].sort((a, b) => a - b);
  clearGroup(view.pathGroup);
  const lines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: true }));
  view.pathGroup.add(lines);
  const axisGeom = new THREE.BufferGeometry();
  axisGeom.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6), 3));
  const axis = new THREE.LineSegments(axisGeom, new THREE.LineBasicMaterial({ color: 0xffff00 }));
  const tip = new THREE.Mesh(new THREE.SphereGeometry(0.8, 12, 8), new THREE.MeshBasicMaterial({ color: 0xffff00 }));
  view.pathGroup.add(axis, tip);
  const bed = machine ? bedOutline(d) : null;
  if (bed) view.pathGroup.add(bed.lines);
  tp.built = { g, lines, axis, tip, segPoint, layerFirst, layerCount, segments: s, maxTilt, machine, bed };
  tp.layers = layers;
  const slider = $('layer-slider');
  const keep = tp.layers.length ? Math.min(Number(slider.value), tp.layers.length - 1) : 0;
  slider.max = Math.max(0, layers.length - 1);
  slider.value = tp.firstBuild ? slider.max : keep;
  tp.firstBuild = false;
  if (mode === 'feature') legendFeatures(d);
  else if (mode === 'tilt') legendTilt(maxTilt, 'tool tilt');
  else $('legend').replaceChildren();
  onLayerChange(true);
  $('canvas-wrap').dataset.buildMs = String(Math.round(performance.now() - t0));
  $('canvas-wrap').dataset.collisionSegments = String(hits);
}

/** Move the preview to point `i` (its layer, the move in the layer): a finding's click. */
export function gotoPoint(i) {
  const b = tp.built;
  if (!b) return;
  const d = tp.data;
  if ((d.flags[i] & 0x80) && !$('show-travel').checked) {
    $('show-travel').checked = true;
    buildToolpath();
  }
  const bb = tp.built;
  const li = tp.layers.indexOf(d.layer[i]);
  if (li < 0) return;
  $('layer-slider').value = String(li);
  const first = bb.layerFirst.get(d.layer[i]);
  let k = first;
  while (k + 1 < bb.segments && bb.segPoint[k] < i && d.layer[bb.segPoint[k + 1]] === d.layer[i]) k++;
  $('move-slider').max = String(Math.max(0, bb.layerCount.get(d.layer[i]) - 1));
  $('move-slider').value = String(k - first);
  onLayerChange(false);
}

export function legendFeatures(d) {
  const seen = new Set();
  for (let i = 0; i < d.count; i++) seen.add(d.flags[i] & 0x7f);
  const L = $('legend');
  L.replaceChildren();
  for (const f of [...seen].sort((a, b) => a - b)) {
    const row = document.createElement('div');
    const sw = document.createElement('span');
    sw.className = 'sw';
    sw.style.background = `#${featureColor(f).getHexString()}`;
    row.append(sw, featureName(f).replace(/-/g, ' '));
    L.append(row);
  }
  if ($('show-travel').checked) {
    const row = document.createElement('div');
    const sw = document.createElement('span');
    sw.className = 'sw';
    sw.style.background = `#${TRAVEL_COLOR.getHexString()}`;
    row.append(sw, 'travel');
    L.append(row);
  }
}

// Machine coordinates (moving-bed machines): the worker sends, per preview point, the head's
// position in the machine frame (`mpos`) and the bed's rotation (`mrot`, 3 columns) from the
// machine's inverse kinematics; the bed's pose at move i maps a part point q to
// mpos_i + R_i (q − p_i).
function machineFrameOn() {
  const d = tp.data;
  return $('machine-frame').checked && !!d && !!d.mpos;
}

/** Enabled when the selected machine moves its bed and the result carries machine coordinates. */
export function updateMachineFrameToggle() {
  const box = $('machine-frame');
  const m = currentMachine();
  const ok = !!m?.moving_bed && !!state.result && !!tp.data?.mpos && tp.data.machine === m.name;
  box.disabled = !ok;
  if (!ok) box.checked = false;
}

function bedRotation(d, i) {
  const r = d.mrot, o = i * 9;
  // mrot holds the columns R e_x, R e_y, R e_z; Matrix3.set takes rows.
  return new THREE.Matrix3().set(r[o], r[o + 3], r[o + 6], r[o + 1], r[o + 4], r[o + 7], r[o + 2], r[o + 5], r[o + 8]);
}

/** The part's bounding box (12 edges) and a bed plate 10 mm wider at its bottom, part frame. */
function bedOutline(d) {
  const box = new THREE.Box3().setFromArray(d.pos);
  if (box.isEmpty()) return null;
  const lo = box.min, hi = box.max, m = 10;
  const c = (x, y, z) => [x, y, z];
  const corners = [];
  for (const z of [lo.z, hi.z]) corners.push(c(lo.x, lo.y, z), c(hi.x, lo.y, z), c(hi.x, hi.y, z), c(lo.x, hi.y, z));
  const edges = [];
  for (let k = 0; k < 4; k++) edges.push(corners[k], corners[(k + 1) % 4], corners[4 + k], corners[4 + ((k + 1) % 4)], corners[k], corners[4 + k]);
  const plate = [c(lo.x - m, lo.y - m, lo.z), c(hi.x + m, lo.y - m, lo.z), c(hi.x + m, hi.y + m, lo.z), c(lo.x - m, hi.y + m, lo.z)];
  for (let k = 0; k < 4; k++) edges.push(plate[k], plate[(k + 1) % 4]);
  const part = new Float32Array(edges.flat());
  const geom = new THREE.BufferGeometry();
  geom.setAttribute('position', new THREE.BufferAttribute(new Float32Array(part.length), 3));
  const lines = new THREE.LineSegments(geom, new THREE.LineBasicMaterial({ color: 0x9be39b }));
  return { part, lines };
}

function placeBed(bed, d, i, R) {
  const a = bed.lines.geometry.attributes.position;
  const p = new THREE.Vector3().fromArray(d.pos, i * 3);
  const m = new THREE.Vector3().fromArray(d.mpos, i * 3);
  const q = new THREE.Vector3();
  for (let k = 0; k < a.count; k++) {
    q.fromArray(bed.part, k * 3).sub(p).applyMatrix3(R).add(m);
    a.setXYZ(k, q.x, q.y, q.z);
  }
  a.needsUpdate = true;
  bed.lines.geometry.computeBoundingSphere();
  // The bed plate's first corner (machine frame, mm): a hook for tests and a11y readers.
  const k = a.count - 8;
  $('canvas-wrap').dataset.bed = [a.getX(k), a.getY(k), a.getZ(k)].map((v) => v.toFixed(2)).join(' ');
}

export function onLayerChange(resetMove) {
  const b = tp.built;
  if (!b || !tp.layers.length) return;
  const li = Number($('layer-slider').value);
  const layer = tp.layers[li];
  const first = b.layerFirst.get(layer);
  const count = b.layerCount.get(layer);
  const ms = $('move-slider');
  ms.max = Math.max(0, count - 1);
  if (resetMove) ms.value = ms.max;
  const move = Math.min(Number(ms.value), count - 1);
  const drawn = first + move + 1;
  b.g.setDrawRange(0, drawn * 2);
  const pi = b.segPoint[first + move];
  const d = tp.data;
  const p = new THREE.Vector3().fromArray(b.machine ? d.mpos : d.pos, pi * 3);
  const n = new THREE.Vector3().fromArray(d.axis, pi * 3);
  let map = null;
  if (b.machine) {
    // The tool axis, the bed and the head in the machine frame: n ↦ R_i n,
    // q ↦ mpos_i + R_i (q − p_i).
    const R = bedRotation(d, pi);
    n.applyMatrix3(R).normalize();
    if (b.bed) placeBed(b.bed, d, pi, R);
    map = { p: new THREE.Vector3().fromArray(d.pos, pi * 3), m: p.clone(), R };
  }
  showHead(d, pi, map);
  const len = 12;
  const a = b.axis.geometry.attributes.position;
  a.setXYZ(0, p.x, p.y, p.z);
  a.setXYZ(1, p.x + n.x * len, p.y + n.y * len, p.z + n.z * len);
  a.needsUpdate = true;
  b.tip.position.copy(p);
  $('layer-out').textContent = `${layer} (${li + 1} of ${tp.layers.length})`;
  const tilt = d.tilt[pi];
  $('move-out').textContent = `${move + 1} of ${count} — ${b.machine ? 'machine ' : ''}x ${p.x.toFixed(2)} y ${p.y.toFixed(2)} z ${p.z.toFixed(2)}, tilt ${tilt.toFixed(1)}°`;
  const vp = $('canvas-wrap');
  vp.dataset.layer = String(layer);
  vp.dataset.move = String(move);
  vp.dataset.drawn = String(drawn);
  // the file line of the move shown (a checked G-code's preview; 0 for an unwarp's own)
  vp.dataset.line = String(d.line?.[pi] ?? '');
  view.dirty = true;
}

export function setViewMode(mode) {
  $('view-mode').value = mode;
  const tpMode = mode === 'toolpath';
  view.modelGroup.visible = !tpMode;
  view.pathGroup.visible = tpMode;
  $('tp-controls').hidden = !tpMode;
  $('sliders').hidden = !tpMode || !tp.data;
  if (tpMode && tp.data) {
    if (!tp.built) buildToolpath();
    const box = new THREE.Box3().setFromBufferAttribute(tp.built.g.attributes.position);
    frame(box);
    if ($('color-mode').value === 'feature') legendFeatures(tp.data);
  } else if (!tpMode) {
    showModel();
  }
  view.dirty = true;
}
