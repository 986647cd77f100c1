// The steps of the page, as the pipeline runs: 1 the model, 2 the machine and the warp,
// 4 the G-code back (unwarp), 5 the result and its summary. Each step resets what depends on it.
import { refreshOverhangs } from './overhang.js';
import { clearHead } from './head.js';
import { state } from './state.js';
import { showFindings, showUnwarpWarnings } from './check.js';
import { $, baseName, box3, el, info, setDownload, setLazyDownload } from './dom.js';
import { call } from './worker-client.js';
import { clearError, showError } from './errors.js';
import { cliArgs, commandLine, readSettings, saveHash, unwarpOptions, warpOptions } from './settings.js';
import { slicerCliArgs, slicerSettings } from './slicer-form.js';
import { buildWarpParams, enforceLimits, showMachine } from './forms.js';
import { currentMachine, customOn, customSpec, customText, describeCustom, forgetCustom, machineViewArgument } from './machines.js';
import { clearGroup, showModel, SURFACE_GRID } from './view.js';
import { setViewMode, updateMachineFrameToggle } from './preview.js';

const tp = state.tp;

// Step 1: the model.
export async function loadModel(bytes, name) {
  clearError();
  resetWarp();
  state.stl = null;
  state.modelReport = null;
  state.stlName = name;
  $('model-info').replaceChildren();
  $('warp-button').disabled = true;
  try {
    const { report } = await call('inspect', { stl: bytes.buffer.slice(0) });
    state.stl = bytes;
    state.modelReport = { ...report, bbox: box3(report.bbox) };
  } catch (e) {
    showError(`Cannot read “${name}”`, e, 'mesh');
    showModel();
    return;
  }
  const r = state.modelReport;
  const size = ['x', 'y', 'z'].map((k) => (r.bbox.max[k] - r.bbox.min[k]).toFixed(2)).join(' × ');
  const defects = [];
  for (const [k, label] of [['open_edges', 'open edges'], ['nonmanifold_edges', 'non-manifold edges'], ['degenerate', 'degenerate triangles'], ['zero_normals', 'zero normals'], ['flipped_normals', 'flipped normals']]) {
    if (r[k]) defects.push(`${r[k]} ${label}`);
  }
  info($('model-info'), [
    ['file', name],
    ['format', String(r.format)],
    ['size', `${size} mm`],
    ['triangles', r.triangles.toLocaleString('en')],
    ['defects', defects.length ? defects.join(', ') : 'none'],
    ...(r.warnings?.length ? [['warnings', r.warnings.join('; ')]] : []),
  ]);
  $('model-info').dataset.triangles = String(r.triangles);
  $('warp-button').disabled = false;
  $('suggest-button').disabled = false;
  setViewMode('model');
  showModel();
  await doWarp();
}


// Step 2: the machine and the warp.
export function resetWarp() {
  state.warped = null;
  setDownload('warped-download', null);
  setDownload('job-download', null);
  $('warp-info').replaceChildren();
  showWarpWarnings(null);
  $('gcode-input').disabled = true;
  $('slice-here').disabled = true;
  resetResult();
  showWarnings();
}

export function resetResult() {
  state.result = null;
  tp.data = null;
  tp.built = null;
  clearGroup(state.view.pathGroup);
  clearHead();
  setDownload('result-download', null);
  setDownload('summary-download', null);
  setDownload('config-download', null);
  setDownload('sliced-download', null);
  $('summary').replaceChildren();
  showFindings(null);
  showUnwarpWarnings(null);
  delete $('findings').dataset.mode;
  delete $('findings').dataset.preview;
  $('progress').value = 0;
  $('progress-text').textContent = '';
  $('sliders').hidden = true;
  $('canvas-wrap').removeAttribute('data-drawn');
  updateMachineFrameToggle();
}

