// The built-in slicer's settings editor, built from the core's own description: one row per key
// of `describe().slicer_settings` (the core's defaults: a 0.4 mm nozzle / 1.75 mm PLA profile,
// keys named as PrusaSlicer's options), its type from its default's JSON type. What the page
// sends the core is the JSON object of the CLI's `--slicer-settings` file: the keys whose value
// differs from the core's default, and any key the page does not know (from a link or a loaded
// file) as it is, so the core names it (`planar.settings-json`) instead of the page dropping it.
// The layer heights are the warp's (`layer_height` of the Slicing options): the core starts
// from them, so the form leaves those two keys out.
import { state } from './state.js';
import { $ } from './dom.js';
import { paramRow, readRow, validValue, writeRow } from './params.js';

/** Keys the form leaves out: the core sets them to the warp's layer height. */
const FROM_THE_WARP = ['layer_height', 'first_layer_height'];

/** A `Param` (params.js) for slicer setting `key` with the core's default `v`. */
function paramOf(key, v) {
  const type = typeof v === 'boolean' ? 'bool' : Array.isArray(v) ? (v.length === 2 ? 'pair' : 'triple') : 'number';
  return {
    key, flag: null, label: key, type, unit: '', min: null, max: null, min_exclusive: false, max_exclusive: false,
    step: null, default: v, optional: false, choices: null,
    help: `default ${Array.isArray(v) ? v.join(', ') : String(v)}; the CLI: --set ${key}=${JSON.stringify(v)}`,
  };
}

/** The slicer settings' Params, in the core's order. */
export function slicerParams() {
  return Object.entries(state.schema.slicer_settings).filter(([k]) => !FROM_THE_WARP.includes(k)).map(([k, v]) => paramOf(k, v));
}

function rows() {
  const params = slicerParams();
  return [...$('slicer-settings').querySelectorAll(':scope > .param')].map((row) => ({ row, p: params.find((q) => q.key === row.dataset.key) })).filter((r) => r.p);
}

/** Builds the editor (once, after `describe()`). */
export function buildSlicerForm() {
  $('slicer-settings').replaceChildren(...slicerParams().map((p) => {
    const row = paramRow(p, 'slicer', `s-${p.key}`);
    row.querySelector('[data-param]').setAttribute('data-testid', `slicer-${p.key}`);
    return row;
  }));
}

/**
 * The settings JSON object sent to the core: the keys that differ from its defaults, then the
 * keys the page does not know (kept from the last settings applied, sent as they are).
 */
export function slicerSettings() {
  const out = {};
  for (const { row, p } of rows()) {
    const v = readRow(row, p);
    if (JSON.stringify(v) !== JSON.stringify(p.default)) out[p.key] = v;
  }
  return { ...out, ...state.slicerExtra };
}

/**
 * Shows a slicer settings object (`--slicer-settings` JSON): every row back to the core's
 * default, then the keys it names; a key the form has no row for (unknown to the core, or a
 * layer height) or a value of the wrong type is kept in `state.slicerExtra` and sent as it is.
 */
export function applySlicerSettings(obj) {
  state.slicerExtra = {};
  const byKey = new Map(rows().map((r) => [r.p.key, r]));
  for (const { row, p } of byKey.values()) writeRow(row, p, p.default);
  if (!obj || typeof obj !== 'object' || Array.isArray(obj)) return;
  for (const [k, v] of Object.entries(obj)) {
    const r = byKey.get(k);
    if (r && validValue(r.p, v)) writeRow(r.row, r.p, v);
    else state.slicerExtra[k] = v;
  }
  showExtra();
}

/** The keys sent as they are, listed under the editor. */
function showExtra() {
  const keys = Object.keys(state.slicerExtra);
  $('slicer-extra').textContent = keys.length ? `also sent as given (the core checks them): ${keys.map((k) => `${k} = ${JSON.stringify(state.slicerExtra[k])}`).join(', ')}` : '';
}

/** The CLI's `--set key=value` arguments for `slicerSettings()` (`warpslice run --slicer builtin`). */
export function slicerCliArgs() {
  return Object.entries(slicerSettings()).flatMap(([k, v]) => ['--set', `${k}=${JSON.stringify(v)}`]);
}
