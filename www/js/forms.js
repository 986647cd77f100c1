// The forms, generated from the core's schema (`describe()`): the machine select (presets), the
// warp select and the selected warp's parameters, the warp options (slicing) and the unwarp
// options. Limits are the schema's; a machine narrows them by its tilt limit (a warp's degree
// parameter is its layer tilt) and by the warps it can print.
import { state } from './state.js';
import { $ } from './dom.js';
import { clampRow, paramRow } from './params.js';
import { axesText, currentMachine, selectedPreset } from './machines.js';

/** The warp the page starts with (any warp of the schema can be chosen). */
const FIRST_WARP = 'conic';

/** The schema entry of warp `name`. */
export function warpSchema(name) {
  return state.schema.warps.find((w) => w.name === name);
}

/** The rows of a group, each with its Param: [{row, p}]. */
export function rows(group) {
  const box = { warp: $('warp-params'), warp_options: $('warp-options'), unwarp_options: $('unwarp-options') }[group];
  const params = group === 'warp' ? warpSchema($('warp-select').value)?.params ?? [] : state.schema[group];
  return [...box.querySelectorAll(':scope > .param')].map((row) => ({ row, p: params.find((q) => q.key === row.dataset.key) })).filter((r) => r.p);
}

/** Id of an option row's input: `p-<key>`, `p-unwarp-<key>` when a warp option has that key too. */
function optionId(group, key) {
  const k = key.replace(/\./g, '-');
  if (group === 'unwarp_options' && state.schema.warp_options.some((p) => p.key === key)) return `p-unwarp-${k}`;
  return `p-${k}`;
}

/** Fills the machine and warp selects and the option fieldsets (once, after `describe()`). */
export function buildForms() {
  const ms = $('machine-select');
  for (const m of state.schema.machines) ms.add(new Option(`${m.name} — ${m.kind}, ${m.axes.length} axes`, m.name));
  const ws = $('warp-select');
  for (const w of state.schema.warps) ws.add(new Option(`${w.name} — ${w.help}`, w.name));
  ws.value = warpSchema(FIRST_WARP) ? FIRST_WARP : state.schema.warps[0].name;
  for (const group of ['warp_options', 'unwarp_options']) {
    const box = $(group === 'warp_options' ? 'warp-options' : 'unwarp-options');
    box.replaceChildren(...state.schema[group].map((p) => paramRow(p, group, optionId(group, p.key))));
  }
  buildWarpParams();
}

/** The selected warp's parameter rows, showing `values` (a warp spec) where given. */
export function buildWarpParams(values = {}) {
  const w = warpSchema($('warp-select').value);
  const box = $('warp-params');
  box.replaceChildren(...w.params.map((p) => paramRow(p, 'warp', `p-${w.name}-${p.key}`, values[p.key])));
  const formula = document.createElement('small');
  formula.className = 'formula';
  formula.textContent = `${w.formula}${w.seed ? ` (seed ${w.seed})` : ''}`;
  box.append(formula);
  enforceLimits();
}

/** Clamps every number to its limits (the machine's tilt limit included) and fixes a fixed tilt. */
export function enforceLimits() {
  const m = currentMachine();
  for (const { row, p } of rows('warp')) {
    const tilt = p.unit === 'deg';
    clampRow(row, p, tilt ? m?.max_tilt_deg ?? null : null);
    const fixed = tilt && m?.fixed_tilt_deg != null;
    const input = row.querySelector('input[type=number]');
    if (fixed && input) input.value = String(m.fixed_tilt_deg);
    input?.toggleAttribute('readonly', fixed);
  }
  for (const group of ['warp_options', 'unwarp_options']) for (const { row, p } of rows(group)) clampRow(row, p);
  const lh = $('p-layer_height');
  for (const e of document.querySelectorAll('.lh')) e.textContent = lh ? lh.value : '';
}

/** Machine info line, and the warps this machine cannot print disabled (the first it can picked). */
export function showMachine() {
  const m = currentMachine();
  const standIn = m.standIn === 'last' ? `the last custom machine it accepted, “${m.name}”` : 'the preset';
  const bad = m.customError ? `custom machine JSON refused: ${m.customError.message} (until it is fixed: ${standIn}) — `
    : m.customPending ? `checking the custom machine JSON… (meanwhile: ${standIn}) — ` : '';
  const custom = m.custom ? `custom machine “${m.name}” (${m.kind}; its own axes, limits and warps, from the core)` : `${m.name} (${m.kind})`;
  const notes = (m.notes ?? []).map((n) => n.replace(/\.$/, '')).join('; ');
  const summary = m.summary && !notes.startsWith(m.summary) ? `${m.summary.replace(/\.$/, '')}; ` : '';
  $('machine-info').textContent = `${bad}${custom} — ${summary}axes ${axesText(m)}${notes ? `; ${notes}` : ''}. ` +
    `Output: ${m.name === 'cartesian' && !m.custom ? '3-axis G-code' : `the machine's G-code (${m.flavour})`}.`;
  const sel = $('warp-select');
  for (const o of sel.options) o.disabled = !m.warps.includes(o.value);
  if (sel.selectedOptions[0]?.disabled) {
    sel.value = m.warps.includes(FIRST_WARP) ? FIRST_WARP : m.warps[0];
    return true;
  }
  return false;
}

/** Fills the custom machine textarea with the selected preset's JSON when it is empty. */
export function seedCustomJson() {
  const ta = $('machine-json');
  if (!ta.value.trim()) ta.value = JSON.stringify(selectedPreset().spec, null, 2);
}