export async function doWarp() {
  if (!state.stl) return;
  enforceLimits();
  saveHash();
  clearError();
  const seq = ++state.warpSeq;
  resetWarp();
  $('warp-button').disabled = true;
  $('warp-info').textContent = 'warping…';
  showWarpWarnings(null);
  try {
    const cli = ['warpslice', 'warp', state.stlName, ...cliArgs().warp, '-o', `${baseName(state.stlName)}.warped.stl`];
    const out = await call('warp', { stl: state.stl.buffer.slice(0), options: warpOptions(), every: 5, grid: SURFACE_GRID });
    if (seq !== state.warpSeq) return;
    out.report.warped_bbox = box3(out.report.warped_bbox);
    state.warped = out;
    const r = out.report;
    const wb = r.warped_bbox;
    const dl = document.createElement('dl');
    dl.className = 'info';
    info(dl, [
      ['warped size', ['x', 'y', 'z'].map((k) => (wb.max[k] - wb.min[k]).toFixed(2)).join(' × ') + ' mm'],
      ['triangles out', r.triangles_out.toLocaleString('en')],
      ['largest tilt', `${r.largest_tilt_deg.toFixed(2)}°`],
      ['anchor slab', r.anchor != null ? `${r.anchor} mm (first layer, dropped by unwarp)` : 'none (flat bottom)'],
      ['command line', commandLine(cli)],
    ]);
    $('warp-info').replaceChildren(dl);
    $('warp-info').dataset.largestTilt = String(r.largest_tilt_deg);
    showWarpWarnings(r);
    const name = baseName(state.stlName);
    setDownload('warped-download', new Blob([out.stl], { type: 'model/stl' }), `${name}.warped.stl`);
    setDownload('job-download', new Blob([out.job], { type: 'application/json' }), `${name}.warped.job.json`);
    $('gcode-input').disabled = false;
    $('slice-here').disabled = false;
  } catch (e) {
    if (seq !== state.warpSeq) return;
    $('warp-info').textContent = '';
    if (!e.cancelled) showError('Cannot warp this model', e, 'warp');
  } finally {
    if (seq === state.warpSeq) $('warp-button').disabled = !state.stl;
  }
  showWarnings();
  showModel();
  await refreshOverhangs();
  showModel();
}

/**
 * The warp report's `warnings` (what the STL reader tolerated in the model, a capped
 * subdivision), one item each, as the CLI prints them after `warning: `. `null` clears them.
 */
function showWarpWarnings(report) {
  $('warp-warnings').replaceChildren(...(report?.warnings ?? []).map((w) => {
    const li = document.createElement('li');
    li.textContent = w;
    return li;
  }));
}

/** The warp against the machine: its tilt limit or fixed tilt, a 3-axis machine's vertical nozzle. */
export function showWarnings() {
  const ul = $('warnings');
  ul.replaceChildren();
  const m = currentMachine();
  const w = state.warped;
  if (!m || !w) return;
  const add = (text, ok = false) => {
    const li = document.createElement('li');
    li.textContent = text;
    if (ok) li.className = 'ok';
    ul.append(li);
  };
  const tilt = w.report.largest_tilt_deg;
  if (m.max_tilt_deg != null && tilt > m.max_tilt_deg + 1e-6) add(`The layers need up to ${tilt.toFixed(1)}° of tilt; ${m.name} reaches ${m.max_tilt_deg}°: lower the warp.`);
  if (m.fixed_tilt_deg != null && Math.abs(tilt - m.fixed_tilt_deg) > 0.5 && tilt > 0) add(`${m.name} holds the nozzle at ${m.fixed_tilt_deg}°; these layers need ${tilt.toFixed(1)}°.`);
  if (!m.axes.some((a) => a.rotary) && tilt > 0) add(`3-axis: the nozzle stays vertical while the layers slope up to ${tilt.toFixed(1)}°; make sure the nozzle cone clears that slope.`);
  if (!ul.children.length) add(`Within ${m.name}'s tilt limits (largest tilt ${tilt.toFixed(1)}°); the axis ranges are checked when unwarping.`, true);
}

/** A machine or custom machine JSON was chosen: its info, the warps it prints, its limits. */
export function onMachineChange() {
  if (showMachine()) buildWarpParams();
  else enforceLimits();
  showWarnings();
  updateMachineFrameToggle();
}

/**
 * The custom machine JSON was switched on or off, edited (`delay` ms of quiet first, while
 * typing) or loaded from settings: asks the core what machine it is (`describe_machine`) and
 * shows it (its warps, its tilt limits in the form, the warnings), or shows the core's refusal
 * with the advice for its code; the form then goes on with the last custom machine the core
 * accepted, or the selected preset. Re-warps when the machine changed the warp (a tilt clamped,
 * a warp it does not print). Resolves once the answer is shown (or dropped for a newer one).
 */
