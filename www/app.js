// warpslice web app: the page. Heavy work runs in worker.js; this file owns the form, the
// settings (JSON / URL hash), the downloads and the three.js view.
import * as THREE from './vendor/three.module.js';
import { OrbitControls } from './vendor/OrbitControls.js';
import { STLLoader } from './vendor/STLLoader.js';

const $ = (id) => document.getElementById(id);

// ---------------------------------------------------------------------------------------------
// Worker RPC. Cancel = terminate the worker and start a fresh one (the wasm state goes with it).
// ---------------------------------------------------------------------------------------------
let worker = null;
let nextId = 1;
const pending = new Map();

function startWorker() {
  worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
  worker.onmessage = (ev) => {
    const m = ev.data;
    const p = pending.get(m.id);
    if (!p) return;
    if (m.type === 'progress' || m.type === 'registration') {
      p.onEvent?.(m);
    } else if (m.type === 'error') {
      pending.delete(m.id);
      p.reject(new Error(m.message));
    } else {
      pending.delete(m.id);
      p.resolve(m);
    }
  };
  worker.onerror = (ev) => {
    for (const [, p] of pending) p.reject(new Error(`the worker stopped: ${ev.message || 'unknown error'}`));
    pending.clear();
  };
}

function call(op, args = {}, transfer = [], onEvent = null) {
  if (!worker) startWorker();
  const id = nextId++;
  return new Promise((resolve, reject) => {
    pending.set(id, { resolve, reject, onEvent });
    worker.postMessage({ id, op, ...args }, transfer);
  });
}

function cancelWorker() {
  worker?.terminate();
  worker = null;
  for (const [, p] of pending) p.reject(Object.assign(new Error('cancelled'), { cancelled: true }));
  pending.clear();
}

// ---------------------------------------------------------------------------------------------
// Warps: parameters, one line each, with limits.
// ---------------------------------------------------------------------------------------------
const DIRECTION = { type: 'select', options: ['outward', 'inward'], help: 'outward: layers fall away from the centre (the nozzle tilts outward); inward: the opposite.' };
const WARPS = {
  conic: {
    label: 'conic',
    params: {
      angle: { label: 'Cone angle (°)', min: 1, max: 89, step: 0.5, value: 30, help: 'Slope of the cone-shaped layers = the nozzle tilt (Slicer4RTN).' },
      direction: { ...DIRECTION, label: 'Direction', value: 'outward' },
      cx: { label: 'Centre x (mm)', min: -500, max: 500, step: 0.5, value: 0, help: 'Cone axis, relative to the model centre.' },
      cy: { label: 'Centre y (mm)', min: -500, max: 500, step: 0.5, value: 0, help: 'Cone axis, relative to the model centre.' },
    },
    spec: (p) => ({ kind: 'conic', angle: p.angle, direction: p.direction, center: [p.cx, p.cy] }),
  },
  curved: {
    label: 'curved',
    params: {
      strength: { label: 'Strength', min: 0, max: 3, step: 0.05, value: 0.3, help: 'Rise of the layers at the model edge per half-width (slope at the edge ≈ 2 × strength).' },
      direction: { ...DIRECTION, label: 'Direction', value: 'outward' },
      offset: { label: 'Offset (mm)', min: -500, max: 500, step: 0.5, value: 0, help: 'Moves the lowest line of the curve along x.' },
      width: { label: 'Width (mm)', min: 0, max: 1000, step: 1, value: 0, help: 'Width the curve spans; 0 = the model’s width in x.' },
    },
    spec: (p) => ({ kind: 'curved', strength: p.strength, direction: p.direction, offset: p.offset, width: p.width }),
  },
  tilted: {
    label: 'tilted',
    params: {
      strength: { label: 'Slope', min: 0, max: 5, step: 0.05, value: 0.2, help: 'Rise per mm away from x = −offset (tilt = atan slope).' },
      direction: { ...DIRECTION, label: 'Direction', value: 'outward' },
      offset: { label: 'Offset (mm)', min: -500, max: 500, step: 0.5, value: 0, help: 'Where the roof ridge lies along x.' },
    },
    spec: (p) => ({ kind: 'tilted', strength: p.strength, direction: p.direction, offset: p.offset }),
  },
  belt: {
    label: 'belt',
    params: {
      angle: { label: 'Angle (°)', min: 1, max: 89, step: 0.5, value: 15, help: 'Tilt of the plane layers from horizontal = the nozzle tilt.' },
      tx: { label: 'Toward x', min: -1, max: 1, step: 0.1, value: 0, help: 'Direction the layers fall toward (x part; normalised).' },
      ty: { label: 'Toward y', min: -1, max: 1, step: 0.1, value: 1, help: 'Direction the layers fall toward (y part; normalised).' },
    },
    spec: (p) => ({ kind: 'belt', angle: p.angle, toward: [p.tx, p.ty] }),
  },
};

// ---------------------------------------------------------------------------------------------
// Machines: what each kind can tilt, read from the preset JSON (machine_presets()).
// ---------------------------------------------------------------------------------------------
let PRESETS = [];

