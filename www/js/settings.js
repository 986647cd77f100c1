// Settings: the form ⇄ a JSON object ⇄ the URL hash (`#s=<json>`) and the exported file.
//   { machine: preset name, machine_json: custom machine JSON text | null,
//     warp: { kind, …the warp's parameters },            // the core's warp spec
//     <warp option key>: value, …,                       // base, max_edge, tolerance, layer_height, anchor
//     unwarp: { <unwarp option key, dotted = nested>: value, … } }   // the core's UnwarpOptions
// Every key comes from the schema; a value that is not valid for its Param is ignored.
import { $ } from './dom.js';
import { getPath, readRow, setPath, validValue, writeRow } from './params.js';
import { buildWarpParams, enforceLimits, rows, showMachine, warpSchema } from './forms.js';
import { customOn, machineArgument, presetMachine } from './machines.js';

/** The form as a settings object. */
export function readSettings() {
  const s = { machine: $('machine-select').value, machine_json: customOn() ? $('machine-json').value : null, warp: { kind: $('warp-select').value } };
  for (const { row, p } of rows('warp')) s.warp[p.key] = readRow(row, p);
  for (const { row, p } of rows('warp_options')) setPath(s, p.key, readRow(row, p));
  s.unwarp = {};
  for (const { row, p } of rows('unwarp_options')) setPath(s.unwarp, p.key, readRow(row, p));
  return s;
}

/** Shows a settings object in the form (unknown keys and invalid values are ignored). */
export function applySettings(s) {
  if (!s || typeof s !== 'object') return;
  if (typeof s.machine === 'string' && presetMachine(s.machine)) $('machine-select').value = s.machine;
  const custom = typeof s.machine_json === 'string' && s.machine_json.trim() !== '';
  $('machine-custom').checked = custom;
  if (custom) $('machine-json').value = s.machine_json;
  showMachine();
  const kind = s.warp?.kind;
  const opt = [...$('warp-select').options].find((o) => o.value === kind);
  if (opt && !opt.disabled) $('warp-select').value = kind;
  const w = warpSchema($('warp-select').value);
  const values = {};
  for (const p of w.params) if (s.warp && s.warp.kind === w.name && validValue(p, s.warp[p.key])) values[p.key] = s.warp[p.key];
  buildWarpParams(values);
  for (const { row, p } of rows('warp_options')) {
    const v = getPath(s, p.key);
    if (v !== undefined) writeRow(row, p, v);
  }
  for (const { row, p } of rows('unwarp_options')) {
    const v = s.unwarp ? getPath(s.unwarp, p.key) : undefined;
    if (v !== undefined) writeRow(row, p, v);
  }
  enforceLimits();
}

/**
 * The core's WarpOptions for the form: `{ warp: { spec: {kind, …}, base }, max_edge, tolerance,
 * layer_height, anchor }` (`base`, a WarpParams field, goes into `warp`; an option that is off
 * is left out, so the core's default applies).
 */
export function warpOptions() {
  const s = readSettings();
  const o = { warp: { spec: {} } };
  for (const [k, v] of Object.entries(s.warp)) if (v !== null) o.warp.spec[k] = v;
  for (const { p } of rows('warp_options')) {
    const v = getPath(s, p.key);
    if (v === null || v === undefined) continue;
    const key = p.key.replace(/^warp\./, '');
    if (key === 'base') o.warp.base = v;
    else setPath(o, key, v);
  }
  return o;
}

/** The core's UnwarpOptions for the form, with the machine (a preset name or object). */
export function unwarpOptions() {
  const s = readSettings();
  const o = {};
  for (const { p } of rows('unwarp_options')) {
    const v = getPath(s.unwarp, p.key);
    if (v !== null && v !== undefined) setPath(o, p.key, v);
  }
  const machine = machineArgument();
  if (machine !== undefined) o.machine = machine;
  return o;
}

export function saveHash() {
  history.replaceState(null, '', `#s=${encodeURIComponent(JSON.stringify(readSettings()))}`);
}

export function settingsFromHash() {
  const m = /^#s=(.*)$/.exec(location.hash);
  if (!m) return null;
  try {
    return JSON.parse(decodeURIComponent(m[1]));
  } catch {
    return null;
  }
}