export async function refreshCustom(delay = 0) {
  const c = state.custom;
  clearTimeout(c.timer);
  c.timer = 0;
  if (!customOn()) {
    forgetCustom();
    clearError('custom-machine');
    return;
  }
  if (delay > 0) {
    c.timer = setTimeout(() => refreshCustom(0), delay);
    return;
  }
  const text = customText();
  const answered = c.text === text && !c.pending;
  if (!answered && !(await describeCustom(text))) return;
  if (!customOn() || customText() !== text) return; // changed meanwhile: its own refresh follows
  const before = JSON.stringify(readSettings().warp);
  onMachineChange();
  if (c.error) showError('The core refuses this custom machine JSON', c.error, 'machine', 'custom-machine');
  else clearError('custom-machine');
  if (JSON.stringify(readSettings().warp) !== before) scheduleWarp();
  else saveHash();
}

/** Re-warps 400 ms after the last change of the form. */
export function scheduleWarp() {
  enforceLimits();
  saveHash();
  clearTimeout(state.warpTimer);
  if (state.stl) state.warpTimer = setTimeout(doWarp, 400);
}

// Step 4: the G-code back.
export async function doUnwarp(file) {
  return runToResult({
    file,
    what: `unwarp “${file.name}”`,
    request: (args, onEvent) => call('unwarp', { file, ...args }, [], onEvent),
    again: () => doUnwarp(file),
  });
}

/**
 * A run that ends in a machine G-code (step 4's unwarp of a dropped file, or step 3's built-in
 * slice + unwarp, `builtin.js`): `request(args, onEvent)` calls the worker with the job, the
 * warped STL, the unwarp options and the machine frame in `args`; its progress drives the bar
 * (phases `slice`, `scan`, `unwarp`); a `sliced` event names the planar G-code (`file` until
 * then); `onEvent` also gets every event. Then the result: downloads, summary, preview, checks.
 * `again()` runs it once more (the collision refusal's "write anyway").
 */