/** {maxTilt (deg or null), warps: allowed warp kinds, notes: [..], fixedTilt?} for a preset. */
function machineCaps(preset) {
  const s = preset?.spec ?? { kind: 'cartesian' };
  const all = Object.keys(WARPS);
  switch (s.kind) {
    case 'cartesian':
      return { maxTilt: s.max_tilt_deg ?? null, warps: all, notes: ['3 axes: the nozzle stays vertical; steep layers need a nozzle whose cone clears them.'] };
    case 'b-head':
      return {
        maxTilt: s.b_limit_deg, warps: ['curved', 'tilted', 'belt'], beltX: true,
        notes: [`head tilts about Y only (B ±${s.b_limit_deg}°), pivot ${s.pivot_to_tip_mm} mm above the tip`].concat(s.clip ? [`below z = ${s.clip_z_mm} mm the tilt is clipped to ${s.clip_b0_deg}° (bed clearance)`] : []),
      };
    case 'rtn':
      return { maxTilt: s.tilt_deg, fixedTilt: s.tilt_deg, warps: ['conic'], notes: [`nozzle fixed at ${s.tilt_deg}° and rotating about Z (${s.revolution} revolution): conic layers at that angle`] };
    case 'pax':
      return { maxTilt: s.max_tilt_deg, warps: all, notes: [`5-axis head, tilt up to ${s.max_tilt_deg}°`] };
    case 'ab-table':
      return { maxTilt: s.a_limit_deg, warps: all, notes: [`A/B rotary table, A within ±${s.a_limit_deg}°`] };
    case 'three-z':
      return { maxTilt: s.max_tilt_deg, warps: all, volume: s.build_volume_mm, notes: [`tilting bed on three Z motors, tilt up to ${s.max_tilt_deg}°, build volume ${s.build_volume_mm.join(' × ')} mm`] };
    case 'r-theta':
      return { maxTilt: s.max_tilt_deg, warps: all, radius: s.max_radius_mm, notes: [`polar printer, tilt up to ${s.max_tilt_deg}°, reach r ≤ ${s.max_radius_mm} mm`] };
    case 'lathe-a':
      return { maxTilt: null, warps: all, notes: ['rotating mandrel about X (A axis)'] };
    default:
      return { maxTilt: null, warps: all, notes: [] };
  }
}

function currentPreset() {
  return PRESETS.find((p) => p.name === $('machine-select').value) ?? PRESETS[0];
}

function axesText(p) {
  return p.axes.map((a) => (a.rotary ? `${a.name} ${a.min ?? '−∞'}…${a.max ?? '∞'}°` : a.name)).join(', ');
}

// ---------------------------------------------------------------------------------------------
// Settings: form ⇄ JSON ⇄ URL hash.
// ---------------------------------------------------------------------------------------------
const state = { stl: null, stlName: '', modelReport: null, warped: null, result: null, busy: false };

function paramInputs() {
  return [...$('warp-params').querySelectorAll('[data-param]')];
}

function readSettings() {
  const kind = $('warp-select').value;
  const params = {};
  for (const el of paramInputs()) params[el.dataset.param] = el.type === 'number' ? Number(el.value) : el.value;
  const base = $('p-base-on')?.checked ? [Number($('p-base-z0').value), Number($('p-base-z1').value)] : null;
  return {
    machine: $('machine-select').value,
    warp: { kind, ...params },
    base,
    layer_height: Number($('p-layer_height').value),
    max_edge: Number($('p-max_edge').value),
    anchor: $('p-anchor').value,
    unwarp: {
      z_offset: Number($('p-z_offset').value),
      drop_skirt: $('p-drop_skirt').checked,
      place: $('p-place-on').checked ? [Number($('p-place-x').value), Number($('p-place-y').value)] : null,
    },
  };
}

function applySettings(s) {
  if (!s || typeof s !== 'object') return;
  if (s.machine && PRESETS.some((p) => p.name === s.machine)) $('machine-select').value = s.machine;
  onMachineChange(false);
  if (s.warp?.kind && WARPS[s.warp.kind] && ![...$('warp-select').options].find((o) => o.value === s.warp.kind)?.disabled) {
    $('warp-select').value = s.warp.kind;
  }
  buildWarpParams(s.warp);
  if (s.base) {
    $('p-base-on').checked = true;
    $('p-base-z0').value = s.base[0];
    $('p-base-z1').value = s.base[1];
  }
  for (const k of ['layer_height', 'max_edge']) if (Number.isFinite(s[k])) $(`p-${k}`).value = s[k];
  if (['auto', 'on', 'off'].includes(s.anchor)) $('p-anchor').value = s.anchor;
  if (s.unwarp) {
    if (Number.isFinite(s.unwarp.z_offset)) $('p-z_offset').value = s.unwarp.z_offset;
    $('p-drop_skirt').checked = !!s.unwarp.drop_skirt;
    const pl = s.unwarp.place;
    const placed = Array.isArray(pl) && pl.length === 2 && pl.every(Number.isFinite);
    $('p-place-on').checked = placed;
    if (placed) [$('p-place-x').value, $('p-place-y').value] = pl;
  }
  enforceLimits();
}

/** The core's WarpOptions for the current form. */
function warpOptions() {
  const s = readSettings();
  const w = WARPS[s.warp.kind];
  return {
    warp: { spec: w.spec(s.warp), base: s.base },
    max_edge: s.max_edge,
    tolerance: 0.01,
    layer_height: s.layer_height,
    anchor: s.anchor,
  };
}

function unwarpOptions() {
  const s = readSettings();
  const o = {};
  if (s.unwarp.z_offset) o.z_offset = s.unwarp.z_offset;
  if (s.unwarp.drop_skirt) o.drop_skirt = true;
  if (s.unwarp.place && s.unwarp.place.every(Number.isFinite)) o.place = s.unwarp.place;
  // The machine's own G-code (its axes, tessellated, its flavour); plain 3-axis for cartesian,
  // exactly as the CLI's `unwarp --machine NAME`.
  const p = currentPreset();
  if (p && p.name !== 'cartesian') o.machine = p.name;
  return o;
}

function saveHash() {
  const text = JSON.stringify(readSettings());
  history.replaceState(null, '', `#s=${encodeURIComponent(text)}`);
}

function settingsFromHash() {
  const m = /^#s=(.*)$/.exec(location.hash);
  if (!m) return null;
  try {
    return JSON.parse(decodeURIComponent(m[1]));
  } catch {
    return null;
  }
}

