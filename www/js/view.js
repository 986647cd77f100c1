// The 3D view (three.js): scene, camera, orbit controls, the model with its layer surfaces
// coloured by tilt and the warped mesh beside it, and the colour legend.
import * as THREE from '../vendor/three.module.js';
import { OrbitControls } from '../vendor/OrbitControls.js';
import { STLLoader } from '../vendor/STLLoader.js';
import { state } from './state.js';
import { $ } from './dom.js';
import { currentMachine } from './machines.js';
import { overhangFacets, tiltFacets } from './overhang.js';

/** Colour of a facet that overhangs (`overhang.js`). */
const OVERHANG_COLOR = 0xd62728;
/** Colour of what tilts beyond the machine's limit (layer-surface samples, tilt-map facets). */
const OVER_LIMIT_COLOR = 0xff00ff;

const view = state.view;

/** The `performance.measure` name of one WebGL frame (`renderer.render`), start to end. */
export const FRAME_MEASURE = 'warpslice-frame';
/** Frames rendered so far (their measures are cleared every 1000). */
let frames = 0;

export function initView() {
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
      const t1 = performance.now();
      wrap.dataset.renderMs = String(Math.max(Number(wrap.dataset.renderMs || 0), Math.round(t1 - t)));
      // the frame's interval, for the web tier's long-task figure (main-thread tasks outside
      // WebGL frames); the measure is consumed by a PerformanceObserver there, not buffered
      // here past a few (a page left open does not grow the timeline)
      performance.measure(FRAME_MEASURE, { start: t, end: t1 });
      if (++frames % 1000 === 0) performance.clearMeasures(FRAME_MEASURE);
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

export function clearGroup(g) {
  if (g.children.length) view.dirty = true;
  for (const c of [...g.children]) {
    g.remove(c);
    c.geometry?.dispose();
    c.material?.dispose();
  }
}

export function frame(box) {
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
export function tiltColor(deg, max, c = new THREE.Color()) {
  const t = Math.max(0, Math.min(1, deg / (max || 1)));
  return c.setHSL((1 - t) * 0.66, 0.85, 0.5);
}

function stlGeometry(bytes) {
  const buf = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const g = new STLLoader().parse(buf);
  g.computeVertexNormals();
  return g;
}

export function showModel() {
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
  // overhanging facets (the core's per-facet flags, STL order = the loader's triangle order),
  // or with the tilt map every facet by the core's tool tilt at its centroid
  const facets = overhangFacets();
  const tilts = tiltFacets();
  const triangles = geom.attributes.position.count / 3;
  const limit = currentMachine()?.max_tilt_deg ?? null;
  const maxTilt = Math.max(1, state.warped?.report.largest_tilt_deg ?? 0);
  const wrap = $('canvas-wrap');
  for (const k of ['tiltFacets', 'tiltOverLimit', 'tiltChecksum', 'tiltMax']) delete wrap.dataset[k];
  const tiltMap = state.warped && tilts && tilts.length === triangles;
  const coloured = tiltMap || (facets && facets.length === triangles);
  if (tiltMap) {
    const col = new Float32Array(tilts.length * 9);
    const c = new THREE.Color(), over = new THREE.Color(OVER_LIMIT_COLOR);
    let nOver = 0, checksum = 0, top = 0;
    for (let f = 0; f < tilts.length; f++) {
      const t = tilts[f];
      const beyond = limit != null && t > limit + 1e-6;
      nOver += beyond;
      checksum += (f + 1) * t;
      top = Math.max(top, t);
      const fc = beyond ? over : tiltColor(t, maxTilt, c);
      for (let v = 0; v < 3; v++) fc.toArray(col, f * 9 + v * 3);
    }
    geom.setAttribute('color', new THREE.BufferAttribute(col, 3));
    // what the page coloured, for the tests: Σ (i + 1)·tilt_i sees each facet's own tilt
    Object.assign(wrap.dataset, { tiltFacets: String(tilts.length), tiltOverLimit: String(nOver), tiltChecksum: String(checksum), tiltMax: String(top) });
    delete wrap.dataset.overhangFacets;
  } else if (coloured) {
    const col = new Float32Array(facets.length * 9);
    const base = new THREE.Color(0xb8c4d0), hot = new THREE.Color(OVERHANG_COLOR);
    let n = 0;
    for (let f = 0; f < facets.length; f++) {
      const c = facets[f] ? hot : base;
      n += facets[f];
      for (let v = 0; v < 3; v++) c.toArray(col, f * 9 + v * 3);
    }
    geom.setAttribute('color', new THREE.BufferAttribute(col, 3));
    $('canvas-wrap').dataset.overhangFacets = String(n);
  } else {
    delete $('canvas-wrap').dataset.overhangFacets;
  }
  const mat = new THREE.MeshStandardMaterial({ color: coloured ? 0xffffff : 0xb8c4d0, vertexColors: !!coloured, roughness: 0.7, transparent: !!showLayers, opacity: showLayers ? 0.35 : 1, side: THREE.DoubleSide });
  view.modelGroup.add(new THREE.Mesh(geom, mat));
  const box = new THREE.Box3().setFromBufferAttribute(geom.attributes.position);
  if (state.warped) {
    const w = state.warped;
    if (showLayers && w.surfaces.length) {
      const n = w.surfaces.length / 5;
      const inside = footprint(geom, JSON.parse(w.job).model_bbox, SURFACE_GRID);
      const pos = new Float32Array(n * 3), col = new Float32Array(n * 3);
      const c = new THREE.Color();
      // Samples beyond the machine's tilt limit are drawn magenta.
      const over = new THREE.Color(OVER_LIMIT_COLOR);
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
    legendTilt(maxTilt, tiltMap ? 'tool tilt (facets, layers)' : 'layer tilt');
    // the machine's limit on the same scale, and the colour of what passes it
    if (limit != null) {
      const row = document.createElement('div');
      row.dataset.testid = 'legend-tilt-limit';
      const sw = document.createElement('span');
      sw.className = 'sw';
      sw.style.background = `#${(limit < maxTilt ? new THREE.Color(OVER_LIMIT_COLOR) : tiltColor(limit, maxTilt)).getHexString()}`;
      row.append(sw, `machine limit ${limit}°${limit < maxTilt ? ': beyond it' : ''}`);
      $('legend').append(row);
    } else if (Number(wrap.dataset.overLimit) > 0) {
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
export const SURFACE_GRID = 48;

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

export function legendTilt(max, title) {
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