export async function runToResult({ file = null, what, request, again, onEvent = null }) {
  if (!state.warped) {
    showError('Warp a model first', { code: 'page.no-warp', message: 'The G-code is unwarped with the job of the warped model (steps 1–2).' });
    return;
  }
  clearError();
  resetResult();
  saveHash();
  state.busy = true;
  $('cancel').disabled = false;
  $('gcode-input').disabled = true;
  $('slice-here').disabled = true;
  const prog = $('progress');
  const text = $('progress-text');
  prog.removeAttribute('data-done');
  prog.removeAttribute('data-cancelled');
  prog.removeAttribute('data-step');
  prog.removeAttribute('data-worker-bytes');
  for (const k of ['idle-bytes', 'unwarp-ms', 'check-ms']) prog.removeAttribute(`data-${k}`);
  text.textContent = 'reading…';
  const t0 = performance.now();
  try {
    // The machine of this unwarp as the core describes the JSON sent (an edit may be unanswered).
    if (customOn() && (state.custom.text !== customText() || state.custom.pending || state.custom.timer)) await refreshCustom();
    const m = currentMachine();
    const options = unwarpOptions();
    const machineFrame = m.moving_bed ? { machine: machineViewArgument(), name: m.name } : null;
    const args = { job: state.warped.job, warpedStl: state.warped.stl, options, machineFrame };
    let sliced = null;
    const out = await request(args, (ev) => {
      onEvent?.(ev);
      if (ev.type === 'sliced') {
        file = ev.sliced;
        sliced = { report: ev.report, ms: ev.ms };
      }
      if (ev.type === 'progress') {
        prog.value = ev.done / ev.total;
        prog.dataset.phase = ev.phase;
        prog.dataset.step = `${ev.done}/${ev.total}`;
        prog.dataset.workerBytes = String(Math.max(Number(prog.dataset.workerBytes || 0), ev.workerBytes || 0));
        // the slice: `layers` cuts, then `layers` layers written (two steps per layer)
        const slicing = ev.done <= ev.layers ? `slicing: cut layer ${ev.done} of ${ev.layers}` : `slicing: wrote layer ${ev.done - ev.layers} of ${ev.layers}`;
        text.textContent = ev.phase === 'slice' ? slicing
          : `${ev.phase === 'scan' ? 'finding the part' : 'unwarping'} ${Math.round((100 * ev.done) / ev.total)} %`;
      }
    });
    prog.value = 1;
    const secs = (performance.now() - t0) / 1000;
    text.textContent = `done in ${secs.toFixed(1)} s`;
    prog.dataset.done = '1';
    prog.dataset.ms = String(Math.round(performance.now() - t0));
    // the worker's figures (the page's web tier prints them): its memory at the end and idle,
    // the unwarp's and its check's times
    if (out.workerBytes) prog.dataset.workerBytes = String(Math.max(Number(prog.dataset.workerBytes || 0), out.workerBytes));
    for (const k of ['idleBytes', 'unwarpMs', 'checkMs']) if (out[k] !== undefined) prog.dataset[k] = String(Math.round(out[k]));
    state.result = out;
    // the job of this run (a change of the form meanwhile re-warps: state.warped is the new one)
    out.job = args.job;
    if (sliced) out.sliced = sliced;
    const name = baseName(file.name);
    // the built-in slicer's planar G-code (the CLI's `run --keep-sliced`)
    setDownload('sliced-download', sliced ? file : null, file.name);
    setDownload('result-download', out.blob, `${name}.${m.name}.gcode`);
    if (out.config) {
      // the firmware configuration the G-code needs, ready to paste (the CLI's --config-out)
      setDownload('config-download', new Blob([out.config.text], { type: 'text/plain' }), `${name}.${m.name}.${out.config.flavour}.${out.config.file}.txt`);
    }
    const summary = makeSummary(out, file);
    setLazyDownload('summary-download', () => summaryBlob(summary, out.lists), `${name}.summary.json`);
    info($('summary'), Object.entries(summary.display));
    showUnwarpWarnings(out.report);
    tp.data = out.preview;
    tp.built = null;
    tp.firstBuild = true;
    updateMachineFrameToggle();
    const tv = performance.now();
    setViewMode('toolpath');
    $('sliders').hidden = false;
    // the worker's `warpslice check` of the machine file (its output lines)
    showFindings(out.check, out.checkError, out.checkPreview);
    if (out.check) $('findings').dataset.mode = 'unwarp';
    prog.dataset.viewMs = String(Math.round(performance.now() - tv));
    prog.dataset.afterMs = String(Math.round(performance.now() - t0) - Number(prog.dataset.ms));
  } catch (e) {
    prog.value = 0;
    if (e.cancelled) {
      text.textContent = 'cancelled';
      prog.dataset.cancelled = '1';
    } else {
      text.textContent = 'failed';
      setViewMode('model');
      showError(`Cannot ${what}`, e, 'unwarp');
      if (e.code === 'machine.collision') offerAllowCollisions(again);
    }
  } finally {
    state.busy = false;
    $('cancel').disabled = true;
    $('gcode-input').disabled = !state.warped;
    $('slice-here').disabled = !state.warped;
  }
}

/**
 * Under a collision refusal (`machine.collision`, the check on by default): a button that
 * writes the file anyway and lists every finding — the "Allow collisions" option
 * (`--allow-collisions`) switched on, and the unwarp run again.
 */
function offerAllowCollisions(again) {
  const allow = document.querySelector('input[data-param="allow_collisions"]');
  if (!allow) return;
  const button = el('button', { type: 'button', textContent: 'Write anyway, list findings', 'data-testid': 'allow-collisions-retry' });
  button.addEventListener('click', () => {
    allow.checked = true;
    allow.dispatchEvent(new Event('change', { bubbles: true }));
    again();
  });
  $('error').append(el('div', {}, button));
}

/**
 * The summary's JSON text (2-space indent) as a Blob. `lists`: the worker's JSON text of the
 * whole report and check when the page got their findings lists cut (worker.js `pageLists`),
 * put in place of the page's cut copies without parsing them here.
 */
function summaryBlob(summary, lists) {
  const type = { type: 'application/json' };
  const keys = ['report', 'check'].filter((k) => lists?.[k] && summary[k] !== undefined);
  if (!keys.length) return new Blob([JSON.stringify(summary, null, 2)], type);
  const marked = { ...summary };
  for (const k of keys) marked[k] = `\u0000${k}\u0000`;
  const text = JSON.stringify(marked, null, 2);
  const at = keys.map((k) => [text.indexOf(JSON.stringify(marked[k])), k]).sort((a, b) => a[0] - b[0]);
  const parts = [];
  let from = 0;
  for (const [i, k] of at) {
    parts.push(text.slice(from, i), lists[k]);
    from = i + JSON.stringify(marked[k]).length;
  }
  parts.push(text.slice(from));
  return new Blob(parts, type);
}

