// The machine of the form: a preset of the core's schema (`describe().machines`) or a custom
// machine JSON pasted into the textarea, as the core describes it (`describe_machine`, asked in
// the worker). Everything the page knows about a machine (its axes, tilt limits, the warps it can
// print, whether it moves its bed) comes from that schema entry, computed by the core from the
// machine's own parameters.
import { state } from './state.js';
import { $ } from './dom.js';
import { call } from './worker-client.js';

/** The schema entry of the preset `name` (undefined when there is none). */
export function presetMachine(name) {
  return state.schema?.machines.find((m) => m.name === name);
}

/** The selected preset's schema entry. */
export function selectedPreset() {
  return presetMachine($('machine-select').value) ?? state.schema?.machines[0];
}

/** Whether the custom machine JSON is switched on. */
export function customOn() {
  return $('machine-custom').checked;
}

/**
 * The custom machine JSON as an object; throws an Error with `.code = 'page.machine-json'`
 * when it is not a JSON object.
 */
export function customSpec() {
  let v;
  try {
    v = JSON.parse($('machine-json').value);
  } catch (e) {
    throw Object.assign(new Error(`custom machine JSON: ${e.message}`), { code: 'page.machine-json' });
  }
  if (!v || typeof v !== 'object' || Array.isArray(v)) throw Object.assign(new Error('custom machine JSON: not a JSON object'), { code: 'page.machine-json' });
  return v;
}

/** The custom machine JSON's text, as typed. */
export function customText() {
  return $('machine-json').value;
}

/**
 * Asks the core what the machine JSON `text` is (`describe_machine` in the worker) and keeps the
 * answer in `state.custom`: its schema entry, or the core's error `{code, message}` (the last
 * entry the core accepted is kept beside it). Resolves true when this is the newest request's
 * answer (an older one is dropped; one cancelled with the worker is asked again).
 */
export async function describeCustom(text) {
  const c = state.custom;
  const seq = ++c.seq;
  // The textarea holds a machine object (the core would also take a preset's name).
  const ask = !text.trim().startsWith('{')
    ? Promise.resolve({ machine: null, error: { code: 'page.machine-json', message: 'custom machine JSON: not a JSON object' } })
    : call('describe-machine', { machine: text }).then(
      ({ machine }) => ({ machine, error: null }),
      (e) => ({ machine: null, error: { code: e.code ?? null, message: e.message }, cancelled: !!e.cancelled }),
    );
  c.pending = ask;
  const r = await ask;
  if (seq !== c.seq) return false;
  c.pending = null;
  if (r.cancelled) return describeCustom(text); // the worker was stopped (Cancel): ask the fresh one
  Object.assign(c, { text, machine: r.machine, error: r.error });
  if (r.machine) c.valid = { text, machine: r.machine };
  return true;
}

/**
 * The schema entry of the machine in use: the selected preset, or the custom machine as the core
 * describes it (`custom: true`). While the core refuses the custom JSON (`customError`, its
 * `{code, message}`) or has not answered yet (`customPending`), the form goes on with the last
 * custom machine it accepted (`standIn: 'last'`) or else the selected preset (`standIn: 'preset'`).
 */
export function currentMachine() {
  const preset = selectedPreset();
  if (!customOn()) return preset;
  const c = state.custom;
  const text = customText();
  if (c.text === text && c.machine) return { ...c.machine, custom: true };
  const standIn = c.valid ? { ...c.valid.machine, custom: true, standIn: 'last' } : { ...preset, standIn: 'preset' };
  return c.text === text && c.error ? { ...standIn, customError: c.error } : { ...standIn, customPending: true };
}

/** Forgets the core's answers about the custom machine JSON (switched off): drops one on its way. */
export function forgetCustom() {
  const c = state.custom;
  clearTimeout(c.timer);
  Object.assign(c, { text: null, machine: null, error: null, valid: null, seq: c.seq + 1, pending: null, timer: 0 });
}

/**
 * The unwarp options' `machine`: the preset's name, the custom machine object, or undefined for
 * the plain 3-axis output (the preset `cartesian`, like the CLI without `--machine`).
 */
export function machineArgument() {
  if (customOn()) return customSpec();
  const p = selectedPreset();
  return p && p.name !== 'cartesian' ? p.name : undefined;
}

/** The machine argument of `machine_view`: a preset name or the machine JSON text. */
export function machineViewArgument() {
  return customOn() ? JSON.stringify(customSpec()) : selectedPreset().name;
}

/** `X 0…230 mm, Y, Z 0…210 mm, A −30…30°`: each axis' travel (describe's `min`/`max`). */
export function axesText(m) {
  const range = (a, unit) => (!a.rotary && a.min == null && a.max == null ? a.name : `${a.name} ${a.min ?? '−∞'}…${a.max ?? '∞'}${unit}`);
  return m.axes.map((a) => range(a, a.rotary ? '°' : ' mm')).join(', ');
}
