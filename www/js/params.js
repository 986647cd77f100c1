// One form row per parameter of the core's schema (`describe()`'s `Param`):
//   { key, flag, label, type: number|choice|bool|pair|triple|text, unit, min, max, min_exclusive,
//     max_exclusive, step, default, optional, choices, help }
// A row is `<div class="param" data-group data-key data-type>` holding its input(s); reading
// and writing a row's value and clamping it to its limits work from the Param alone, so a new
// warp or option of the core appears in the page without a line of JS.
import { el } from './dom.js';

/** Number of inputs of a Param's type. */
const ARITY = { pair: 2, triple: 3 };
/** Suffixes of the inputs of a pair / triple (`p-place-x`, `p-place-y`). */
const PART = ['x', 'y', 'z'];
/** Test hooks kept from before the schema (the browser tests address these inputs). */
const TESTIDS = { layer_height: 'layer-height' };

/** A unit as shown after the label. */
export function unitText(unit) {
  return unit === 'deg' ? '°' : unit || '';
}

/** The label text of a Param: its label and unit. */
export function labelText(p) {
  const u = unitText(p.unit);
  return u ? `${p.label} (${u})` : p.label;
}

/** The input ids of a row (one per value; `base` is the id for one value). */
export function inputIds(p, base) {
  const n = ARITY[p.type];
  return n ? PART.slice(0, n).map((s) => `${base}-${s}`) : [base];
}

function numberInput(p, id, v) {
  return el('input', {
    type: 'number', id, value: v == null ? '' : String(v),
    min: p.min ?? null, max: p.max ?? null, step: p.step ?? 'any',
    dataset: { minExclusive: p.min_exclusive ? '1' : null, maxExclusive: p.max_exclusive ? '1' : null },
  });
}

/**
 * The row of Param `p` in `group` (`warp`, `warp_options`, `unwarp_options`) with ids from
 * `idBase`, showing `value` (undefined: the default; null: off, for an optional Param).
 */
export function paramRow(p, group, idBase, value) {
  const v = value === undefined ? p.default : value;
  const ids = inputIds(p, idBase);
  const helpId = `${idBase}-help`;
  const row = el('div', { className: 'param', dataset: { group, key: p.key, type: p.type, flag: p.flag ?? null, optional: p.optional ? '1' : null } });
  const testid = TESTIDS[p.key] ?? (group === 'warp' ? `param-${p.key}` : `opt-${p.key.replace(/\./g, '-')}`);
  let inputs;
  if (p.type === 'choice') {
    const sel = el('select', { id: ids[0] });
    if (p.optional) sel.add(new Option('— (default)', ''));
    for (const c of p.choices ?? []) sel.add(new Option(c, c));
    sel.value = v == null ? '' : String(v);
    inputs = [sel];
  } else if (p.type === 'bool') {
    inputs = [el('input', { type: 'checkbox', id: ids[0], checked: !!v })];
    // A switch on by default (the collision check) has no off flag in the CLI (a flag sets it),
    // so the page cannot switch it off either: shown checked, fixed. (A value without a flag,
    // a built-in slicer setting, is `--set key=false` on the CLI: it can be switched off.)
    if (p.default === true && p.flag) {
      inputs[0].checked = true;
      inputs[0].disabled = true;
    }
  } else if (p.type === 'text') {
    inputs = [el('input', { type: 'text', id: ids[0], value: v == null ? '' : String(v), spellcheck: false, autocomplete: 'off' })];
  } else if (ARITY[p.type]) {
    const arr = Array.isArray(v) ? v : [];
    inputs = ids.map((id, k) => numberInput(p, id, arr[k] ?? (Array.isArray(p.default) ? p.default[k] : '')));
    inputs.forEach((inp, k) => inp.setAttribute('aria-label', `${labelText(p)}, ${PART[k]}`));
  } else {
    inputs = [numberInput(p, ids[0], v)];
  }
  inputs[0].dataset.param = p.key;
  inputs[0].setAttribute('data-testid', testid);
  for (const inp of inputs) inp.setAttribute('aria-describedby', helpId);
  const help = el('small', { id: helpId }, p.help ?? '', ...(p.flag ? [' (', el('code', { className: 'flag', textContent: p.flag }), ')'] : []));
  // An optional value (default null) is switched on by a checkbox; off = not sent.
  const optionalSwitch = p.optional && p.type !== 'choice' && p.type !== 'bool';
  if (p.type === 'bool') {
    row.append(el('label', { className: 'check', htmlFor: ids[0] }, inputs[0], ` ${labelText(p)}`), el('span'), help);
  } else if (optionalSwitch) {
    const on = el('input', { type: 'checkbox', id: `${idBase}-on`, checked: v != null, 'data-testid': `${p.key.replace(/\./g, '-')}-on` });
    on.dataset.switch = '1';
    on.addEventListener('change', () => syncSwitch(row));
    const span = el('span', { className: 'values' });
    inputs.forEach((inp, k) => span.append(...(k ? [' , ', inp] : [inp])));
    row.append(el('label', { className: 'check', htmlFor: `${idBase}-on` }, on, ` ${labelText(p)}`), span, help);
  } else {
    const span = el('span', { className: 'values' });
    inputs.forEach((inp, k) => span.append(...(k ? [' , ', inp] : [inp])));
    row.append(el('label', { htmlFor: ids[0], textContent: labelText(p) }), span, help);
  }
  syncSwitch(row);
  return row;
}

