// Issue 15 in the page: how much of the model overhangs, planar and under the current warp (the
// core's `overhangs`, the measure of `warpslice overhangs`), the model's overhanging facets
// coloured in the view, and "Suggest a warp": the core's ranked admissible warps for the machine
// (`warpslice suggest`), each applied to the form with one click. Both run in the worker.
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