export function makeSummary(out, file) {
  const r = out.report;
  const d = out.preview;
  // Print length: the sum of extruding segment lengths in the (possibly decimated) preview.
  let printLen = 0;
  for (let i = 1; i < d.count; i++) {
    if (d.flags[i] & 0x80 || d.layer[i] !== d.layer[i - 1]) continue;
    printLen += Math.hypot(d.pos[i * 3] - d.pos[i * 3 - 3], d.pos[i * 3 + 1] - d.pos[i * 3 - 2], d.pos[i * 3 + 2] - d.pos[i * 3 - 1]);
  }
  const s = readSettings();
  const base = baseName(state.stlName);
  const m = currentMachine();
  const cli = cliArgs();
  const cliWarp = ['warpslice', 'warp', state.stlName, ...cli.warp, '-o', `${base}.warped.stl`];
  const cliUnwarp = ['warpslice', 'unwarp', file.name, '--job', `${base}.warped.job.json`, '--stl', `${base}.warped.stl`, ...cli.unwarp, '-o', `${baseName(file.name)}.${m.name}.gcode`];
  // sliced here: the one command that warps, slices with the built-in slicer and unwarps
  const cliRun = out.sliced ? ['warpslice', 'run', state.stlName, '--slicer', 'builtin', ...slicerCliArgs(), ...cli.warp, ...cli.unwarp, '-o', `${base}.${m.name}.gcode`] : undefined;
  const sr = out.sliced?.report;
  return {
    machine: s.machine,
    machine_json: customOn() ? customSpec() : undefined,
    settings: s,
    cli: { warp: cliWarp, unwarp: cliUnwarp, run: cliRun },
    slicer: out.sliced ? { settings: slicerSettings(), report: sr, ms: out.sliced.ms } : undefined,
    machine_output: r.machine ? `${r.machine.machine} (${r.machine.flavour})` : '3-axis',
    warp: JSON.parse(out.job).warp,
    gcode_in: file.name,
    bytes_in: file.size,
    bytes_out: out.bytes,
    report: r,
    check: out.check ?? undefined,
    print_length_mm: d.stride === 1 ? printLen : null,
    worst_interpolation_error_mm: r.machine ? r.machine.worst_position_mm : null,
    display: {
      machine: r.machine ? `${r.machine.machine}, ${r.machine.flavour}, feed ${r.machine.feed}` : `${s.machine} (3-axis)`,
      warp: `${s.warp.kind}`,
      lines: `${r.lines_in.toLocaleString('en')} in → ${r.lines_out.toLocaleString('en')} out`,
      E: `${r.e_in.toFixed(1)} mm in → ${r.e_out.toFixed(1)} mm out (anchor ${r.e_anchor.toFixed(1)}, skirt ${r.e_skirt.toFixed(1)} ${r.skirt})`,
      'print length': d.stride === 1 ? `${(printLen / 1000).toFixed(2)} m` : `preview decimated 1:${d.stride}`,
      'largest tilt': `${r.largest_tilt_deg.toFixed(2)}°`,
      'worst interpolation error': r.machine
        ? `${r.machine.worst_position_mm.toFixed(4)} mm, ${r.machine.worst_angle_deg.toFixed(3)}°`
        : 'none (3-axis: straight moves)',
      placement: `offset ${r.translation.map((v) => v.toFixed(2)).join(', ')} mm, residual ${r.residual.toExponential(2)}`,
      'output size': `${(out.bytes / 1e6).toFixed(2)} MB`,
      ...(sr ? { 'sliced here': `${sr.layers} layers, ${sr.volume_mm3.toFixed(1)} mm³ in ${sr.filament_mm.toFixed(1)} mm of filament, ${sr.retractions} retractions${sr.repaired_loops + sr.dropped_chains ? `; repairs: ${sr.repaired_loops} open cross-sections closed, ${sr.dropped_chains} left out` : ''}${sr.thin_walls + sr.thin_unprinted ? `; thin walls: ${sr.thin_walls} lines, ${sr.thin_wall_mm.toFixed(1)} mm (${sr.thin_unprinted} thin parts too narrow, left out)` : ''} (${(out.sliced.ms / 1000).toFixed(1)} s)` } : {}),
      'command line': cliRun ? commandLine(cliRun) : `${commandLine(cliWarp)}; (slice); ${commandLine(cliUnwarp)}`,
    },
  };
}