// ---------------------------------------------------------------------------------------------
// Form building and limits.
// ---------------------------------------------------------------------------------------------
function buildWarpParams(values = {}) {
  const kind = $('warp-select').value;
  const box = $('warp-params');
  box.replaceChildren();
  for (const [name, def] of Object.entries(WARPS[kind].params)) {
    const row = document.createElement('div');
    row.className = 'param';
    const id = `p-${kind}-${name}`;
    const label = document.createElement('label');
    label.htmlFor = id;
    label.textContent = def.label;
    let input;
    if (def.type === 'select') {
      input = document.createElement('select');
      for (const o of def.options) input.add(new Option(o, o));
      input.value = values[name] ?? def.value;
    } else {
      input = document.createElement('input');
      input.type = 'number';
      Object.assign(input, { min: def.min, max: def.max, step: def.step });
      input.value = values[name] ?? def.value;
    }
    input.id = id;
    input.dataset.param = name;
    input.dataset.testid = `param-${name}`;
    input.setAttribute('data-testid', `param-${name}`);
    const help = document.createElement('small');
    help.id = `${id}-help`;
    help.textContent = def.help;
    input.setAttribute('aria-describedby', help.id);
    row.append(label, input, help);
    box.append(row);
  }
  // The flat base blend, common to every warp.
  const row = document.createElement('div');
  row.className = 'param';
  row.innerHTML = `<label class="check" for="p-base-on"><input type="checkbox" id="p-base-on"> flat base</label>
    <span><label for="p-base-z0" class="visually-hidden">base z0 (mm)</label><input type="number" id="p-base-z0" min="0" max="500" step="0.5" value="0" aria-label="base from z (mm)">
    – <label for="p-base-z1" class="visually-hidden">base z1 (mm)</label><input type="number" id="p-base-z1" min="0.5" max="500" step="0.5" value="5" aria-label="base to z (mm)"> mm</span>
    <small>Keep the layers flat from z0 and blend into the warp by z1 (a flat first layer on the bed).</small>`;
  box.append(row);
  enforceLimits();
}

/** Clamp numeric inputs to their limits (machine ones included) and note what was changed. */
function enforceLimits() {
  const caps = machineCaps(currentPreset());
  const kind = $('warp-select').value;
  for (const el of paramInputs()) {
    if (el.type !== 'number') continue;
    const def = WARPS[kind].params[el.dataset.param];
    let max = def.max;
    if ((kind === 'conic' || kind === 'belt') && el.dataset.param === 'angle' && caps.maxTilt != null) max = Math.min(max, caps.maxTilt);
    if (kind === 'tilted' && el.dataset.param === 'strength' && caps.maxTilt != null && caps.maxTilt < 89) {
      max = Math.min(max, Math.round(Math.tan((caps.maxTilt * Math.PI) / 180) * 100) / 100);
    }
    el.max = max;
    const v = Number(el.value);
    if (!Number.isFinite(v) || el.value === '') el.value = def.value;
    else if (v < def.min) el.value = def.min;
    else if (v > max) el.value = max;
  }
  if (caps.beltX && kind === 'belt') {
    $(`p-belt-ty`).value = 0;
    $(`p-belt-ty`).disabled = true;
    if (Number($(`p-belt-tx`).value) === 0) $(`p-belt-tx`).value = 1;
  }
  if (caps.fixedTilt != null && kind === 'conic') $('p-conic-angle').value = caps.fixedTilt;
  $('p-conic-angle')?.toggleAttribute('readonly', caps.fixedTilt != null && kind === 'conic');
  for (const [id, lo, hi] of [['p-layer_height', 0.05, 1], ['p-max_edge', 0.1, 20], ['p-z_offset', -2, 2]]) {
    const v = Number($(id).value);
    if (!Number.isFinite(v) || v < lo) $(id).value = lo;
    else if (v > hi) $(id).value = hi;
  }
  for (const el of document.querySelectorAll('.lh')) el.textContent = $('p-layer_height').value;
}

function onMachineChange(rebuild = true) {
  const p = currentPreset();
  const caps = machineCaps(p);
  const kind = p.spec.kind === p.name ? '' : ` (${p.spec.kind})`;
  const notes = caps.notes.map((n) => n.replace(/\.$/, '')).join('; ');
  $('machine-info').textContent = `${p.name}${kind} — axes ${axesText(p)}${notes ? `; ${notes}` : ''}. ` +
    'Machine G-code output is coming: the result is the 3-axis G-code for now.';
  const sel = $('warp-select');
  for (const o of sel.options) {
    o.disabled = !caps.warps.includes(o.value);
  }
  if (sel.selectedOptions[0]?.disabled) {
    sel.value = caps.warps[0];
    if (rebuild) buildWarpParams();
  } else if (rebuild) {
    enforceLimits();
  }
  showWarnings();
  updateMachineFrameToggle();
}

// ---------------------------------------------------------------------------------------------
// Errors in plain words.
// ---------------------------------------------------------------------------------------------
function explain(message, context) {
  const m = message.toLowerCase();
  let todo = '';
  if (context === 'stl') todo = 'Check that the file is an STL exported from a CAD program (ASCII or binary) and not empty; re-export it if it was cut short.';
  else if (context === 'warp') todo = 'Lower the warp strength or angle, or change the flat base; then press Warp again.';
  else if (m.includes('binary g-code')) todo = '';
  else if (m.includes('arc') || m.includes('g2') || m.includes('g3')) todo = 'Turn off arc fitting in the slicer (PrusaSlicer: Printer settings → Arc fitting: disabled) and export again.';
  else if (m.includes('hash')) todo = 'Use the job file of this exact warped STL; warp again if in doubt.';
  else if (context === 'gcode' && m.includes('does not match')) todo = 'In the browser the placement is always detected: slice the warped STL downloaded in step 3, not the original model, with first layer height = layer height.';
  else if (context === 'gcode') todo = 'Check that this G-code was sliced from the warped STL downloaded in step 3 with these settings (same layer height, first layer height = layer height), and that it is plain text.';
  return todo;
}

function showError(title, message, context) {
  const box = $('error');
  box.replaceChildren();
  const t = document.createElement('strong');
  t.textContent = title;
  const p = document.createElement('div');
  p.textContent = message;
  box.append(t, p);
  const todo = explain(message, context);
  if (todo) {
    const d = document.createElement('div');
    d.textContent = `What to do: ${todo}`;
    box.append(d);
  }
  box.hidden = false;
  box.scrollIntoView?.({ block: 'nearest' });
}

function clearError() {
  $('error').hidden = true;
  $('error').replaceChildren();
}

// ---------------------------------------------------------------------------------------------
// Downloads.
// ---------------------------------------------------------------------------------------------
function setDownload(id, blob, name) {
  const a = $(id);
  if (a.href?.startsWith('blob:')) URL.revokeObjectURL(a.href);
  if (!blob) {
    a.removeAttribute('href');
    a.classList.add('disabled');
    a.setAttribute('aria-disabled', 'true');
    return;
  }
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.classList.remove('disabled');
  a.removeAttribute('aria-disabled');
}

