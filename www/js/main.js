// warpslice web app: the entry module. Starts the worker, builds the forms from the core's
// self-description (`describe()`), applies the settings of the URL hash and wires the page.
// The modules, by concern: state.js (the one state object), worker-client.js (RPC to
// worker.js), machines.js, params.js + forms.js (forms from the schema), settings.js (JSON and
// URL hash), steps.js (model → warp → unwarp → result), view.js (3D view), preview.js
// (toolpath preview), advice.js + errors.js (errors and what to do, by code), dom.js.
import { doSuggest, refreshOverhangs, watchFieldExpression } from './overhang.js';
import { state } from './state.js';
import { doCheck } from './check.js';
import { $ } from './dom.js';
import { call } from './worker-client.js';
import { showError } from './errors.js';
import { buildForms, buildWarpParams, enforceLimits, seedCustomJson } from './forms.js';
import { loadSettings, readSettings, saveHash, settingsFromHash } from './settings.js';
import { doUnwarp, doWarp, loadModel, onMachineChange, refreshCustom, scheduleWarp } from './steps.js';
import { initView, showModel } from './view.js';
import { buildToolpath, onLayerChange, setViewMode } from './preview.js';
import { cancelRun, doSliceHere } from './builtin.js';
import { applySlicerSettings, buildSlicerForm } from './slicer-form.js';

function dropZone(zone, input, onFile) {
  zone.addEventListener('dragover', (e) => {
    e.preventDefault();
    zone.classList.add('over');
  });
  zone.addEventListener('dragleave', () => zone.classList.remove('over'));
  zone.addEventListener('drop', (e) => {
    e.preventDefault();
    zone.classList.remove('over');
    const f = e.dataTransfer?.files?.[0];
    if (f && !input.disabled) onFile(f);
  });
  input.addEventListener('change', () => {
    const f = input.files?.[0];
    if (f) onFile(f);
    input.value = '';
  });
}

function tabs() {
  const list = [...document.querySelectorAll('[role=tab]')];
  const select = (tab) => {
    for (const t of list) {
      const on = t === tab;
      t.setAttribute('aria-selected', String(on));
      t.tabIndex = on ? 0 : -1;
      $(t.getAttribute('aria-controls')).hidden = !on;
    }
    tab.focus();
  };
  list.forEach((t, i) => {
    t.addEventListener('click', () => select(t));
    t.addEventListener('keydown', (e) => {
      if (e.key === 'ArrowRight') select(list[(i + 1) % list.length]);
      if (e.key === 'ArrowLeft') select(list[(i + list.length - 1) % list.length]);
    });
  });
}