/**
 * An optional row's inputs follow its switch: disabled while it is off; switched on with
 * nothing typed, they show the numbers that will be sent (0).
 */
function syncSwitch(row) {
  const sw = row.querySelector('[data-switch]');
  if (!sw) return;
  for (const inp of rowInputs(row)) {
    inp.disabled = !sw.checked;
    if (sw.checked && inp.value === '') inp.value = '0';
  }
}

function rowInputs(row) {
  return [...row.querySelectorAll('input:not([data-switch]), select')];
}

/** The value of a row: a number, string, bool or array; null when an optional one is off. */
export function readRow(row, p) {
  const sw = row.querySelector('[data-switch]');
  if (sw && !sw.checked) return null;
  const inputs = rowInputs(row);
  if (p.type === 'bool') return inputs[0].checked;
  if (p.type === 'choice') return inputs[0].value === '' ? null : inputs[0].value;
  if (p.type === 'text') return inputs[0].value;
  const nums = inputs.map((i) => Number(i.value));
  return ARITY[p.type] ? nums : nums[0];
}

/** Whether `v` is a value of Param `p` (null: off, allowed for an optional one). */
export function validValue(p, v) {
  if (v == null) return !!p.optional;
  if (p.type === 'bool') return typeof v === 'boolean';
  if (p.type === 'choice') return (p.choices ?? []).includes(v);
  if (p.type === 'text') return typeof v === 'string';
  if (ARITY[p.type]) return Array.isArray(v) && v.length === ARITY[p.type] && v.every(Number.isFinite);
  return Number.isFinite(v);
}

/** Shows `v` in a row (an invalid value leaves the row as it is). */
export function writeRow(row, p, v) {
  if (!validValue(p, v)) return;
  const sw = row.querySelector('[data-switch]');
  if (sw) sw.checked = v != null;
  const inputs = rowInputs(row);
  if (v == null) {
    if (p.type === 'choice') inputs[0].value = '';
  } else if (p.type === 'bool') inputs[0].checked = (p.default === true && !!p.flag) || v;
  else if (ARITY[p.type]) inputs.forEach((inp, k) => (inp.value = String(v[k])));
  else inputs[0].value = String(v);
  syncSwitch(row);
}

/**
 * Clamps a row's numbers to the Param's limits (`max` tightened by `maxOverride`, e.g. a
 * machine's tilt limit); an empty or non-numeric entry goes back to the default.
 */
export function clampRow(row, p, maxOverride = null) {
  if (p.type !== 'number' && !ARITY[p.type]) return;
  const max = maxOverride != null && (p.max == null || maxOverride < p.max) ? maxOverride : p.max;
  const inputs = rowInputs(row);
  const step = p.step ?? 0;
  inputs.forEach((inp, k) => {
    inp.max = max ?? '';
    const dflt = Array.isArray(p.default) ? p.default[k] : p.default;
    const v = Number(inp.value);
    if (inp.value === '' || !Number.isFinite(v)) {
      if (dflt != null) inp.value = String(dflt);
      return;
    }
    if (p.min != null && (v < p.min || (p.min_exclusive && v <= p.min))) inp.value = String(p.min_exclusive ? (dflt != null && dflt > p.min ? dflt : p.min + (step || 1e-3)) : p.min);
    else if (max != null && (v > max || (p.max_exclusive && max === p.max && v >= max))) inp.value = String(p.max_exclusive && max === p.max ? max - (step || 1e-3) : max);
  });
}

/** Sets `obj[a][b]…` for the dotted key `a.b…`. */
export function setPath(obj, key, v) {
  const parts = key.split('.');
  let o = obj;
  for (const k of parts.slice(0, -1)) o = o[k] && typeof o[k] === 'object' ? o[k] : (o[k] = {});
  o[parts.at(-1)] = v;
}

/** `obj[a][b]…` for the dotted key `a.b…` (undefined when absent). */
export function getPath(obj, key) {
  let o = obj;
  for (const k of key.split('.')) {
    if (o == null || typeof o !== 'object') return undefined;
    o = o[k];
  }
  return o;
}