function baseName(name) {
  return (name || 'model').replace(/\.[^.]*$/, '').replace(/[^\w.-]+/g, '_') || 'model';
}

// ---------------------------------------------------------------------------------------------
// 3D view.
// ---------------------------------------------------------------------------------------------
const view = {};

function initView() {
  const wrap = $('canvas-wrap');
  const renderer = new THREE.WebGLRenderer({ antialias: false, powerPreference: 'high-performance' });
  renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
  wrap.append(renderer.domElement);
  renderer.domElement.setAttribute('aria-label', '3D view: drag to orbit, scroll to zoom');
  renderer.domElement.tabIndex = 0;
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x20242a);
  const camera = new THREE.PerspectiveCamera(40, 1, 0.1, 10000);
  camera.up.set(0, 0, 1);
  camera.position.set(120, -160, 120);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.listenToKeyEvents?.(renderer.domElement);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.4);
  sun.position.set(1, -1, 2);
  scene.add(sun);
  const grid = new THREE.GridHelper(200, 20, 0x556070, 0x394250);
  grid.rotation.x = Math.PI / 2;
  scene.add(grid);
  view.grid = grid;
  const modelGroup = new THREE.Group();
  const pathGroup = new THREE.Group();
  scene.add(modelGroup, pathGroup);
  Object.assign(view, { renderer, scene, camera, controls, modelGroup, pathGroup, wrap, dirty: true });
  controls.addEventListener('change', () => (view.dirty = true));
  new ResizeObserver(() => resize()).observe(wrap);
  resize();
  const loop = () => {
    if (view.dirty) {
      view.dirty = false;
      const t = performance.now();
      renderer.render(scene, camera);
      wrap.dataset.renderMs = String(Math.max(Number(wrap.dataset.renderMs || 0), Math.round(performance.now() - t)));
    }
    requestAnimationFrame(loop);
  };
  loop();
}

function resize() {
  const { renderer, camera, wrap } = view;
  const w = wrap.clientWidth || 600, h = wrap.clientHeight || 400;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  view.dirty = true;
}

function clearGroup(g) {
  if (g.children.length) view.dirty = true;
  for (const c of [...g.children]) {
    g.remove(c);
    c.geometry?.dispose();
    c.material?.dispose();
  }
}

function frame(box) {
  if (box.isEmpty()) return;
  const c = box.getCenter(new THREE.Vector3());
  const r = box.getSize(new THREE.Vector3()).length() / 2 || 10;
  view.controls.target.copy(c);
  view.grid.position.set(Math.round(c.x / 10) * 10, Math.round(c.y / 10) * 10, 0);
  view.camera.position.copy(c).add(new THREE.Vector3(1.2 * r, -1.8 * r, 1.3 * r));
  view.camera.near = r / 100;
  view.camera.far = r * 100;
  view.camera.updateProjectionMatrix();
  view.controls.update();
  view.dirty = true;
}

/** Tilt colour: blue (0°) → green → red (at `max`°). */
function tiltColor(deg, max, c = new THREE.Color()) {
  const t = Math.max(0, Math.min(1, deg / (max || 1)));
  return c.setHSL((1 - t) * 0.66, 0.85, 0.5);
}

function stlGeometry(bytes) {
  const buf = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const g = new STLLoader().parse(buf);
  g.computeVertexNormals();
  return g;
}

function showModel() {
  clearGroup(view.modelGroup);
  if (!state.stl || !state.modelReport) return;
  const r = state.modelReport;
  let geom;
  try {
    geom = stlGeometry(state.stl);
  } catch {
    return;
  }
  const t = [-(r.bbox.min.x + r.bbox.max.x) / 2, -(r.bbox.min.y + r.bbox.max.y) / 2, -r.bbox.min.z];
  geom.translate(...t);
  const showLayers = state.warped && $('show-layers').checked;
  const mat = new THREE.MeshStandardMaterial({ color: 0xb8c4d0, roughness: 0.7, transparent: !!showLayers, opacity: showLayers ? 0.35 : 1, side: THREE.DoubleSide });
  view.modelGroup.add(new THREE.Mesh(geom, mat));
  const box = new THREE.Box3().setFromBufferAttribute(geom.attributes.position);
  if (state.warped) {
    const w = state.warped;
    const maxTilt = Math.max(1, w.report.largest_tilt_deg);
    if (showLayers && w.surfaces.length) {
      const n = w.surfaces.length / 5;
      const inside = footprint(geom, JSON.parse(w.job).model_bbox, SURFACE_GRID);
      const pos = new Float32Array(n * 3), col = new Float32Array(n * 3);
      const c = new THREE.Color();
      // Samples beyond the machine's tilt limit are drawn magenta.
      const limit = machineCaps(currentPreset()).maxTilt;
      const over = new THREE.Color(0xff00ff);
      let nOver = 0;
      let k = 0;
      for (let i = 0; i < n; i++) {
        if (!inside(w.surfaces[i * 5], w.surfaces[i * 5 + 1])) continue;
        pos.set(w.surfaces.subarray(i * 5, i * 5 + 3), k * 3);
        const t = w.surfaces[i * 5 + 3];
        if (limit != null && t > limit + 1e-6) {
          over.toArray(col, k * 3);
          nOver++;
        } else {
          tiltColor(t, maxTilt, c).toArray(col, k * 3);
        }
        k++;
      }
      $('canvas-wrap').dataset.overLimit = String(nOver);
      $('canvas-wrap').dataset.surfacePoints = String(k);
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(pos.subarray(0, k * 3), 3));
      g.setAttribute('color', new THREE.BufferAttribute(col.subarray(0, k * 3), 3));
      view.modelGroup.add(new THREE.Points(g, new THREE.PointsMaterial({ size: 2, sizeAttenuation: false, vertexColors: true })));
    }
    if ($('show-warped').checked) {
      const wg = stlGeometry(w.stl);
      const dx = box.max.x - box.min.x + 10;
      wg.translate(dx, 0, 0);
      const m = new THREE.Mesh(wg, new THREE.MeshStandardMaterial({ color: 0xe0a050, roughness: 0.6, side: THREE.DoubleSide }));
      view.modelGroup.add(m);
      box.union(new THREE.Box3().setFromBufferAttribute(wg.attributes.position));
    }
    legendTilt(maxTilt, 'layer tilt');
    if (Number($('canvas-wrap').dataset.overLimit) > 0) {
      const row = document.createElement('div');
      const sw = document.createElement('span');
      sw.className = 'sw';
      sw.style.background = '#ff00ff';
      row.append(sw, 'beyond the machine');
      $('legend').append(row);
    }
  } else {
    $('legend').replaceChildren();
  }
  frame(box);
}

