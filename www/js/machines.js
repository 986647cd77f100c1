// The machine of the form: a preset of the core's schema (`describe().machines`) or a custom
// machine JSON pasted into the textarea. Everything the page knows about a machine (its axes,
// tilt limits, the warps it can print, whether it moves its bed) comes from that schema entry.
import { state } from './state.js';
import { $ } from './dom.js';

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

/**
 * The schema entry of the machine in use. A custom machine takes its capabilities from the
 * preset of its `kind` (the selected one if it is of that kind): the core checks the machine's
 * own limits when it unwarps.
 */
export function currentMachine() {
  const preset = selectedPreset();
  if (!customOn()) return preset;
  let spec;
  try {
    spec = customSpec();
  } catch (e) {
    return { ...preset, customError: e.message };
  }
  const like = preset?.kind === spec.kind ? preset : state.schema?.machines.find((m) => m.kind === spec.kind);
  return { ...(like ?? preset), name: String(spec.name ?? 'custom'), custom: true, spec, like: like?.name ?? null };
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

/** `X, Y, Z, A −30…30°` */
export function axesText(m) {
  return m.axes.map((a) => (a.rotary ? `${a.name} ${a.min ?? '−∞'}…${a.max ?? '∞'}°` : a.name)).join(', ');
}
