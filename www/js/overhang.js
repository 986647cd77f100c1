// Issue 15 in the page: how much of the model overhangs, planar and under the current warp (the
// core's `overhangs`, the measure of `warpslice overhangs`), the model's overhanging facets
// coloured in the view (or, with the tilt map, every facet by the warp's tool tilt there), and
// "Suggest a warp": the core's ranked admissible warps for the machine
// (`warpslice suggest`), each applied to the form with one click; and the field warp's
// expression box checked as it is typed (the core's `overhangs` under the typed g: its error
// code and message, or the overhang left and the largest tilt, under the box). All run in the
// worker.
import { state } from './state.js';
import { $, el } from './dom.js';
import { call } from './worker-client.js';
import { applySettings, readSettings, warpOptions } from './settings.js';
import { currentMachine, customOn, customText, selectedPreset } from './machines.js';
import { showError } from './errors.js';

/** The printable overhang angle θ of the form (degrees; the core's default when empty). */
function overhangAngle() {
  const v = Number($('overhang-angle').value);
  return Number.isFinite(v) && v > 0 && v < 90 ? v : 45;
}

/** `area (percent)` of an `OverhangMeasure`. */
function measureText(m) {
  return `${m.area_mm2.toFixed(1)} mm² (${m.percent.toFixed(1)} % of the surface, ${m.facets} facets)`;
}

/**
 * Measures the model's overhang planar and under the warp of the form (after a warp), shows
 * both and colours the overhanging facets (`view.js` reads `state.overhangs`).
 */
export async function refreshOverhangs() {
  if (!state.stl) return;
  const seq = ++state.overhangSeq;
  const options = state.warped ? JSON.stringify(warpOptions()) : '';
  try {
    const out = await call('overhangs', { stl: state.stl.buffer.slice(0), options, angle: overhangAngle() });
    if (seq !== state.overhangSeq) return;
    state.overhangs = out.report;
    showOverhangs();
  } catch (e) {
    if (seq !== state.overhangSeq) return;
    state.overhangs = null;
    $('overhang-info').textContent = '';
    if (!e.cancelled) showError('Cannot measure the overhang', e, 'warp');
  }
}

/** The overhang figures of `state.overhangs` in the warp step. */
function showOverhangs() {
  const r = state.overhangs;
  const box = $('overhang-info');
  if (!r) {
    box.textContent = '';
    return;
  }
  const lines = [`overhang beyond ${r.overhang_angle_deg}°: planar ${measureText(r.planar)}`];
  if (r.warped) lines.push(`this warp (${r.flags}): ${measureText(r.warped)}`);
  box.textContent = lines.join('; ');
  box.dataset.planarMm2 = String(r.planar.area_mm2);
  box.dataset.warpedMm2 = r.warped ? String(r.warped.area_mm2) : '';
  box.dataset.flags = r.flags ?? '';
}

/** The per-facet 0/1 overhang flags to colour (the warp's when one is applied), or null. */
export function overhangFacets() {
  const r = state.overhangs;
  if (!r || !$('show-overhangs').checked) return null;
  return r.warped ? r.warped_facets : r.planar_facets;
}

/**
 * The tilt map: the warp's tool tilt from +z at each facet's centroid (degrees, the core's
 * `warped_tilts_deg`, facet order), when a warp is applied and the map is switched on; or null.
 */
export function tiltFacets() {
  const r = state.overhangs;
  if (!r?.warped_tilts_deg?.length || !$('show-tilt-map').checked) return null;
  return r.warped_tilts_deg;
}

/** The machine `suggest` is asked for: the custom machine JSON or the preset's name. */
function suggestMachine() {
  if (customOn()) return customText();
  return selectedPreset()?.name ?? currentMachine()?.name;
}

