// Settings: the form ⇄ a JSON object ⇄ the URL hash (`#s=<json>`) and the exported file.
//   { machine: preset name, machine_json: custom machine JSON text | null,
//     warp: { kind, …the warp's parameters },            // the core's warp spec
//     <warp option key>: value, …,                       // base, max_edge, tolerance, layer_height, anchor
//     unwarp: { <unwarp option key, dotted = nested>: value, … },    // the core's UnwarpOptions
//     slicer: { <built-in slicer setting>: value, … } }   // keys that differ from the core's defaults
// Every key comes from the schema; a value that is not valid for its Param is ignored.
import { state } from './state.js';
import { $ } from './dom.js';
import { getPath, readRow, setPath, validValue, writeRow } from './params.js';
import { buildWarpParams, enforceLimits, rows, showMachine, warpSchema } from './forms.js';
import { customOn, describeCustom, machineArgument, presetMachine } from './machines.js';
import { applySlicerSettings, slicerSettings } from './slicer-form.js';

/** The form as a settings object. */
export function readSettings() {
  const s = { machine: $('machine-select').value, machine_json: customOn() ? $('machine-json').value : null, warp: { kind: $('warp-select').value } };
  for (const { row, p } of rows('warp')) s.warp[p.key] = readRow(row, p);
  for (const { row, p } of rows('warp_options')) setPath(s, p.key, readRow(row, p));
  s.unwarp = {};
  for (const { row, p } of rows('unwarp_options')) setPath(s.unwarp, p.key, readRow(row, p));
  s.slicer = slicerSettings();
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
  if (s.slicer !== undefined) applySlicerSettings(s.slicer);
  enforceLimits();
}

/**
 * Shows a settings object in the form like `applySettings`, its custom machine JSON described by
 * the core first (so that the warp the settings name is offered when that machine prints it).
 */
export async function loadSettings(s) {
  if (s && typeof s === 'object' && typeof s.machine_json === 'string' && s.machine_json.trim() !== '') await describeCustom(s.machine_json);
  applySettings(s);
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

/**
 * The CLI's arguments for the form (`warpslice warp MODEL <warp> -o OUT`, `warpslice unwarp
 * GCODE --job JOB <unwarp> -o OUT`): every value that differs from its default, by the
 * Param's flag; a custom machine is `--machine <its name>.json`.
 */
export function cliArgs() {
  const s = readSettings();
  const add = (out, p, v) => {
    if (v == null || !p.flag || JSON.stringify(v) === JSON.stringify(p.default)) return;
    if (p.type === 'bool') {
      if (v) out.push(p.flag);
    } else out.push(p.flag, Array.isArray(v) ? v.join(',') : String(v));
  };
  const warp = ['--warp', s.warp.kind];
  for (const p of warpSchema(s.warp.kind).params) add(warp, p, s.warp[p.key]);
  for (const p of state.schema.warp_options) add(warp, p, getPath(s, p.key));
  const unwarp = [];
  for (const p of state.schema.unwarp_options) add(unwarp, p, getPath(s.unwarp, p.key));
  const machine = machineArgument();
  if (machine !== undefined) unwarp.push('--machine', typeof machine === 'string' ? machine : `${String(machine.name ?? 'custom')}.json`);
  return { warp, unwarp };
}

/** A command line as text (arguments with spaces or quotes quoted). */
export function commandLine(args) {
  return args.map((a) => (/^[\w@%+=:,./-]+$/.test(a) ? a : `'${a.replace(/'/g, `'\\''`)}'`)).join(' ');
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