/** Lattice of the layer-surface samples (layer_surfaces' grid). */
const SURFACE_GRID = 48;

/**
 * Whether a lattice point (x, y) of the model's XY bbox lies under the model: the cells whose
 * centre some triangle covers in XY. Returns a test function (x, y) → bool.
 */
function footprint(geom, bbox, grid) {
  const v = (a) => (Array.isArray(a) ? a : [a.x, a.y, a.z]);
  const [x0, y0] = v(bbox.min), [x1, y1] = v(bbox.max);
  const dx = (x1 - x0) / (grid - 1) || 1, dy = (y1 - y0) / (grid - 1) || 1;
  const mask = new Uint8Array(grid * grid);
  const p = geom.attributes.position.array;
  const cross = (ax, ay, bx, by, cx, cy) => (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  for (let t = 0; t + 8 < p.length; t += 9) {
    const ax = p[t], ay = p[t + 1], bx = p[t + 3], by = p[t + 4], cx = p[t + 6], cy = p[t + 7];
    const area = cross(ax, ay, bx, by, cx, cy);
    if (Math.abs(area) < 1e-12) continue;
    const i0 = Math.max(0, Math.ceil((Math.min(ax, bx, cx) - x0) / dx)), i1 = Math.min(grid - 1, Math.floor((Math.max(ax, bx, cx) - x0) / dx));
    const j0 = Math.max(0, Math.ceil((Math.min(ay, by, cy) - y0) / dy)), j1 = Math.min(grid - 1, Math.floor((Math.max(ay, by, cy) - y0) / dy));
    for (let i = i0; i <= i1; i++) {
      const x = x0 + i * dx;
      for (let j = j0; j <= j1; j++) {
        if (mask[i * grid + j]) continue;
        const y = y0 + j * dy;
        const s = Math.sign(area);
        if (s * cross(ax, ay, bx, by, x, y) >= 0 && s * cross(bx, by, cx, cy, x, y) >= 0 && s * cross(cx, cy, ax, ay, x, y) >= 0) mask[i * grid + j] = 1;
      }
    }
  }
  return (x, y) => {
    const i = Math.round((x - x0) / dx), j = Math.round((y - y0) / dy);
    return i >= 0 && j >= 0 && i < grid && j < grid && mask[i * grid + j] === 1;
  };
}

function legendTilt(max, title) {
  const L = $('legend');
  L.replaceChildren();
  const h = document.createElement('div');
  h.textContent = title;
  L.append(h);
  for (const f of [0, 0.5, 1]) {
    const d = document.createElement('div');
    const sw = document.createElement('span');
    sw.className = 'sw';
    sw.style.background = `#${tiltColor(f * max, max).getHexString()}`;
    d.append(sw, `${(f * max).toFixed(1)}°`);
    L.append(d);
  }
}

// ---------------------------------------------------------------------------------------------
// Toolpath preview.
// ---------------------------------------------------------------------------------------------
const FEATURES = ['object', 'outer wall', 'inner wall', 'overhang wall', 'infill', 'solid infill', 'top solid', 'bottom solid', 'bridge', 'gap fill', 'ironing', 'support', 'support interface', 'skirt', 'brim', 'wipe tower', 'custom'];
const FEATURE_COLORS = [0xc8c8c8, 0xff7f0e, 0xffd166, 0x0000ff, 0xb03030, 0xa040c0, 0xff3060, 0x8060ff, 0x5080ff, 0xffffff, 0xff90ff, 0x40c040, 0x80ff80, 0x00c0c0, 0x00a0a0, 0x808000, 0x707070];
const TRAVEL_COLOR = new THREE.Color(0x3a8cff);
const tp = { data: null, built: null, layers: [] };

/** Build the segment geometry (segment i = points i-1 → i of the same or the next layer). */
function buildToolpath() {
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
  const palette = new Float32Array(FEATURE_COLORS.length * 3);
  FEATURE_COLORS.forEach((h, k) => c.setHex(h).toArray(palette, k * 3));
  const travelRgb = TRAVEL_COLOR.toArray([]);
  const rgb = [0, 0, 0];
  for (let i = 1; i < n; i++) {
    const travel = (d.flags[i] & 0x80) !== 0;
    if (travel && !showTravel) continue;
    if (travel) {
      rgb[0] = travelRgb[0]; rgb[1] = travelRgb[1]; rgb[2] = travelRgb[2];
    } else if (mode === 'feature') {
      const k = Math.min(d.flags[i] & 0x7f, FEATURE_COLORS.length - 1) * 3;
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
}

function legendFeatures(d) {
  const seen = new Set();
  for (let i = 0; i < d.count; i++) seen.add(d.flags[i] & 0x7f);
  const L = $('legend');
  L.replaceChildren();
  for (const f of [...seen].sort((a, b) => a - b)) {
    const row = document.createElement('div');
    const sw = document.createElement('span');
    sw.className = 'sw';
    sw.style.background = `#${new THREE.Color(FEATURE_COLORS[f] ?? 0xc8c8c8).getHexString()}`;
    row.append(sw, FEATURES[f] ?? `feature ${f}`);
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
const MOVING_BED_KINDS = new Set(['ab-table', 'three-z', 'lathe-a', 'r-theta']);

function movingBed(preset) {
  return !!preset && MOVING_BED_KINDS.has(preset.spec?.kind);
}

function machineFrameOn() {
  const d = tp.data;
  return $('machine-frame').checked && !!d && !!d.mpos;
}

/** Enabled when the selected machine moves its bed and the result carries machine coordinates. */
function updateMachineFrameToggle() {
  const box = $('machine-frame');
  const ok = movingBed(currentPreset()) && !!state.result && !!tp.data?.mpos && tp.data.machine === currentPreset().name;
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

function onLayerChange(resetMove) {
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
  if (b.machine) {
    // The tool axis and the bed in the machine frame: n ↦ R_i n, q ↦ mpos_i + R_i (q − p_i).
    const R = bedRotation(d, pi);
    n.applyMatrix3(R).normalize();
    if (b.bed) placeBed(b.bed, d, pi, R);
  }
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
  view.dirty = true;
}

function setViewMode(mode) {
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

// ---------------------------------------------------------------------------------------------
// Step 1: the model.
// ---------------------------------------------------------------------------------------------
async function loadModel(bytes, name) {
  clearError();
  resetWarp();
  state.stl = null;
  state.modelReport = null;
  state.stlName = name;
  $('model-info').replaceChildren();
  $('warp-button').disabled = true;
  try {
    const { report } = await call('inspect', { stl: bytes.buffer.slice(0) });
    state.stl = bytes;
    state.modelReport = { ...report, bbox: box3(report.bbox) };
  } catch (e) {
    showError(`Cannot read “${name}”`, e.message, 'stl');
    showModel();
    return;
  }
  const r = state.modelReport;
  const size = ['x', 'y', 'z'].map((k) => (r.bbox.max[k] - r.bbox.min[k]).toFixed(2)).join(' × ');
  const defects = [];
  for (const [k, label] of [['open_edges', 'open edges'], ['nonmanifold_edges', 'non-manifold edges'], ['degenerate', 'degenerate triangles'], ['zero_normals', 'zero normals'], ['flipped_normals', 'flipped normals']]) {
    if (r[k]) defects.push(`${r[k]} ${label}`);
  }
  info($('model-info'), [
    ['file', name],
    ['format', String(r.format)],
    ['size', `${size} mm`],
    ['triangles', r.triangles.toLocaleString('en')],
    ['defects', defects.length ? defects.join(', ') : 'none'],
    ...(r.warnings?.length ? [['warnings', r.warnings.join('; ')]] : []),
  ]);
  $('model-info').dataset.triangles = String(r.triangles);
  $('warp-button').disabled = false;
  setViewMode('model');
  showModel();
  await doWarp();
}

/** The core's Aabb ({min: [x,y,z], max: [x,y,z]}) as {min: {x,y,z}, max: {x,y,z}}. */
function box3(b) {
  const v = (a) => (Array.isArray(a) ? { x: a[0], y: a[1], z: a[2] } : a);
  return b ? { min: v(b.min), max: v(b.max) } : b;
}

function info(dl, rows) {
  dl.replaceChildren();
  for (const [k, v] of rows) {
    const dt = document.createElement('dt');
    dt.textContent = k;
    const dd = document.createElement('dd');
    dd.textContent = v;
    dl.append(dt, dd);
  }
}

// ---------------------------------------------------------------------------------------------
// Step 2: warp.
// ---------------------------------------------------------------------------------------------
function resetWarp() {
  state.warped = null;
  setDownload('warped-download', null);
  setDownload('job-download', null);
  $('warp-info').replaceChildren();
  $('gcode-input').disabled = true;
  resetResult();
  showWarnings();
}

function resetResult() {
  state.result = null;
  tp.data = null;
  tp.built = null;
  clearGroup(view.pathGroup);
  setDownload('result-download', null);
  setDownload('summary-download', null);
  $('summary').replaceChildren();
  $('progress').value = 0;
  $('progress-text').textContent = '';
  $('sliders').hidden = true;
  $('canvas-wrap').removeAttribute('data-drawn');
  updateMachineFrameToggle();
}

let warpSeq = 0;
async function doWarp() {
  if (!state.stl) return;
  enforceLimits();
  saveHash();
  clearError();
  const seq = ++warpSeq;
  resetWarp();
  $('warp-button').disabled = true;
  $('warp-info').textContent = 'warping…';
  try {
    const out = await call('warp', { stl: state.stl.buffer.slice(0), options: warpOptions(), every: 5, grid: SURFACE_GRID });
    if (seq !== warpSeq) return;
    out.report.warped_bbox = box3(out.report.warped_bbox);
    state.warped = out;
    const r = out.report;
    const wb = r.warped_bbox;
    const dl = document.createElement('dl');
    dl.className = 'info';
    info(dl, [
      ['warped size', ['x', 'y', 'z'].map((k) => (wb.max[k] - wb.min[k]).toFixed(2)).join(' × ') + ' mm'],
      ['triangles out', r.triangles_out.toLocaleString('en')],
      ['largest tilt', `${r.largest_tilt_deg.toFixed(2)}°`],
      ['anchor slab', r.anchor != null ? `${r.anchor} mm (first layer, dropped by unwarp)` : 'none (flat bottom)'],
    ]);
    $('warp-info').replaceChildren(dl);
    $('warp-info').dataset.largestTilt = String(r.largest_tilt_deg);
    const name = baseName(state.stlName);
    setDownload('warped-download', new Blob([out.stl], { type: 'model/stl' }), `${name}.warped.stl`);
    setDownload('job-download', new Blob([out.job], { type: 'application/json' }), `${name}.warped.job.json`);
    $('gcode-input').disabled = false;
  } catch (e) {
    if (seq !== warpSeq) return;
    $('warp-info').textContent = '';
    if (!e.cancelled) showError('Cannot warp this model', e.message, 'warp');
  } finally {
    if (seq === warpSeq) $('warp-button').disabled = !state.stl;
  }
  showWarnings();
  showModel();
}

function showWarnings() {
  const ul = $('warnings');
  ul.replaceChildren();
  const p = currentPreset();
  if (!p) return;
  const caps = machineCaps(p);
  const add = (text, ok = false) => {
    const li = document.createElement('li');
    li.textContent = text;
    if (ok) li.className = 'ok';
    ul.append(li);
  };
  const w = state.warped;
  if (!w) return;
  const tilt = w.report.largest_tilt_deg;
  if (caps.maxTilt != null && tilt > caps.maxTilt + 1e-6) add(`The layers need up to ${tilt.toFixed(1)}° of tilt; ${p.name} reaches ${caps.maxTilt}°: lower the warp.`);
  if (caps.fixedTilt != null && Math.abs(tilt - caps.fixedTilt) > 0.5 && tilt > 0) add(`${p.name} holds the nozzle at ${caps.fixedTilt}°; these layers need ${tilt.toFixed(1)}°.`);
  if (p.spec.kind === 'b-head' && p.spec.clip && tilt > p.spec.clip_b0_deg) add(`Tilts above ${p.spec.clip_b0_deg}° are clipped within ${p.spec.clip_z_mm} mm of the bed on ${p.name}.`);
  if (p.spec.kind === 'cartesian' && tilt > 0) add(`3-axis: the nozzle stays vertical while the layers slope up to ${tilt.toFixed(1)}°; make sure the nozzle cone clears that slope.`);
  const wb = w.report.warped_bbox;
  const mb = state.modelReport.bbox;
  if (caps.volume) {
    const size = [mb.max.x - mb.min.x, mb.max.y - mb.min.y, wb.max.z - wb.min.z];
    if (size.some((v, i) => v > caps.volume[i])) add(`The part (${size.map((v) => v.toFixed(0)).join(' × ')} mm) exceeds the build volume ${caps.volume.join(' × ')} mm.`);
  }
  if (caps.radius) {
    const reach = Math.hypot((mb.max.x - mb.min.x) / 2, (mb.max.y - mb.min.y) / 2);
    if (reach > caps.radius) add(`The part reaches r = ${reach.toFixed(0)} mm from its centre; ${p.name} reaches ${caps.radius} mm.`);
  }
  if (!ul.children.length) add(`Within ${p.name}'s limits (largest tilt ${tilt.toFixed(1)}°).`, true);
}

// ---------------------------------------------------------------------------------------------
// Step 4: the G-code back.
// ---------------------------------------------------------------------------------------------
async function doUnwarp(file) {
  if (!state.warped) {
    showError('Warp a model first', 'The G-code is unwarped with the job of the warped model (steps 1–2).', '');
    return;
  }
  clearError();
  resetResult();
  saveHash();
  state.busy = true;
  $('cancel').disabled = false;
  $('gcode-input').disabled = true;
  const prog = $('progress');
  const text = $('progress-text');
  prog.removeAttribute('data-done');
  prog.removeAttribute('data-worker-bytes');
  text.textContent = 'reading…';
  const t0 = performance.now();
  try {
    const preset = currentPreset();
    const machineFrame = movingBed(preset) ? { machine: preset.name, kind: preset.spec.kind } : null;
    const out = await call('unwarp', { file, job: state.warped.job, options: unwarpOptions(), machineFrame }, [], (ev) => {
      if (ev.type === 'progress') {
        prog.value = ev.done / ev.total;
        prog.dataset.workerBytes = String(Math.max(Number(prog.dataset.workerBytes || 0), ev.workerBytes || 0));
        text.textContent = `${ev.phase === 'scan' ? 'finding the part' : 'unwarping'} ${Math.round((100 * ev.done) / ev.total)} %`;
      }
    });
    prog.value = 1;
    const secs = (performance.now() - t0) / 1000;
    text.textContent = `done in ${secs.toFixed(1)} s`;
    prog.dataset.done = '1';
    prog.dataset.ms = String(Math.round(performance.now() - t0));
    state.result = out;
    const name = baseName(file.name);
    setDownload('result-download', out.blob, `${name}.${currentPreset().name}.gcode`);
    const summary = makeSummary(out, file);
    setDownload('summary-download', new Blob([JSON.stringify(summary, null, 2)], { type: 'application/json' }), `${name}.summary.json`);
    info($('summary'), Object.entries(summary.display));
    tp.data = out.preview;
    tp.built = null;
    tp.firstBuild = true;
    updateMachineFrameToggle();
    const tv = performance.now();
    setViewMode('toolpath');
    $('sliders').hidden = false;
    prog.dataset.viewMs = String(Math.round(performance.now() - tv));
    prog.dataset.afterMs = String(Math.round(performance.now() - t0) - Number(prog.dataset.ms));
  } catch (e) {
    prog.value = 0;
    if (e.cancelled) {
      text.textContent = 'cancelled';
    } else {
      text.textContent = 'failed';
      setViewMode('model');
      showError(`Cannot unwarp “${file.name}”`, e.message, 'gcode');
    }
  } finally {
    state.busy = false;
    $('cancel').disabled = true;
    $('gcode-input').disabled = !state.warped;
  }
}

function makeSummary(out, file) {
  const r = out.report;
  const d = out.preview;
  // Print length: the sum of extruding segment lengths in the (possibly decimated) preview.
  let printLen = 0;
  for (let i = 1; i < d.count; i++) {
    if (d.flags[i] & 0x80 || d.layer[i] !== d.layer[i - 1]) continue;
    printLen += Math.hypot(d.pos[i * 3] - d.pos[i * 3 - 3], d.pos[i * 3 + 1] - d.pos[i * 3 - 2], d.pos[i * 3 + 2] - d.pos[i * 3 - 1]);
  }
  const s = readSettings();
  return {
    machine: s.machine,
    machine_output: r.machine ? `${r.machine.machine} (${r.machine.flavour})` : '3-axis',
    warp: JSON.parse(state.warped.job).warp,
    gcode_in: file.name,
    bytes_in: file.size,
    bytes_out: out.bytes,
    report: r,
    print_length_mm: d.stride === 1 ? printLen : null,
    worst_interpolation_error_mm: r.machine ? r.machine.worst_position_mm : null,
    display: {
      machine: r.machine ? `${r.machine.machine}, ${r.machine.flavour}, feed ${r.machine.feed}` : `${s.machine} (3-axis)`,
      warp: `${s.warp.kind}`,
      lines: `${r.lines_in.toLocaleString('en')} in → ${r.lines_out.toLocaleString('en')} out`,
      E: `${r.e_in.toFixed(1)} mm in → ${r.e_out.toFixed(1)} mm out (anchor ${r.e_anchor.toFixed(1)}, skirt ${r.e_skirt.toFixed(1)} ${r.skirt})`,
      'print length': d.stride === 1 ? `${(printLen / 1000).toFixed(2)} m` : `preview decimated 1:${d.stride}`,
      'largest tilt': `${r.largest_tilt_deg.toFixed(2)}°`,
      'worst interpolation error': r.machine
        ? `${r.machine.worst_position_mm.toFixed(4)} mm, ${r.machine.worst_angle_deg.toFixed(3)}°`
        : 'none (3-axis: straight moves)',
      placement: `offset ${r.translation.map((v) => v.toFixed(2)).join(', ')} mm, residual ${r.residual.toExponential(2)}`,
      'output size': `${(out.bytes / 1e6).toFixed(2)} MB`,
    },
  };
}

// ---------------------------------------------------------------------------------------------
// Wiring.
// ---------------------------------------------------------------------------------------------
function dropZone(zone, input, onFile) {
  zone.addEventListener('dragover', (e) => {
    e.preventDefault();
    zone.classList.add('over');
  });
  zone.addEventListener('dragleave', () => zone.classList.remove('over'));
  zone.addEventListener('drop', (e) => {
    e.preventDefault();
    zone.classList.remove('over');
    const f = e.dataTransfer?.files?.[0];
    if (f && !input.disabled) onFile(f);
  });
  input.addEventListener('change', () => {
    const f = input.files?.[0];
    if (f) onFile(f);
    input.value = '';
  });
}

function tabs() {
  const list = [...document.querySelectorAll('[role=tab]')];
  const select = (tab) => {
    for (const t of list) {
      const on = t === tab;
      t.setAttribute('aria-selected', String(on));
      t.tabIndex = on ? 0 : -1;
      $(t.getAttribute('aria-controls')).hidden = !on;
    }
    tab.focus();
  };
  list.forEach((t, i) => {
    t.addEventListener('click', () => select(t));
    t.addEventListener('keydown', (e) => {
      if (e.key === 'ArrowRight') select(list[(i + 1) % list.length]);
      if (e.key === 'ArrowLeft') select(list[(i + list.length - 1) % list.length]);
    });
  });
}

let warpTimer = 0;
function scheduleWarp() {
  enforceLimits();
  saveHash();
  clearTimeout(warpTimer);
  if (state.stl) warpTimer = setTimeout(doWarp, 400);
}

async function main() {
  initView();
  tabs();
  const init = await call('init');
  $('version').textContent = `v${init.version}`;
  PRESETS = init.presets;
  for (const p of PRESETS) $('machine-select').add(new Option(`${p.name} — ${p.spec.kind}, ${p.axes.length} axes`, p.name));
  buildWarpParams();
  applySettings(settingsFromHash() ?? {});
  onMachineChange();

  dropZone($('model-drop'), $('model-input'), async (f) => loadModel(new Uint8Array(await f.arrayBuffer()), f.name));
  dropZone($('gcode-drop'), $('gcode-input'), (f) => doUnwarp(f));
  $('example-select').addEventListener('change', async (e) => {
    const name = e.target.value;
    if (!name) return;
    try {
      const { stl } = await call('example', { name });
      await loadModel(new Uint8Array(stl), `${name}.stl`);
    } catch (err) {
      showError('Cannot make the example', err.message, '');
    }
  });
  $('machine-select').addEventListener('change', () => {
    onMachineChange();
    scheduleWarp();
  });
  $('warp-select').addEventListener('change', () => {
    buildWarpParams();
    scheduleWarp();
  });
  $('warp-params').addEventListener('change', scheduleWarp);
  for (const id of ['p-layer_height', 'p-max_edge', 'p-anchor']) $(id).addEventListener('change', scheduleWarp);
  for (const id of ['p-z_offset', 'p-drop_skirt', 'p-place-on', 'p-place-x', 'p-place-y']) $(id).addEventListener('change', () => {
    enforceLimits();
    saveHash();
  });
  $('warp-button').addEventListener('click', doWarp);
  $('show-warped').addEventListener('change', showModel);
  $('show-layers').addEventListener('change', showModel);
  $('cancel').addEventListener('click', () => cancelWorker());
  $('view-mode').addEventListener('change', (e) => setViewMode(e.target.value));
  $('color-mode').addEventListener('change', buildToolpath);
  $('show-travel').addEventListener('change', buildToolpath);
  $('machine-frame').addEventListener('change', () => {
    tp.built = null;
    setViewMode('toolpath');
  });
  $('layer-slider').addEventListener('input', () => onLayerChange(true));
  $('move-slider').addEventListener('input', () => onLayerChange(false));
  $('settings-export').addEventListener('click', () => {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(new Blob([JSON.stringify(readSettings(), null, 2)], { type: 'application/json' }));
    a.download = 'warpslice-settings.json';
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  });
  $('settings-import').addEventListener('change', async (e) => {
    const f = e.target.files?.[0];
    e.target.value = '';
    if (!f) return;
    try {
      applySettings(JSON.parse(await f.text()));
      onMachineChange(false);
      scheduleWarp();
    } catch (err) {
      showError('Cannot read these settings', err.message, '');
    }
  });
  $('settings-link').addEventListener('click', async () => {
    saveHash();
    try {
      await navigator.clipboard.writeText(location.href);
      $('settings-link').textContent = 'Link copied';
    } catch {
      $('settings-link').textContent = 'Link is in the address bar';
    }
    setTimeout(() => ($('settings-link').textContent = 'Copy link to these settings'), 2000);
  });
  window.addEventListener('hashchange', () => {
    const s = settingsFromHash();
    if (s) {
      applySettings(s);
      scheduleWarp();
    }
  });
  document.body.dataset.ready = '1';
  // Offline support where service workers are allowed (https, or http://localhost); the tests
  // use 127.0.0.1 and so run without it.
  if ('serviceWorker' in navigator && (location.protocol === 'https:' || location.hostname === 'localhost')) {
    navigator.serviceWorker.register('./sw.js').catch(() => {});
  }
}

main().catch((e) => showError('The app could not start', e.message, ''));