/** "Suggest a warp": the core's ranked warps for the machine, each with an Apply button. */
export async function doSuggest() {
  if (!state.stl) return;
  const list = $('suggestions');
  list.replaceChildren();
  list.dataset.done = '0';
  $('suggest-info').textContent = 'searching…';
  const layer = Number(readSettings().layer_height) || undefined;
  const options = JSON.stringify({ overhang_angle: overhangAngle(), ...(layer ? { layer_height: layer } : {}) });
  try {
    const out = await call('suggest', { stl: state.stl.buffer.slice(0), machine: suggestMachine(), options });
    const r = out.report;
    state.suggestions = r;
    $('suggest-info').textContent = r.suggestions.length
      ? `${r.machine}: planar leaves ${measureText(r.planar)}; ${r.measured} warps measured, the best first:`
      : `${r.machine}: no admissible warp leaves less overhang than planar (${measureText(r.planar)})`;
    r.suggestions.forEach((s, i) => {
      const apply = el('button', { type: 'button', dataset: { testid: `suggestion-apply-${i + 1}` } }, 'Apply');
      apply.addEventListener('click', () => applySuggestion(i));
      list.append(el('li', { dataset: { testid: `suggestion-${i + 1}`, flags: s.flags, areaMm2: String(s.overhang_area_mm2) } },
        `${s.flags} — ${s.overhang_area_mm2.toFixed(1)} mm² left (${s.overhang_percent.toFixed(1)} %), largest tilt ${s.largest_tilt_deg.toFixed(1)}°, ${s.layers} layers `, apply));
    });
  } catch (e) {
    $('suggest-info').textContent = '';
    if (!e.cancelled) showError('Cannot suggest a warp', e, 'warp');
  } finally {
    list.dataset.done = '1';
  }
}

/** Puts suggestion `i`'s warp into the form (the base blend too) and warps again. */
function applySuggestion(i) {
  const s = state.suggestions?.suggestions[i];
  if (!s) return;
  const { kind, ...params } = s.warp.spec;
  const settings = readSettings();
  settings.warp = { kind, ...params };
  settings.base = s.warp.base ?? null;
  applySettings(settings);
  // the form's change handlers re-warp; this says it at once
  $('warp-params').dispatchEvent(new Event('change'));
}

/** Milliseconds after the last keystroke in the field's expression box before it is checked. */
const FIELD_CHECK_DELAY_MS = 300;
let fieldTimer = null;

/** Checks the field warp's expression while it is typed (the box's `input` events). */
export function watchFieldExpression() {
  $('warp-params').addEventListener('input', (e) => {
    if (e.target?.dataset?.param !== 'expr') return;
    clearTimeout(fieldTimer);
    fieldTimer = setTimeout(checkFieldExpression, FIELD_CHECK_DELAY_MS);
  });
}

/** The status line under the expression box (made on first use), or null without one. */
function fieldStatus() {
  const row = $('warp-params').querySelector('.param[data-key="expr"]');
  if (!row) return null;
  let s = row.querySelector('[data-testid="field-check"]');
  if (!s) {
    s = el('small', { className: 'field-check', role: 'status', dataset: { testid: 'field-check' } });
    row.append(s);
  }
  return s;
}

/**
 * The core's verdict on the typed field over the loaded model: `warpslice overhangs` under the
 * warp of the form, in the worker. Refused: the core's code and message under the box; else the
 * overhang left under the field (planar beside it) and the largest tilt, and the view colours
 * the facets that still overhang under it.
 */
export async function checkFieldExpression() {
  const box = fieldStatus();
  if (!box || !state.stl) return;
  const seq = ++state.fieldSeq;
  const expr = $('warp-params').querySelector('[data-param="expr"]')?.value ?? '';
  box.dataset.state = 'checking';
  try {
    const options = JSON.stringify(warpOptions());
    const out = await call('overhangs', { stl: state.stl.buffer.slice(0), options, angle: overhangAngle() });
    if (seq !== state.fieldSeq) return;
    const r = out.report;
    box.textContent = `the core takes g(x, y): ${measureText(r.warped)} overhanging (planar ${r.planar.area_mm2.toFixed(1)} mm²), largest tilt ${r.warped.largest_tilt_deg.toFixed(1)}°`;
    box.dataset.warpedMm2 = String(r.warped.area_mm2);
    delete box.dataset.code;
    box.dataset.expr = expr;
    box.dataset.state = 'ok';
  } catch (e) {
    if (seq !== state.fieldSeq || e.cancelled) return;
    box.textContent = `${e.code ?? 'error'}: ${e.message}`;
    box.dataset.code = e.code ?? '';
    delete box.dataset.warpedMm2;
    box.dataset.expr = expr;
    box.dataset.state = 'error';
  }
}
