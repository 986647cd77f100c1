// `warpslice check` on the page: the findings view (count, the first findings with their file
// lines; a click moves the preview to that move), the unwarp report's warnings, and the
// "Check a G-code" mode (any tool's rotary G-code, the machine of the machine form). The check
// itself runs in the worker (`check` op; after a machine unwarp the worker checks its output).
import { state } from './state.js';
import { $, el, info } from './dom.js';
import { call } from './worker-client.js';
import { clearError, showError } from './errors.js';
import { customOn, customText, currentMachine, machineViewArgument } from './machines.js';
import { refreshCustom, resetResult } from './steps.js';
import { buildToolpath, gotoPoint, setViewMode, updateMachineFrameToggle } from './preview.js';

/** Findings listed on the page (the report counts them all; the JSON download has the list). */
export const FINDINGS_SHOWN = 20;

/** One finding as a line of text (the CLI's wording). */
export function findingText(f) {
  if (f.kind === 'reach') return `line ${f.line}: reach: axis ${f.axis} = ${f.value.toFixed(3)} is beyond its limit ${f.limit}`;
  if (f.kind === 'speed') return `line ${f.line}: speed: axis ${f.axis} would move at ${f.value.toFixed(0)}/min, over its largest feed ${f.limit.toFixed(0)}/min`;
  const c = f.collision;
  return `line ${f.line}: collision: the ${c.part} goes ${c.depth_mm.toFixed(3)} mm into the ${c.obstacle === 'bed' ? 'bed' : 'printed material'}`;
}

/** The first preview point at or after file line `line` (the preview keeps file lines in check mode). */
function pointOfLine(d, line) {
  if (!d?.line) return -1;
  for (let i = 0; i < d.count; i++) if (d.line[i] >= line) return i;
  return -1;
}

/** Move the preview to point `i` of `d`, showing `d` first if another preview is shown. */
function showPoint(d, i) {
  if (state.tp.data !== d) {
    state.tp.data = d;
    state.tp.built = null;
    state.tp.firstBuild = true;
    updateMachineFrameToggle();
    setViewMode('toolpath');
    $('findings').dataset.preview = 'check';
  }
  gotoPoint(i);
}

/**
 * Shows a check report in `#findings`: the counts, the first findings (buttons moving the
 * preview to their move), the warnings. `null`: clears it. `preview`: the checked file's
 * preview (file lines, collisions flagged); when it is not the one shown (after an unwarp, whose
 * own preview has no output lines) a click switches the view to it first.
 */
export function showFindings(report, error = null, preview = state.tp.data) {
  const box = $('findings');
  box.replaceChildren();
  delete box.dataset.count;
  if (error) {
    box.append(el('p', { textContent: `check failed: ${error.message}`, dataset: { code: error.code } }));
    return;
  }
  if (!report) return;
  const c = report.counts;
  const total = c.reach + c.collision + c.speed;
  box.dataset.count = String(total);
  box.append(el('p', {
    'data-testid': 'findings-count',
    textContent: total === 0
      ? `check: no findings (reach, ${report.collisions_checked ? 'collisions' : 'collisions not checked'}, axis speeds)`
      : `check: ${total} finding${total === 1 ? '' : 's'} — ${c.reach} reach, ${c.collision} collision, ${c.speed} speed`,
  }));
  const ol = el('ol', { className: 'findings' });
  const d = preview;
  for (const f of report.findings.slice(0, FINDINGS_SHOWN)) {
    const i = pointOfLine(d, f.line);
    const text = findingText(f);
    const dataset = { line: f.line, kind: f.kind, part: f.collision?.part, obstacle: f.collision?.obstacle, axis: f.axis };
    const item = i >= 0
      ? el('button', { type: 'button', textContent: text, dataset })
      : el('span', { textContent: text, dataset });
    if (i >= 0) item.addEventListener('click', () => showPoint(d, i));
    ol.append(el('li', {}, item));
  }
  box.append(ol);
  if (total > FINDINGS_SHOWN) box.append(el('p', { className: 'muted', textContent: `… ${total - Math.min(total, report.findings.length, FINDINGS_SHOWN)} more (download the report for the list)` }));
  const dl = el('dl', { className: 'info' });
  info(dl, [
    ['estimated time', `${report.print_time_min.toFixed(1)} min (${report.slowdown_min.toFixed(1)} min axis slow-down)`],
    ['filament', `${report.total_e_mm.toFixed(2)} mm net, ${report.extruded_mm.toFixed(2)} mm extruded`],
    ['moves', `${report.moves.toLocaleString('en')} (${report.extruding_moves.toLocaleString('en')} extruding), ${report.lines.toLocaleString('en')} lines`],
    ['largest tilt', `${report.largest_tilt_deg.toFixed(2)}°`],
    ['tilt histogram', report.tilt_histogram.map((n, k) => (n ? `${k * report.tilt_bin_deg}–${(k + 1) * report.tilt_bin_deg}° ${n}` : null)).filter(Boolean).join(', ') || 'no extrusion'],
  ]);
  box.append(dl);
  for (const w of report.warnings) box.append(el('p', { className: 'warning', textContent: `warning: ${w}` }));
}

/** The unwarp report's `warnings` (truncated input, clamped points, …) in `#unwarp-warnings`. */
export function showUnwarpWarnings(report) {
  const ul = $('unwarp-warnings');
  ul.replaceChildren(...(report?.warnings ?? []).map((w) => el('li', { textContent: w })));
}

/** "Check a G-code": `file` for the machine of the machine form; the preview and the report. */
export async function doCheck(file) {
  clearError();
  resetResult();
  showFindings(null);
  showUnwarpWarnings(null);
  const text = $('check-progress');
  text.textContent = 'checking…';
  try {
    if (customOn() && (state.custom.text !== customText() || state.custom.pending || state.custom.timer)) await refreshCustom();
    const m = currentMachine();
    const out = await call('check', { file, machine: machineViewArgument() }, [], (ev) => {
      if (ev.type === 'progress') text.textContent = `checking ${Math.round((100 * ev.done) / ev.total)} %`;
    });
    text.textContent = `${file.name} checked for ${m.name} in ${(out.ms / 1000).toFixed(1)} s`;
    state.tp.data = out.preview;
    state.tp.built = null;
    state.tp.firstBuild = true;
    updateMachineFrameToggle();
    setViewMode('toolpath');
    buildToolpath();
    $('sliders').hidden = false;
    showFindings(out.report);
    $('findings').dataset.mode = 'check';
  } catch (e) {
    text.textContent = 'failed';
    if (!e.cancelled) showError(`Cannot check “${file.name}”`, e, 'check');
  }
}