async function main() {
  initView();
  tabs();
  const init = await call('init');
  state.schema = init.schema;
  $('version').textContent = `v${init.schema.version}`;
  buildForms();
  buildSlicerForm();
  await loadSettings(settingsFromHash() ?? {});
  onMachineChange();
  await refreshCustom();

  dropZone($('model-drop'), $('model-input'), async (f) => loadModel(new Uint8Array(await f.arrayBuffer()), f.name));
  dropZone($('gcode-drop'), $('gcode-input'), (f) => doUnwarp(f));
  dropZone($('check-drop'), $('check-input'), (f) => doCheck(f));
  $('example-select').addEventListener('change', async (e) => {
    const name = e.target.value;
    if (!name) return;
    try {
      const { stl } = await call('example', { name });
      await loadModel(new Uint8Array(stl), `${name}.stl`);
    } catch (err) {
      showError('Cannot make the example', err);
    }
  });
  $('machine-select').addEventListener('change', () => {
    onMachineChange();
    scheduleWarp();
  });
  $('warp-select').addEventListener('change', () => {
    buildWarpParams();
    scheduleWarp();
  });
  $('warp-params').addEventListener('change', scheduleWarp);
  watchFieldExpression();
  $('warp-options').addEventListener('change', scheduleWarp);
  $('unwarp-options').addEventListener('change', () => {
    enforceLimits();
    saveHash();
  });
  // The custom machine JSON: the core describes it (refreshCustom), at once when it is switched
  // on or left, 300 ms after the last keystroke while it is typed.
  $('machine-custom').addEventListener('change', () => {
    if ($('machine-custom').checked) seedCustomJson();
    onMachineChange();
    scheduleWarp();
    refreshCustom();
  });
  $('machine-json').addEventListener('input', () => {
    if ($('machine-custom').checked) refreshCustom(300);
  });
  $('machine-json').addEventListener('change', () => {
    $('machine-custom').checked = $('machine-json').value.trim() !== '';
    onMachineChange();
    saveHash();
    refreshCustom();
  });
  $('warp-button').addEventListener('click', doWarp);
  $('show-warped').addEventListener('change', showModel);
  $('show-layers').addEventListener('change', showModel);
  $('show-overhangs').addEventListener('change', showModel);
  $('show-tilt-map').addEventListener('change', showModel);
  $('overhang-angle').addEventListener('change', async () => {
    await refreshOverhangs();
    showModel();
  });
  $('suggest-button').addEventListener('click', doSuggest);
  $('cancel').addEventListener('click', cancelRun);
  $('slice-here').addEventListener('click', doSliceHere);
  $('slicer-settings').addEventListener('change', saveHash);
  // the CLI's --slicer-settings FILE: its keys over the core's defaults
  $('slicer-settings-import').addEventListener('change', async (e) => {
    const f = e.target.files?.[0];
    e.target.value = '';
    if (!f) return;
    try {
      applySlicerSettings(JSON.parse(await f.text()));
      saveHash();
    } catch (err) {
      showError('Cannot read these slicer settings', { code: 'page.settings', message: err.message });
    }
  });
  $('view-mode').addEventListener('change', (e) => setViewMode(e.target.value));
  $('color-mode').addEventListener('change', buildToolpath);
  $('show-travel').addEventListener('change', buildToolpath);
  $('machine-frame').addEventListener('change', () => {
    state.tp.built = null;
    setViewMode('toolpath');
  });
  $('layer-slider').addEventListener('input', () => onLayerChange(true));
  $('move-slider').addEventListener('input', () => onLayerChange(false));
  $('settings-export').addEventListener('click', () => {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(new Blob([JSON.stringify(readSettings(), null, 2)], { type: 'application/json' }));
    a.download = 'warpslice-settings.json';
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  });
  $('settings-import').addEventListener('change', async (e) => {
    const f = e.target.files?.[0];
    e.target.value = '';
    if (!f) return;
    try {
      await loadSettings(JSON.parse(await f.text()));
      onMachineChange();
      scheduleWarp();
      await refreshCustom();
    } catch (err) {
      showError('Cannot read these settings', { code: 'page.settings', message: err.message });
    }
  });
  $('settings-link').addEventListener('click', async () => {
    saveHash();
    try {
      await navigator.clipboard.writeText(location.href);
      $('settings-link').textContent = 'Link copied';
    } catch {
      $('settings-link').textContent = 'Link is in the address bar';
    }
    setTimeout(() => ($('settings-link').textContent = 'Copy link to these settings'), 2000);
  });
  window.addEventListener('hashchange', async () => {
    const s = settingsFromHash();
    if (s) {
      await loadSettings(s);
      onMachineChange();
      scheduleWarp();
      await refreshCustom();
    }
  });
  document.body.dataset.ready = '1';
  // Offline support where service workers are allowed (https, or http://localhost); the tests
  // use 127.0.0.1 and so run without it.
  if ('serviceWorker' in navigator && (location.protocol === 'https:' || location.hostname === 'localhost')) {
    navigator.serviceWorker.register('./sw.js').catch(() => {});
  }
}

main().catch((e) => showError('The app could not start', e));
