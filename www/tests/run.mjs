// End-to-end tests of the web app in a real browser (Debian chromium via playwright-core).
//
//   node www/tests/run.mjs            # everything (needs www/pkg, www/vendor, the CLI, prusa-slicer)
//   WARPSLICE_WEB_BIG=0 node ...      # skip the 100 MB G-code test
//   WARPSLICE_WEB_GREP=100 node ...   # only the tests whose name contains '100' ('a|b': either)
//   WARPSLICE_ALLOW_SKIP=1 node ...   # a missing corpus is skipped (printed) instead of failing
//   WARPSLICE_CLI=path node ...       # compare with this CLI binary (built from the same tree as
//                                     # www/pkg) instead of building $CARGO_TARGET_DIR/release/warpslice
//
// Serves www/ on 127.0.0.1, drives the page, slices the downloaded warped STL with prusa-slicer,
// and checks the browser's output is byte-identical to the CLI's for the same settings.
// The service worker registers only on https / localhost: its test (tests/offline.mjs) serves
// on http://localhost in a browser of its own, then stops that server and works offline.
// Screenshots go to artifacts/web/. Prints `N passed, N failed`; exits non-zero on failure.
import { chromium } from 'playwright-core';
import { execFileSync, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { createHash } from 'node:crypto';
import { startServer } from '../scripts/serve.mjs';
import { offlineRoundTrip, offlineTeacherLink } from './offline.mjs';
import { builtinTests } from './builtin.mjs';
import { suggestTests } from './suggest.mjs';
import { assertHeadAtMove, drawnHead, headTests, selectMachineSettled, AXIS_DEG, TIP_MM } from './head.mjs';

const WWW = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const ROOT = resolve(WWW, '..');
const ART = join(ROOT, 'artifacts', 'web');
const CORPUS = resolve(ROOT, '..', 'shared', 'corpus', 'stl');
const SLICE = resolve(ROOT, '..', 'shared', 'tools', 'slice.sh');
const TARGET = process.env.CARGO_TARGET_DIR ? resolve(process.env.CARGO_TARGET_DIR) : join(ROOT, 'target');
const CLI = process.env.WARPSLICE_CLI ? resolve(process.env.WARPSLICE_CLI) : join(TARGET, 'release', 'warpslice');
const BIG = process.env.WARPSLICE_WEB_BIG !== '0';
/** The 100 MB G-code's 5-axis run (pax-5axis, every collision listed: about 3 min of browser and CLI on the 2-core CI machine) joins the 3-axis one with the full product (`WARPSLICE_FULL_MATRIX=1`) or `WARPSLICE_WEB_BIG_5AXIS=1`; otherwise it says it is skipped. */
const BIG_5AXIS = process.env.WARPSLICE_FULL_MATRIX === '1' || process.env.WARPSLICE_WEB_BIG_5AXIS === '1';
/** Issue 13: the worker's memory (wasm linear memory + preview buffers) at most this above the wasm module's idle size for the 100 MB G-code's 3-axis unwarp, bytes. */
const WORKER_ABOVE_IDLE_MAX = 64 * 2 ** 20;
const TMP = mkdtempSync(join(tmpdir(), 'warpslice-web-'));
mkdirSync(ART, { recursive: true });
for (const f of readdirSync(ART)) if (f.endsWith('.png')) rmSync(join(ART, f)); // this run's screenshots only

let passed = 0, failed = 0;
const t0all = Date.now();
// run only the tests whose name contains this (`a|b`: either)
const GREP = process.env.WARPSLICE_WEB_GREP?.split('|');
async function test(name, fn) {
  if (GREP && !GREP.some((g) => name.includes(g)) && !name.startsWith('page loads')) return;
  const t0 = Date.now();
  try {
    await fn();
    passed++;
    console.log(`ok   ${name} (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
  } catch (e) {
    failed++;
    console.log(`FAIL ${name}: ${e.stack || e}`);
  }
}
function assert(cond, msg) {
  if (!cond) throw new Error(`assertion failed: ${msg}`);
}
function sha(buf) {
  return createHash('sha256').update(buf).digest('hex').slice(0, 16);
}
function sh(cmd, args, opts = {}) {
  return execFileSync(cmd, args, { stdio: ['ignore', 'pipe', 'pipe'], maxBuffer: 1 << 26, ...opts }).toString();
}
function cliWarp(stl, out, warpArgs) {
  sh(CLI, ['warp', stl, ...warpArgs, '-o', out]);
}
function slice(stl, gcode) {
  sh('bash', [SLICE, 'prusaslicer', 'rel', stl, gcode]);
}

// --- prerequisites ------------------------------------------------------------------------------
for (const [what, p, fix] of [
  ['wasm package', join(WWW, 'pkg', 'warpslice_bg.wasm'), 'wasm-pack build --release --target web --out-dir www/pkg'],
  ['three.js vendor copy', join(WWW, 'vendor', 'three.module.js'), '(cd www && npm ci)'],
  ['chromium', '/usr/bin/chromium', 'apt-get install -y chromium chromium-driver'],
  ['slice.sh', SLICE, 'the shared tools folder ../shared/tools'],
]) {
  if (!existsSync(p)) {
    console.log(`missing ${what} (${p}): run ${fix}`);
    console.log('0 passed, 1 failed');
    process.exit(1);
  }
}
// The CLI the browser is compared with: built from the same tree as www/pkg (a no-op when fresh).
if (process.env.WARPSLICE_CLI) {
  console.log(`the CLI: ${CLI} (WARPSLICE_CLI)`);
  if (!existsSync(CLI)) {
    console.log(`missing CLI ${CLI}`);
    console.log('0 passed, 1 failed');
    process.exit(1);
  }
} else {
  console.log(`building the CLI (${CLI})`);
  // with the hand-built cases' writer (tests/head.mjs runs it): one build, so the library is
  // compiled once for both (an example's dev-dependencies change the features it is built with)
  execFileSync('cargo', ['build', '--release', '--bin', 'warpslice', '--example', 'finding_cases'], { cwd: ROOT, stdio: 'inherit' });
}

// The generated example, written by the same wasm (node), so the CLI can warp the same bytes.
const wasm = await import(join(WWW, 'pkg', 'warpslice.js'));
await wasm.default({ module_or_path: readFileSync(join(WWW, 'pkg', 'warpslice_bg.wasm')) });
// The core's self-description, which the page's forms and advice are built from.
const schema = JSON.parse(wasm.describe());
const presetNames = schema.machines.map((p) => p.name);

// --- browser --------------------------------------------------------------------------------------
const { server, url } = await startServer(WWW, 0);
const profile = mkdtempSync(join(tmpdir(), 'warpslice-chromium-'));
const context = await chromium.launchPersistentContext(profile, {
  executablePath: '/usr/bin/chromium',
  headless: true,
  acceptDownloads: true,
  viewport: { width: 1280, height: 720 },
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--no-first-run', '--disable-quic', '--enable-precise-memory-info'],
});
const outside = [];
context.on('request', (r) => {
  const u = new URL(r.url());
  if (['blob:', 'data:'].includes(u.protocol)) return;
  if (u.hostname !== '127.0.0.1') outside.push(r.url());
});
const page = context.pages()[0] ?? (await context.newPage());
const consoleErrors = [];
page.on('console', (m) => {
  if (m.type() === 'error') consoleErrors.push(m.text());
});
page.on('pageerror', (e) => consoleErrors.push(`pageerror: ${e.message}`));
let shot = 0;
async function screenshot(name) {
  shot++;
  await page.screenshot({ path: join(ART, `${String(shot).padStart(2, '0')}-${name}.png`) });
}
const tid = (id) => page.locator(`[data-testid="${id}"]`);

async function download(testid, dest) {
  const [dl] = await Promise.all([page.waitForEvent('download'), tid(testid).click()]);
  await dl.saveAs(dest);
  return readFileSync(dest);
}
/** Waits until the warp for the current form settled (warped download enabled, not warping). */
async function warpSettled() {
  await page.waitForFunction(() => {
    const a = document.querySelector('[data-testid="warped-download"]');
    return a && !a.classList.contains('disabled') && document.getElementById('warp-info').textContent !== 'warping…';
  }, null, { timeout: 120000 });
  await page.waitForTimeout(450); // a debounced re-warp (400 ms) may still be scheduled
  await page.waitForFunction(() => !document.querySelector('[data-testid="warped-download"]').classList.contains('disabled'), null, { timeout: 120000 });
}
async function setConic(angle) {
  await tid('machine-select').selectOption('cartesian');
  await tid('warp-select').selectOption('conic');
  await page.locator('#p-conic-angle').fill(String(angle));
  await page.locator('#p-conic-angle').dispatchEvent('change');
  await page.locator('#p-conic-direction').selectOption('outward');
  await warpSettled();
}
async function unwarpInBrowser(gcodePath) {
  await tid('gcode-input').setInputFiles(gcodePath);
  await page.waitForFunction(() => {
    const p = document.querySelector('[data-testid="progress"]');
    const err = document.querySelector('[data-testid="error"]');
    return p.dataset.done === '1' || !err.hidden;
  }, null, { timeout: 600000 });
  const err = await tid('error');
  if (await err.isVisible()) throw new Error(`the page showed an error: ${await err.innerText()}`);
}

/** Full round trip for one model; compares every artifact with the CLI's. */
async function roundTrip(label, stlPath, angle) {
  const dir = join(TMP, label);
  mkdirSync(dir, { recursive: true });
  await setConic(angle);
  await screenshot(`${label}-warped`);
  const wStl = await download('warped-download', join(dir, 'W.stl'));
  const wJob = await download('job-download', join(dir, 'W.job.json'));
  cliWarp(stlPath, join(dir, 'C.stl'), ['--warp', 'conic', '--angle', String(angle), '--direction', 'outward']);
  const cStl = readFileSync(join(dir, 'C.stl'));
  assert(sha(wStl) === sha(cStl), `${label}: warped STL differs from the CLI's (${wStl.length} vs ${cStl.length} bytes)`);
  assert(JSON.stringify(JSON.parse(wJob)) === JSON.stringify(JSON.parse(readFileSync(join(dir, 'C.job.json')))), `${label}: job differs from the CLI's`);
  slice(join(dir, 'W.stl'), join(dir, 'W.gcode'));
  // The page registers to the bead with the warped STL it holds: the CLI's --stl.
  sh(CLI, ['unwarp', join(dir, 'W.gcode'), '--job', join(dir, 'C.job.json'), '--stl', join(dir, 'C.stl'), '-o', join(dir, 'C.out.gcode')]);
  await unwarpInBrowser(join(dir, 'W.gcode'));
  await screenshot(`${label}-toolpath`);
  const out = await download('result-download', join(dir, 'B.out.gcode'));
  const cli = readFileSync(join(dir, 'C.out.gcode'));
  assert(out.length === cli.length && out.equals(cli), `${label}: browser G-code (${out.length} B, ${sha(out)}) is not byte-identical to the CLI's (${cli.length} B, ${sha(cli)})`);
  return dir;
}

/**
 * One model through the page (the form as `setForm` leaves it) and through the CLI (`warpArgs`,
 * `unwarpArgs`): the warped STL, the job and the output G-code must be byte-identical.
 */
async function pageVsCli(label, stlPath, setForm, warpArgs, unwarpArgs = []) {
  const dir = join(TMP, label);
  mkdirSync(dir, { recursive: true });
  await tid('model-input').setInputFiles(stlPath);
  await warpSettled();
  await setForm();
  await warpSettled();
  await screenshot(`${label}-warped`);
  const wStl = await download('warped-download', join(dir, 'W.stl'));
  const wJob = await download('job-download', join(dir, 'W.job.json'));
  cliWarp(stlPath, join(dir, 'C.stl'), warpArgs);
  const cStl = readFileSync(join(dir, 'C.stl'));
  assert(wStl.equals(cStl), `${label}: warped STL (${wStl.length} B, ${sha(wStl)}) differs from the CLI's (${cStl.length} B, ${sha(cStl)}) for ${warpArgs.join(' ')}`);
  assert(JSON.stringify(JSON.parse(wJob)) === JSON.stringify(JSON.parse(readFileSync(join(dir, 'C.job.json')))), `${label}: job differs from the CLI's`);
  slice(join(dir, 'W.stl'), join(dir, 'W.gcode'));
  // a machine's output: the CLI's --config-out too (not a flag of the page's command line)
  const machine = unwarpArgs.includes('--machine');
  const configOut = machine ? ['--config-out', join(dir, 'C.cfg')] : [];
  sh(CLI, ['unwarp', join(dir, 'W.gcode'), '--job', join(dir, 'C.job.json'), '--stl', join(dir, 'C.stl'), ...unwarpArgs, ...configOut, '-o', join(dir, 'C.out.gcode')]);
  await unwarpInBrowser(join(dir, 'W.gcode'));
  await screenshot(`${label}-toolpath`);
  const out = await download('result-download', join(dir, 'B.out.gcode'));
  const cli = readFileSync(join(dir, 'C.out.gcode'));
  assert(out.equals(cli), `${label}: browser G-code (${out.length} B, ${sha(out)}) is not byte-identical to the CLI's (${cli.length} B, ${sha(cli)}) for unwarp ${unwarpArgs.join(' ')}`);
  if (machine) {
    // the page's second download is the CLI's --config-out, byte for byte
    const cfg = await download('config-download', join(dir, 'B.cfg'));
    assert(cfg.equals(readFileSync(join(dir, 'C.cfg'))), `${label}: the page's firmware configuration differs from the CLI's --config-out`);
  } else {
    assert(await page.locator('[data-testid="config-download"].disabled').count() === 1, `${label}: a 3-axis result offers no firmware configuration`);
  }
  // The page's own command lines (summary) are the ones just run, up to file names.
  const summary = JSON.parse(await download('summary-download', join(dir, 'summary.json')));
  const flags = (args) => {
    const m = {};
    for (let i = 0; i < args.length; i++) {
      if (!args[i].startsWith('--')) continue;
      const v = args[i + 1] !== undefined && !args[i + 1].startsWith('--') ? args[++i] : true;
      m[args[i - (v === true ? 0 : 1)]] = typeof v === 'string' && v.includes('/') ? basename(v) : v;
    }
    return JSON.stringify(Object.entries(m).sort());
  };
  assert(summary.cli.unwarp[5] === '--stl', `${label}: the page's unwarp command line gives the warped STL: ${summary.cli.unwarp.join(' ')}`);
  const pageWarp = summary.cli.warp.slice(3, -2), pageUnwarp = summary.cli.unwarp.slice(7, -2);
  assert(flags(pageWarp) === flags(warpArgs), `${label}: the page's warp command line ${pageWarp.join(' ')} is the CLI's ${warpArgs.join(' ')}`);
  assert(flags(pageUnwarp) === flags(unwarpArgs), `${label}: the page's unwarp command line ${pageUnwarp.join(' ')} is the CLI's ${unwarpArgs.join(' ')}`);
  return { dir, out };
}

/**
 * The form of page `pg` for the machine in use there, `m` (a `describe().machines` entry): the
 * warps it prints are the ones offered, its tilt limit caps every degree parameter (the layer
 * tilt; a value past it is clamped to it) and a fixed tilt is fixed.
 */
async function machineForm(pg, m) {
  const offered = await pg.locator('[data-testid="warp-select"] option:not([disabled])').evaluateAll((os) => os.map((o) => o.value));
  assert(JSON.stringify(offered) === JSON.stringify(schema.warps.map((w) => w.name).filter((w) => m.warps.includes(w))), `${m.name}: warps offered ${offered} ≠ its warps ${m.warps}`);
  assert((await pg.locator('[data-testid="machine-info"]').innerText()).includes(m.name), `${m.name}: named in the machine info`);
  for (const w of schema.warps.filter((x) => m.warps.includes(x.name))) {
    await pg.locator('[data-testid="warp-select"]').selectOption(w.name);
    for (const prm of w.params.filter((q) => q.unit === 'deg')) {
      const input = pg.locator(`#p-${w.name}-${prm.key}`);
      const cap = m.max_tilt_deg != null && (prm.max == null || m.max_tilt_deg < prm.max) ? m.max_tilt_deg : prm.max;
      assert((await input.getAttribute('max')) === (cap == null ? '' : String(cap)), `${m.name} ${w.name} ${prm.key}: max ${await input.getAttribute('max')} ≠ ${cap}`);
      if (m.fixed_tilt_deg != null) {
        assert((await input.inputValue()) === String(m.fixed_tilt_deg) && (await input.getAttribute('readonly')) !== null, `${m.name}: ${w.name} ${prm.key} fixed at ${m.fixed_tilt_deg}°`);
      } else {
        await input.fill(String((cap ?? 1000) + 5));
        await input.dispatchEvent('change');
        const v = Number(await input.inputValue());
        assert(cap == null || v <= cap, `${m.name}: ${w.name} ${prm.key} clamped to ${cap} (${v})`);
      }
    }
  }
}

/** Types `value` into the input `selector` and fires its change event. */
async function setInput(selector, value) {
  await page.locator(selector).fill(String(value));
  await page.locator(selector).dispatchEvent('change');
}

/** Waits for the error box; returns its code, message, advice and advice key. */
async function shownError() {
  await page.waitForSelector('[data-testid="error"]:not([hidden])', { timeout: 60000 });
  return page.evaluate(() => {
    const box = document.querySelector('[data-testid="error"]');
    const advice = box.querySelector('[data-testid="error-advice"]');
    return { code: box.dataset.code ?? null, message: box.querySelector('[data-testid="error-message"]')?.textContent, advice: advice?.textContent ?? null, key: advice?.dataset.advice ?? null };
  });
}

/** The form's rows of a container: key, flag, label, and each input's kind and limits. */
async function formRows(container) {
  return page.locator(`${container} > .param`).evaluateAll((rows) => rows.map((r) => ({
    key: r.dataset.key, flag: r.dataset.flag ?? null, type: r.dataset.type, label: r.querySelector('label')?.textContent.trim(),
    inputs: [...r.querySelectorAll('input:not([data-switch]), select')].map((i) => ({
      tag: i.tagName.toLowerCase(), type: i.type, min: i.getAttribute('min'), max: i.getAttribute('max'),
      choices: i.tagName === 'SELECT' ? [...i.options].map((o) => o.value) : null,
    })),
    switch: !!r.querySelector('[data-switch]'),
  })));
}

/** Checks the rows against the schema's Params; `maxFor(p)` is the max a number input must show. */
function checkRows(where, rows, params, maxFor = (p) => p.max) {
  assert(JSON.stringify(rows.map((r) => r.key)) === JSON.stringify(params.map((p) => p.key)), `${where}: rows ${rows.map((r) => r.key)} ≠ schema ${params.map((p) => p.key)}`);
  const arity = { number: 1, pair: 2, triple: 3, choice: 1, bool: 1, text: 1 };
  params.forEach((p, k) => {
    const r = rows[k];
    const what = `${where} ${p.key}`;
    assert(r.type === p.type && r.flag === (p.flag ?? null), `${what}: type ${r.type} / flag ${r.flag} ≠ ${p.type} / ${p.flag}`);
    assert(r.label?.includes(p.label), `${what}: label “${r.label}” lacks “${p.label}”`);
    if (p.unit === 'mm') assert(r.label.includes('(mm)'), `${what}: label “${r.label}” shows the unit mm`);
    if (p.unit === 'deg') assert(r.label.includes('(°)'), `${what}: label “${r.label}” shows the unit °`);
    assert(r.inputs.length === arity[p.type], `${what}: ${r.inputs.length} inputs for a ${p.type}`);
    const optionalSwitch = !!p.optional && p.type !== 'choice' && p.type !== 'bool';
    assert(r.switch === optionalSwitch, `${what}: an on/off switch exactly when optional (${p.optional})`);
    for (const i of r.inputs) {
      if (p.type === 'choice') {
        const want = (p.optional ? [''] : []).concat(p.choices);
        assert(i.tag === 'select' && JSON.stringify(i.choices) === JSON.stringify(want), `${what}: choices ${i.choices} ≠ ${want}`);
      } else if (p.type === 'bool') {
        assert(i.type === 'checkbox', `${what}: a checkbox`);
      } else if (p.type === 'text') {
        assert(i.tag === 'input' && i.type === 'text', `${what}: a text input`);
      } else {
        const max = maxFor(p);
        assert(i.type === 'number', `${what}: a number input`);
        assert((i.min ?? '') === (p.min == null ? '' : String(p.min)), `${what}: min ${i.min} ≠ ${p.min}`);
        assert((i.max ?? '') === (max == null ? '' : String(max)), `${what}: max ${i.max} ≠ ${max}`);
      }
    }
  });
}

/** The long flags of a CLI subcommand's --help. */
function cliFlags(sub) {
  return [...new Set([...sh(CLI, [sub, '--help']).matchAll(/^\s+(?:-\w, )?(--[a-z][a-z0-9-]*)/gm)].map((m) => m[1]))];
}

async function pixels() {
  return sha(await page.locator('#canvas-wrap canvas').screenshot());
}

try {
  await test('page loads with every preset and no CSP error', async () => {
    await page.goto(url);
    await page.waitForSelector('body[data-ready="1"]', { timeout: 60000 });
    const names = await tid('machine-select').locator('option').evaluateAll((os) => os.map((o) => o.value));
    assert(JSON.stringify(names) === JSON.stringify(presetNames), `machine options ${names} ≠ presets ${presetNames}`);
    for (const t of ['model-input', 'machine-select', 'warp-select', 'warped-download', 'job-download', 'gcode-input', 'progress', 'cancel', 'error', 'layer-slider', 'result-download']) {
      assert((await tid(t).count()) === 1, `data-testid ${t} present once`);
    }
    await screenshot('loaded');
    await page.setViewportSize({ width: 820, height: 1180 }); // a tablet, portrait
    await screenshot('loaded-tablet');
    await page.setViewportSize({ width: 1280, height: 720 });
  });

  await test('generated model: every preset in turn shows its limits and re-warps', async () => {
    await tid('example-select').selectOption('cylinder');
    await warpSettled();
    assert((await page.locator('#model-info').getAttribute('data-triangles')) > 0, 'triangle count shown');
    for (const name of presetNames) {
      await tid('machine-select').selectOption(name);
      await warpSettled();
      const info = await tid('machine-info').innerText();
      assert(info.includes(name), `machine info names ${name}`);
      const warn = await tid('warnings').innerText();
      assert(warn.length > 0, `warnings/limits line for ${name}`);
      await screenshot(`preset-${name}`);
    }
  });

  let exampleDir;
  await test('generated model: browser output byte-identical to the CLI (conic 30°, prusa-slicer)', async () => {
    const p = join(TMP, 'cylinder.stl');
    writeFileSync(p, wasm.example_stl('cylinder'));
    exampleDir = await roundTrip('example-cylinder', p, 30);
  });

  await test('layer slider and move slider change the preview', async () => {
    const vp = page.locator('#canvas-wrap');
    const before = await vp.getAttribute('data-drawn');
    const px0 = await pixels();
    await tid('layer-slider').focus();
    await page.keyboard.press('Home');
    for (let i = 0; i < 5; i++) await page.keyboard.press('ArrowRight');
    await page.waitForTimeout(200);
    const after = await vp.getAttribute('data-drawn');
    const px1 = await pixels();
    assert(before !== after, `data-drawn changed (${before} → ${after})`);
    assert(px0 !== px1, 'canvas pixels changed');
    assert((await vp.getAttribute('data-layer')) !== null, 'layer attribute set');
    await screenshot('layer-5');
    await page.locator('#move-slider').focus();
    await page.keyboard.press('Home');
    await page.waitForTimeout(100);
    assert((await vp.getAttribute('data-move')) === '0', 'move slider to the first move');
    await tid('color-mode').selectOption('tilt');
    await tid('show-travel').check();
    await page.waitForTimeout(200);
    await screenshot('tilt-travel');
  });

  await test('every preset: the machine G-code is byte-identical to the CLI\'s (or the same named error)', async () => {
    const p = join(TMP, 'cylinder.stl');
    writeFileSync(p, wasm.example_stl('cylinder'));
    await tid('model-input').setInputFiles(p);
    await warpSettled();
    for (const name of presetNames) {
      const dir = join(TMP, `preset-${name}`);
      mkdirSync(dir, { recursive: true });
      await tid('machine-select').selectOption(name);
      await warpSettled();
      await download('warped-download', join(dir, 'W.stl'));
      await download('job-download', join(dir, 'W.job.json'));
      slice(join(dir, 'W.stl'), join(dir, 'W.gcode'));
      const machineArgs = name === 'cartesian' ? [] : ['--machine', name];
      // the machines turning about the origin get the part placed there (the polar one off
      // its centre), in the page and on the CLI alike
      const place = { 'open5x-ab': [0, 0], 'open5x-prusa-uv': [0, 0], 'open5x-jubilee-bc': [0, 0], 'lathe-a': [0, 0], 'core-r-theta': [60, 0] }[name];
      await tid('place-on').setChecked(!!place);
      if (place) {
        await page.locator('#p-place-x').fill(String(place[0]));
        await page.locator('#p-place-y').fill(String(place[1]));
        machineArgs.push('--place', place.join(','));
      }
      let cliError = null;
      let cliOut = '';
      try {
        cliOut = sh(CLI, ['unwarp', join(dir, 'W.gcode'), '--job', join(dir, 'W.job.json'), '--stl', join(dir, 'W.stl'), ...machineArgs, '-o', join(dir, 'C.out.gcode')]);
      } catch (e) {
        cliError = String(e.stderr ?? e);
      }
      await tid('gcode-input').setInputFiles(join(dir, 'W.gcode'));
      await page.waitForFunction(() => {
        const pr = document.querySelector('[data-testid="progress"]');
        const err = document.querySelector('[data-testid="error"]');
        return pr.dataset.done === '1' || !err.hidden;
      }, null, { timeout: 600000 });
      const err = tid('error');
      if (await err.isVisible()) {
        const text = await err.innerText();
        assert(cliError !== null, `${name}: the page showed an error the CLI did not: ${text}`);
        // placed, the part is within reach; the default head may still meet it (a refusal by
        // the collision check, on by default, as on the CLI)
        assert(!place || text.includes('collision'), `${name}: placed at ${place} the part must print, but: ${text}`);
        await screenshot(`preset-${name}-error`);
        continue;
      }
      assert(cliError === null, `${name}: the CLI failed but the page did not: ${cliError}`);
      const out = await download('result-download', join(dir, 'B.out.gcode'));
      const cli = readFileSync(join(dir, 'C.out.gcode'));
      assert(out.equals(cli), `${name}: browser G-code (${out.length} B, ${sha(out)}) differs from the CLI's (${cli.length} B, ${sha(cli)})`);
      // the unwarp report's warnings (issue 12) are the CLI's `warning:` lines
      const cliWarnings = cliOut.split('\n').filter((l) => l.startsWith('warning: ')).map((l) => l.slice(9));
      const pageWarnings = await tid('unwarp-warnings').locator('li').allInnerTexts();
      assert(JSON.stringify(pageWarnings) === JSON.stringify(cliWarnings), `${name}: page warnings ${JSON.stringify(pageWarnings)} vs the CLI's ${JSON.stringify(cliWarnings)}`);
      // the worker's check of the machine file: the CLI's `warpslice check` of the same file
      if (name !== 'cartesian') {
        // reach and speeds compared (the file passed the collision check: no collision finding)
        const r = spawnSync(CLI, ['check', join(dir, 'C.out.gcode'), '--machine', name, '--json', '--skip-collisions'], { maxBuffer: 1 << 28 });
        assert(r.status === 0 || r.status === 1, `${name}: check exit ${r.status}: ${r.stderr}`);
        const rep = JSON.parse(r.stdout.toString());
        const total = rep.counts.reach + rep.counts.collision + rep.counts.speed;
        const shown = await tid('findings').getAttribute('data-count');
        assert(shown === String(total), `${name}: the page shows ${shown} findings, warpslice check ${total}`);
        const lines = await tid('findings').locator('[data-line]').evaluateAll((es) => es.map((e) => Number(e.dataset.line)));
        const want = rep.findings.slice(0, lines.length).map((f) => f.line);
        assert(JSON.stringify(lines) === JSON.stringify(want), `${name}: finding lines ${lines} vs ${want}`);
        // a click on the first finding shows the checked output's preview at that line
        const first = tid('findings').locator('button[data-line]').first();
        if (await first.count()) {
          const line = await first.getAttribute('data-line');
          await first.click();
          assert((await tid('findings').getAttribute('data-preview')) === 'check', `${name}: the checked output's preview is shown`);
          assert((await tid('viewport').getAttribute('data-line')) === line, `${name}: the preview moved to line ${line}: ${await tid('viewport').getAttribute('data-line')}`);
        }
      }
      await screenshot(`preset-${name}-result`);
    }
    await tid('place-on').setChecked(false);
    await tid('machine-select').selectOption('cartesian');
    await warpSettled();
  });

  await test('a colliding machine file (open5x-ab, conic 30°): the page refuses with the core\'s machine.collision message, and written anyway it is the CLI\'s --allow-collisions file, findings listed', async () => {
    // The default head's heater block meets the 30° cone on the A/B table (the CLI's refusal is
    // checked first, so the case tests something). The page's streamed unwarp runs the core's
    // collision check itself: its refusal is the core's message (the CLI prints it after the
    // file name), and with allow_collisions its file ends with the CLI's finding comments.
    const dir = join(TMP, 'collision');
    mkdirSync(dir, { recursive: true });
    const p = join(dir, 'cylinder.stl');
    writeFileSync(p, wasm.example_stl('cylinder'));
    await tid('model-input').setInputFiles(p);
    await warpSettled();
    // the machine first (a preset brings its own warp), then the 30° cone
    await tid('machine-select').selectOption('open5x-ab');
    await warpSettled();
    await tid('warp-select').selectOption('conic');
    await page.locator('#p-conic-angle').fill('30');
    await page.locator('#p-conic-angle').dispatchEvent('change');
    await page.locator('#p-conic-direction').selectOption('outward');
    // the A/B table turns about the origin: the part goes there
    await tid('place-on').setChecked(true);
    await page.locator('#p-place-x').fill('0');
    await page.locator('#p-place-y').fill('0');
    await page.locator('#p-place-y').dispatchEvent('change');
    await warpSettled();
    const warp = JSON.parse(readFileSync(await download('job-download', join(dir, 'W.job.json')).then(() => join(dir, 'W.job.json')))).warp.spec;
    assert(warp.kind === 'conic' && warp.angle === 30 && warp.direction === 'outward', `the 30° cone: ${JSON.stringify(warp)}`);
    await download('warped-download', join(dir, 'W.stl'));
    await download('job-download', join(dir, 'W.job.json'));
    slice(join(dir, 'W.stl'), join(dir, 'W.gcode'));
    const cliArgs = (extra, out) => ['unwarp', join(dir, 'W.gcode'), '--job', join(dir, 'W.job.json'), '--stl', join(dir, 'W.stl'), '--machine', 'open5x-ab', '--place', '0,0', ...extra, '-o', join(dir, out)];
    const refused = spawnSync(CLI, cliArgs([], 'C.out.gcode'), { encoding: 'utf8' });
    assert(refused.status !== 0 && /machine\.collision|into the/.test(refused.stderr), `the CLI refuses the case: ${refused.status} ${refused.stderr}`);
    await tid('gcode-input').setInputFiles(join(dir, 'W.gcode'));
    const err = await shownError();
    assert(err.code === 'machine.collision', `the page refuses with machine.collision: ${JSON.stringify(err)}`);
    assert(err.message.startsWith('machine open5x-ab: output line '), `the core's message: ${err.message}`);
    assert(refused.stderr.trim() === `error: ${join(dir, 'W.gcode')}: ${err.message}`, `the page's message is the CLI's:\n page: ${err.message}\n CLI:  ${refused.stderr.trim()}`);
    await screenshot('collision-refused');
    // "Write anyway, list findings": allow_collisions on, the unwarp again
    await tid('allow-collisions-retry').click();
    await page.waitForFunction(() => {
      const pr = document.querySelector('[data-testid="progress"]');
      const e = document.querySelector('[data-testid="error"]');
      return pr.dataset.done === '1' || !e.hidden;
    }, null, { timeout: 600000 });
    assert(!(await tid('error').isVisible()), `written anyway: ${await tid('error').innerText().catch(() => '')}`);
    sh(CLI, cliArgs(['--allow-collisions'], 'C.allow.gcode'));
    const cli = readFileSync(join(dir, 'C.allow.gcode'));
    const out = await download('result-download', join(dir, 'B.allow.gcode'));
    assert(out.equals(cli), `allow_collisions: browser G-code (${out.length} B, ${sha(out)}) differs from the CLI's (${cli.length} B, ${sha(cli)})`);
    const listed = cli.toString().split('\n').filter((l) => l.startsWith('; warpslice collision: line ')).length;
    assert(listed > 0, 'the CLI\'s file lists its findings');
    // the findings shown are warpslice check's of the same file (collisions included: the
    // page hands the unwarp's findings to its reach-and-speed check instead of walking twice)
    const r = spawnSync(CLI, ['check', join(dir, 'C.allow.gcode'), '--machine', 'open5x-ab', '--json'], { maxBuffer: 1 << 28 });
    assert(r.status === 1, `check finds the collisions: exit ${r.status}: ${r.stderr}`);
    const rep = JSON.parse(r.stdout.toString());
    assert(rep.counts.collision === listed, `check of the file: ${rep.counts.collision} collisions, ${listed} listed`);
    const shown = await tid('findings').getAttribute('data-count');
    assert(shown === String(rep.counts.reach + rep.counts.collision + rep.counts.speed), `the page shows ${shown} findings, warpslice check ${JSON.stringify(rep.counts)}`);
    const lines = await tid('findings').locator('[data-line]').evaluateAll((es) => es.map((e) => `${e.dataset.kind}:${e.dataset.line}`));
    const want = rep.findings.slice(0, lines.length).map((f) => `${f.kind}:${f.line}`);
    assert(lines.length > 0 && JSON.stringify(lines) === JSON.stringify(want), `finding lines ${lines} vs ${want}`);
    const text = await tid('findings').innerText();
    assert(!text.includes('collisions not checked'), `the findings say the collisions were checked: ${text}`);
    // a click on a collision finding shows the checked file's preview, its collisions in red
    const hit = tid('findings').locator('button[data-kind="collision"]').first();
    assert((await hit.count()) === 1, 'a collision finding is a button');
    await hit.click();
    assert((await tid('findings').getAttribute('data-preview')) === 'check', 'the checked output\'s preview is shown');
    const red = Number(await page.locator('#canvas-wrap').getAttribute('data-collision-segments'));
    assert(red > 0, `the preview draws the collisions in red: ${red} segments`);
    // the head at that move: the nozzle at the A/B table's tip along its tool axis (the file's
    // words through the seed's kinematics, tests/head.mjs), the finding's part red
    const head = await assertHeadAtMove({ page, tid, assert, schema }, { file: join(dir, 'C.allow.gcode'), machine: 'open5x-ab', report: rep });
    assert(head.hit.length > 0, `the clicked collision's move has its part(s) red: line ${head.line}`);
    await screenshot('collision-allowed');
    await page.locator('input[data-param="allow_collisions"]').uncheck();
    await tid('place-on').setChecked(false);
    await tid('machine-select').selectOption('cartesian');
    await warpSettled();
  });

  await test('moving bed (open5x-ab): the machine-coordinates toggle shows the head in X Y Z and the bed at its pose', async () => {
    const dir = join(TMP, 'machine-frame');
    mkdirSync(dir, { recursive: true });
    const p = join(dir, 'cylinder.stl');
    writeFileSync(p, wasm.example_stl('cylinder'));
    await tid('model-input').setInputFiles(p);
    await warpSettled();
    // conic 15°: the default head clears this cylinder on the table (at 30° its heater block
    // meets the cone, and the collision check, on by default, refuses the file)
    await setConic(15);
    await tid('machine-select').selectOption('open5x-ab');
    await warpSettled();
    // the A/B table turns about the origin: the part goes there (its X travel is ±100 mm)
    await tid('place-on').setChecked(true);
    await page.locator('#p-place-x').fill('0');
    await page.locator('#p-place-y').fill('0');
    await page.locator('#p-place-y').dispatchEvent('change');
    await warpSettled();
    assert(await tid('machine-frame').isDisabled(), 'toggle disabled before a result exists');
    await download('warped-download', join(dir, 'W.stl'));
    slice(join(dir, 'W.stl'), join(dir, 'W.gcode'));
    await unwarpInBrowser(join(dir, 'W.gcode'));
    const vp = page.locator('#canvas-wrap');
    assert((await vp.getAttribute('data-frame')) === 'part', 'preview starts in the part frame');
    assert(await tid('machine-frame').isEnabled(), 'toggle enabled for open5x-ab with a result');
    // the head in the part frame at the move shown (the unwarp's own preview: axes from the
    // machine's inverse kinematics): the nozzle at the readout's tip (2 decimals), tilted by
    // the readout's tilt (1 decimal)
    {
      const nozzle = (await drawnHead(page))?.find((h) => h.name === 'nozzle');
      assert(nozzle, 'the head is drawn in the part frame');
      const text = await page.locator('#move-out').innerText();
      const at = text.match(/x (-?[\d.]+) y (-?[\d.]+) z (-?[\d.]+), tilt (-?[\d.]+)°/).slice(1).map(Number);
      const up = nozzle.top.map((x, i) => x - nozzle.base[i]);
      const tiltDeg = (Math.acos(up[2] / Math.hypot(...up)) * 180) / Math.PI;
      assert(Math.abs(tiltDeg - at[3]) <= 0.05 + AXIS_DEG, `the nozzle's tilt ${tiltDeg}° vs the readout's ${at[3]}°`);
      const off = Math.hypot(...nozzle.base.map((x, i) => x - at[i]));
      assert(off <= 0.005 * Math.sqrt(3) + TIP_MM, `the nozzle's tip ${nozzle.base} vs the readout's ${at.slice(0, 3)}: ${off} mm`);
    }
    const pxPart = await pixels();
    await screenshot('machine-frame-off');
    // Keyboard: focus the labelled checkbox and press Space.
    await tid('machine-frame').focus();
    await page.keyboard.press('Space');
    await page.waitForTimeout(300);
    assert(await tid('machine-frame').isChecked(), 'Space ticks the toggle');
    assert((await vp.getAttribute('data-frame')) === 'machine', 'data-frame="machine"');
    const pxMachine = await pixels();
    assert(pxPart !== pxMachine, 'canvas pixels changed in machine coordinates');
    await screenshot('machine-frame-on');
    // Moving along a tilted layer changes A/B, so the bed outline turns.
    await tid('layer-slider').focus();
    await page.keyboard.press('End');
    await page.locator('#move-slider').focus();
    await page.keyboard.press('Home');
    await page.waitForTimeout(200);
    const pxA = await pixels();
    const bedA = await vp.getAttribute('data-bed');
    const moveMax = Number(await page.locator('#move-slider').getAttribute('max'));
    await page.locator('#move-slider').evaluate((el, v) => {
      el.value = String(v);
      el.dispatchEvent(new Event('input', { bubbles: true }));
    }, Math.floor(moveMax / 2));
    await page.waitForTimeout(200);
    const pxB = await pixels();
    const bedB = await vp.getAttribute('data-bed');
    assert(moveMax > 1 && pxA !== pxB, `canvas pixels change with the move slider (max ${moveMax})`);
    assert(bedA && bedB && bedA !== bedB, `bed pose changes with the move slider (${bedA} → ${bedB})`);
    assert((await page.locator('#move-out').innerText()).includes('machine'), 'move readout says machine coordinates');
    // the head in machine coordinates: the A/B table's nozzle is vertical in the machine
    // (seed 004), its tip where the readout puts the head (2 decimals)
    const head = await drawnHead(page);
    const nozzle = head?.find((h) => h.name === 'nozzle');
    assert(nozzle, `the head is drawn in machine coordinates: ${JSON.stringify(head)}`);
    const up = nozzle.top.map((x, i) => x - nozzle.base[i]);
    const tiltDeg = (Math.acos(up[2] / Math.hypot(...up)) * 180) / Math.PI;
    assert(tiltDeg <= AXIS_DEG, `the nozzle is vertical in the machine frame: ${tiltDeg}° (${up})`);
    const readout = (await page.locator('#move-out').innerText()).match(/x (-?[\d.]+) y (-?[\d.]+) z (-?[\d.]+)/).slice(1).map(Number);
    const off = Math.hypot(...nozzle.base.map((x, i) => x - readout[i]));
    assert(off <= 0.005 * Math.sqrt(3) + TIP_MM, `the nozzle's tip ${nozzle.base} at the head's machine position ${readout}: ${off} mm`);
    await screenshot('machine-frame-move');
    await tid('machine-frame').uncheck();
    await page.waitForTimeout(200);
    assert((await vp.getAttribute('data-frame')) === 'part', 'unticked: back to the part frame');
    await screenshot('machine-frame-unticked');
    await tid('place-on').setChecked(false);
    await tid('machine-select').selectOption('cartesian');
    await warpSettled();
    assert(await tid('machine-frame').isDisabled(), 'toggle disabled for cartesian');
    assert(!(await tid('machine-frame').isChecked()), 'toggle unticked for cartesian');
  });

  if (existsSync(join(CORPUS, 'sm_gearwheel_bin.stl'))) {
    await test('corpus model (sm_gearwheel_bin.stl): byte-identical to the CLI', async () => {
      const p = join(CORPUS, 'sm_gearwheel_bin.stl');
      await tid('model-input').setInputFiles(p);
      await warpSettled();
      await roundTrip('corpus-gearwheel', p, 25);
    });
  } else if (process.env.WARPSLICE_ALLOW_SKIP === '1') {
    console.log('SKIPPED corpus model (sm_gearwheel_bin.stl): ../shared/corpus/stl not present (WARPSLICE_ALLOW_SKIP=1)');
  } else {
    await test('corpus model (sm_gearwheel_bin.stl): byte-identical to the CLI', async () => {
      throw new Error(`the corpus model cannot run: ${join(CORPUS, 'sm_gearwheel_bin.stl')} is missing (WARPSLICE_ALLOW_SKIP=1 skips it in a local run)`);
    });
  }

  await test('non-matching G-code shows an error and the page survives', async () => {
    // The G-code sliced for the generated cylinder, against the gearwheel's (or a re-warped) job.
    await tid('warp-select').selectOption('belt');
    await warpSettled();
    const bad = join(TMP, 'hello.gcode');
    writeFileSync(bad, 'G28\nG1 X10 Y10 Z0.2 E1 F1200\n');
    await tid('gcode-input').setInputFiles(bad);
    await page.waitForSelector('[data-testid="error"]:not([hidden])', { timeout: 60000 });
    const text = await tid('error').innerText();
    assert(/what to do/i.test(text), `error says what to do: ${text}`);
    await screenshot('error-gcode');
    if (exampleDir) {
      await tid('gcode-input').setInputFiles(join(exampleDir, 'W.gcode'));
      await page.waitForFunction(() => {
        const p = document.querySelector('[data-testid="progress"]');
        return p.dataset.done === '1' || document.getElementById('progress-text').textContent === 'failed';
      }, null, { timeout: 60000 });
      const failedText = await page.locator('#progress-text').innerText();
      assert(failedText === 'failed', `the wrong model's G-code is refused (progress: ${failedText})`);
      await screenshot('error-wrong-model');
    }
    assert((await page.evaluate(() => 1 + 1)) === 2, 'page alive');
  });

  await test('broken STL (sm_empty.stl) shows an error and the page survives', async () => {
    const p = existsSync(join(CORPUS, 'broken', 'sm_empty.stl')) ? join(CORPUS, 'broken', 'sm_empty.stl') : join(TMP, 'empty.stl');
    if (!existsSync(p)) writeFileSync(p, '');
    await tid('model-input').setInputFiles(p);
    await page.waitForSelector('[data-testid="error"]:not([hidden])', { timeout: 30000 });
    const text = await tid('error').innerText();
    assert(/cannot read/i.test(text), `error shown: ${text}`);
    await screenshot('error-stl');
    await tid('example-select').selectOption('cube');
    await warpSettled();
    assert(await tid('error').isHidden(), 'error cleared after a good model');
  });

  await test('settings round-trip through the URL hash', async () => {
    await tid('machine-select').selectOption('pax-5axis');
    await tid('warp-select').selectOption('tilted');
    await warpSettled();
    const hash = await page.evaluate(() => location.hash);
    assert(hash.startsWith('#s='), 'hash written');
    const page2 = await context.newPage();
    await page2.goto(url + hash);
    await page2.waitForSelector('body[data-ready="1"]');
    assert((await page2.locator('[data-testid="machine-select"]').inputValue()) === 'pax-5axis', 'machine from hash');
    assert((await page2.locator('[data-testid="warp-select"]').inputValue()) === 'tilted', 'warp from hash');
    await page2.close();
  });

  await test('settings export and import as JSON', async () => {
    const p = join(TMP, 'settings.json');
    const exported = JSON.parse(await download('settings-export', p));
    assert(exported.machine === 'pax-5axis' && exported.warp.kind === 'tilted', `exported ${JSON.stringify(exported)}`);
    exported.machine = 'open5x-ab';
    exported.warp = { kind: 'belt', angle: 12, tx: 1, ty: 0 };
    exported.layer_height = 0.25;
    writeFileSync(p, JSON.stringify(exported));
    await tid('settings-import').setInputFiles(p);
    await page.waitForFunction(() => document.querySelector('[data-testid="warp-select"]').value === 'belt');
    assert((await tid('machine-select').inputValue()) === 'open5x-ab', 'machine imported');
    assert((await page.locator('#p-belt-angle').inputValue()) === '12', 'belt angle imported');
    assert((await tid('layer-height').inputValue()) === '0.25', 'layer height imported');
    await warpSettled();
    const job = JSON.parse(await download('job-download', join(TMP, 'imported.job.json')));
    assert(job.layer_height === 0.25 && job.warp.spec.kind === 'belt' && job.warp.spec.angle === 12, `job follows the imported settings: ${JSON.stringify(job.warp)}`);
    await tid('layer-height').fill('0.2');
    await tid('layer-height').dispatchEvent('change');
    await warpSettled();
  });

  await test('cancel right after starting leaves the page usable', async () => {
    if (!exampleDir) throw new Error('needs the generated-model round trip');
    await tid('example-select').selectOption('');
    await page.evaluate(() => (document.getElementById('example-select').value = ''));
    await tid('example-select').selectOption('cylinder');
    await setConic(30);
    // A slow, large input: the example's G-code repeated does not register; use it once and cancel at once.
    await tid('gcode-input').setInputFiles(join(exampleDir, 'W.gcode'));
    await tid('cancel').click({ timeout: 5000 }).catch(() => {});
    await page.waitForFunction(() => ['cancelled', ''].includes(document.getElementById('progress-text').textContent) || document.querySelector('[data-testid="progress"]').dataset.done === '1', null, { timeout: 60000 })
      .catch(async (e) => { throw new Error(`${e.message}; progress text: ${await page.locator('#progress-text').innerText()}; error: ${await tid('error').innerText()}`); });
    await unwarpInBrowser(join(exampleDir, 'W.gcode'));
  });

  if (BIG) {
    await test('100 MB G-code unwarped in the browser (3-axis and pax-5axis) is byte-identical to the native CLI\'s, timed against it in the same run', async () => {
      const big = join(ART, 'big');
      mkdirSync(big, { recursive: true });
      const stl = join(big, 'tall.stl');
      makeCylinder(stl, 60, 40, 96); // ≈ 105 MB of G-code with the settings below
      cliWarp(stl, join(big, 'W.stl'), ['--warp', 'conic', '--angle', '20', '--direction', 'outward', '--max-edge', '4']);
      const key = sha(readFileSync(join(big, 'W.stl')));
      const gcode = join(big, `W.${key}.gcode`);
      if (!existsSync(gcode)) {
        for (const f of readdirSync(big)) if (/^W\.[0-9a-f]+\.gcode$/.test(f)) rmSync(join(big, f)); // stale cache
        const ts = Date.now();
        sh('prusa-slicer', ['--loglevel', '1', '--export-gcode', '--layer-height', '0.2', '--first-layer-height', '0.2', '--nozzle-diameter', '0.4',
          '--filament-diameter', '1.75', '--gcode-flavor', 'marlin2', '--use-relative-e-distances', '--layer-gcode', 'G92 E0',
          '--perimeters', '6', '--fill-density', '35%', '--fill-pattern', 'gyroid', '--output', gcode, join(big, 'W.stl')]);
        console.log(`     sliced the 100 MB test G-code in ${((Date.now() - ts) / 1000).toFixed(0)} s`);
      }
      const size = statSync(gcode).size;
      assert(size >= 90e6, `the test G-code is ~100 MB (${(size / 1e6).toFixed(1)} MB)`);
      // a fresh page: a fresh worker, whose wasm memory is the module's idle size
      await page.goto(url);
      await page.waitForSelector('body[data-ready="1"]');
      await tid('model-input').setInputFiles(stl);
      await warpSettled();
      await setBigWarp('cartesian');
      // Cancel part-way through, then run it for real.
      await tid('gcode-input').setInputFiles(gcode);
      await page.waitForFunction(() => Number(document.querySelector('[data-testid="progress"]').value) > 0.1, null, { timeout: 60000 });
      await tid('cancel').click();
      await page.waitForFunction(() => document.getElementById('progress-text').textContent === 'cancelled', null, { timeout: 10000 });
      assert(await tid('error').isHidden(), 'cancel is not an error');
      assert(await page.locator('[data-testid="result-download"].disabled').count() === 1, 'no result after cancel');
      await screenshot('big-cancelled');
      const figures = { input_bytes: size };
      figures['3-axis'] = await bigRun('3-axis', gcode, big);
      // Issue 13's memory bound, asserted for the 3-axis unwarp only: unlike a time it is
      // deterministic (the same slices, the same allocations, the same preview buffers every
      // run). pax-5axis's is printed: its collision check keeps the printed material (the
      // native CLI's peak RSS is of the same size).
      const above = figures['3-axis'].worker_above_idle_bytes;
      assert(above <= WORKER_ABOVE_IDLE_MAX, `the worker's memory ${(above / 2 ** 20).toFixed(1)} MiB above the wasm module's idle size is at most ${WORKER_ABOVE_IDLE_MAX / 2 ** 20} MiB`);
      await screenshot('big-toolpath');
      // One 5-axis preset: pax-5axis's default head meets the printed cone here (the CLI refuses
      // it with machine.collision), so it runs with the page's "Allow collisions" option, the
      // CLI's --allow-collisions: the check walks every move and lists its findings.
      if (BIG_5AXIS) {
        await setBigWarp('pax-5axis');
        await page.locator('input[data-param="allow_collisions"]').setChecked(true);
        await page.locator('input[data-param="allow_collisions"]').dispatchEvent('change');
        figures['pax-5axis'] = await bigRun('pax-5axis', gcode, big);
        await page.locator('input[data-param="allow_collisions"]').setChecked(false);
        await page.locator('input[data-param="allow_collisions"]').dispatchEvent('change');
      } else {
        console.log('     SKIPPED the 100 MB G-code\'s pax-5axis run (about 3 min; WARPSLICE_FULL_MATRIX=1 or WARPSLICE_WEB_BIG_5AXIS=1 runs it)');
      }
      writeFileSync(join(ART, 'big.json'), JSON.stringify(figures, null, 2));
    });
    } else {
    console.log('SKIPPED 100 MB G-code test (WARPSLICE_WEB_BIG=0)');
  }

  await test('the form lists exactly the core\'s schema: every warp, its parameters, the warp and unwarp options, with labels and limits', async () => {
    await page.goto(url);
    await page.waitForSelector('body[data-ready="1"]');
    const warps = await tid('warp-select').locator('option').evaluateAll((os) => os.map((o) => o.value));
    assert(JSON.stringify(warps) === JSON.stringify(schema.warps.map((w) => w.name)), `warp options ${warps} ≠ schema ${schema.warps.map((w) => w.name)}`);
    const [firstMachine, firstWarp] = [await tid('machine-select').inputValue(), await tid('warp-select').inputValue()];
    for (const w of schema.warps) {
      // a machine that prints this warp; a degree parameter (the layer tilt) is capped at its tilt limit
      const m = schema.machines.find((x) => x.warps.includes(w.name));
      assert(m, `some preset prints the ${w.name} warp`);
      await tid('machine-select').selectOption(m.name);
      await tid('warp-select').selectOption(w.name);
      const cap = (p) => (p.unit === 'deg' && m.max_tilt_deg != null && (p.max == null || m.max_tilt_deg < p.max) ? m.max_tilt_deg : p.max);
      checkRows(`warp ${w.name} on ${m.name}`, await formRows('#warp-params'), w.params, cap);
      assert((await page.locator('#warp-params .formula').innerText()).includes(w.formula), `${w.name}: the formula is shown`);
    }
    // the form as the page starts (the last warp, the field, waits for an expression: the
    // tests after this one load models into the form)
    await tid('machine-select').selectOption(firstMachine);
    await tid('warp-select').selectOption(firstWarp);
    checkRows('warp options', await formRows('#warp-options'), schema.warp_options);
    checkRows('unwarp options', await formRows('#unwarp-options'), schema.unwarp_options);
    // Every flag of the CLI is a field of the page: --warp is the warp select, --machine the
    // machine select and the custom machine JSON, --job and -o are the page's own steps.
    const pageFlags = {
      warp: [...schema.warps.flatMap((w) => w.params), ...schema.warp_options].map((p) => p.flag),
      unwarp: schema.unwarp_options.map((p) => p.flag),
    };
    // `warp --suggested N` and the search's options (issue 15): the page has no Suggest step
    // yet (issue 15 §5); said here, not skipped silently
    const notYet = ['--suggested', ...(schema.suggest_options || []).map((p) => p.flag)]
      .filter((f) => !pageFlags.warp.includes(f));
    console.log(`NOT YET IN THE PAGE (issue 15 §5, the Suggest step): warpslice warp ${notYet.join(' ')}`);
    for (const sub of ['warp', 'unwarp']) {
      const flags = cliFlags(sub);
      for (const f of flags) {
        // the page's own: the job and the warped STL of step 2 (always given), the output and
        // the firmware configuration (the result's second download, for a machine output)
        if (['--warp', '--machine', '--job', '--stl', '--output', '--config-out', '--help'].includes(f)) continue;
        if (sub === 'warp' && notYet.includes(f)) continue;
        assert(pageFlags[sub].includes(f), `warpslice ${sub} ${f} has a field in the page`);
      }
      // and the other way round: every field of the page is a flag of the CLI
      for (const f of pageFlags[sub]) assert(flags.includes(f), `the page's ${f} is a flag of warpslice ${sub}`);
    }
    const warpHelp = /--warp <\w+>[\s\S]*?\[possible values: ([^\]]+)\]/.exec(sh(CLI, ['warp', '--help']));
    assert(warpHelp, 'warpslice warp --help lists the possible warps');
    const warpValues = warpHelp[1].split(', ');
    assert(JSON.stringify(warpValues) === JSON.stringify(warps), `the CLI's warps ${warpValues} are the page's ${warps}`);
    await tid('machine-select').selectOption('cartesian');
    await tid('warp-select').selectOption('conic');
  });

  await test('every machine of the schema: the warps it prints are the ones offered, its tilt limit caps the tilt and a fixed tilt is fixed', async () => {
    const p2 = await context.newPage(); // no model: changing the machine warps nothing
    try {
      await p2.goto(url);
      await p2.waitForSelector('body[data-ready="1"]');
      for (const m of schema.machines) {
        await p2.locator('[data-testid="machine-select"]').selectOption(m.name);
        await machineForm(p2, m);
      }
    } finally {
      await p2.close();
    }
  });

  await test('cylindrical and spherical warps through the page: byte-identical to the CLI (prusa-slicer)', async () => {
    const p = join(TMP, 'cylinder-curved-warps.stl');
    writeFileSync(p, wasm.example_stl('cylinder'));
    // The axis / centre left empty (the core puts it under the part), then given.
    for (const [warp, key, flag, at] of [['cylindrical', 'axis', '--axis-yz', null], ['spherical', 'center', '--sphere-center', null], ['cylindrical', 'axis', '--axis-yz', [0, -25]]]) {
      await pageVsCli(`${warp}-${at ? 'given' : 'empty'}`, p, async () => {
        await tid('machine-select').selectOption('cartesian');
        await tid('warp-select').selectOption(warp);
        await setInput(`#p-${warp}-radius`, 20);
        await tid(`${key}-on`).setChecked(!!at);
        for (const [k, v] of (at ?? []).entries()) await setInput(`#p-${warp}-${key}-${'xyz'[k]}`, v);
      }, ['--warp', warp, '--radius', '20', ...(at ? [flag, at.join(',')] : [])]);
      // The feature legend names the core's features (describe().features).
      await tid('color-mode').selectOption('feature');
      const legend = await page.locator('#legend > div').allInnerTexts();
      const names = schema.features.map((f) => f.replace(/-/g, ' '));
      assert(legend.length > 1 && legend.every((t) => t.trim() === 'travel' || names.includes(t.trim())), `legend ${legend} names features of ${names}`);
      assert(legend.some((t) => t.trim() === 'outer wall'), `prusa-slicer's outer walls are in the legend: ${legend}`);
      const job = JSON.parse(readFileSync(join(TMP, `${warp}-${at ? 'given' : 'empty'}`, 'W.job.json')));
      assert(job.warp.spec.kind === warp && job.warp.spec.radius === 20, `the job is the ${warp} warp of radius 20: ${JSON.stringify(job.warp.spec)}`);
      if (at) assert(JSON.stringify(job.warp.spec[key]) === JSON.stringify(at), `the job's ${key} is the one given: ${JSON.stringify(job.warp.spec)}`);
    }
  });

  await test('custom machine JSON (pax-5axis, limit changed) and the unwarp options: byte-identical to the CLI, and the limit holds', async () => {
    const pax = schema.machines.find((m) => m.name === 'pax-5axis');
    assert(pax && pax.spec.kind === 'pax', 'the pax-5axis preset is in the schema');
    // renamed rotary axes: the feed limits keyed by letter are renamed with them (A → U, B → V)
    const rename = { A: 'U', B: 'V' };
    const maxFeed = Object.fromEntries(Object.entries(pax.spec.max_feed ?? {}).map(([k, v]) => [rename[k] ?? k, v]));
    const custom = { ...pax.spec, name: 'pax-custom', axis_names: ['X', 'Y', 'Z', 'U', 'V'], max_tilt_deg: 20, max_feed: maxFeed };
    const dir = join(TMP, 'custom-machine');
    mkdirSync(dir, { recursive: true });
    const file = join(dir, 'pax-custom.json'); // the page's command line names it <machine name>.json
    writeFileSync(file, JSON.stringify(custom, null, 2));
    const p = join(dir, 'cylinder.stl');
    writeFileSync(p, wasm.example_stl('cylinder'));
    const useCustom = async (angle) => {
      await tid('machine-select').selectOption('pax-5axis');
      await page.locator('#machine-custom-box').evaluate((d) => (d.open = true));
      await tid('machine-json').fill(JSON.stringify(custom, null, 2));
      await tid('machine-json').dispatchEvent('change');
      assert(await tid('machine-custom').isChecked(), 'pasting a machine JSON switches it on');
      await tid('warp-select').selectOption('conic');
      await setInput('#p-conic-angle', angle);
    };
    const unwarpOpts = async () => {
      await tid('flow-ramp-on').check();
      await setInput('#p-flow-ramp-x', 0.8);
      await setInput('#p-flow-ramp-y', 1.2);
      await page.locator('#p-feed').selectOption('all-axes');
      await page.locator('#p-flavour').selectOption('marlin');
      await setInput('#p-z_offset', 0.1);
      await setInput('#p-max_segment', 0.5);
    };
    const { out } = await pageVsCli('custom-machine', p, async () => {
      await useCustom(15);
      await unwarpOpts();
    }, ['--warp', 'conic', '--angle', '15'], ['--machine', file, '--ramp', '0.8,1.2', '--feed', 'all-axes', '--flavour', 'marlin', '--z-offset', '0.1', '--max-segment', '0.5']);
    const text = out.toString();
    assert(/^G1 .*\bU-?\d/m.test(text) && /^G1 .*\bV-?\d/m.test(text) && !/^G1 .*\bB-?\d/m.test(text), 'the output drives the custom machine\'s U and V axes');
    // Marlin 2.1 has no G93: the feed option gives all-axes feed (no G93) and the Marlin header
    assert(!/^G93/m.test(text) && /marlin/i.test(text.split('\n').filter((l) => l.startsWith(';')).join('\n')), 'all-axes feed (no G93) and the Marlin header from the feed and flavour options');
    // The custom limit (20°) holds. The form caps the layer tilt at it (the core's description of
    // this JSON, not the preset's 90°): conic 30° is clamped to 20°. A warp past 20° without a
    // tilt parameter (tilted, strength 0.6: 31°) fails in the page as on the CLI.
    await setInput('#p-conic-angle', 30);
    assert((await page.locator('#p-conic-angle').inputValue()) === '20', `conic 30° is capped at the custom machine's 20°: ${await page.locator('#p-conic-angle').inputValue()}`);
    await tid('warp-select').selectOption('tilted');
    await setInput('#p-tilted-strength', 0.6);
    await warpSettled();
    const tilt30 = Number(await page.locator('#warp-info').getAttribute('data-largest-tilt'));
    assert(tilt30 > 30, `the tilted warp tilts the layers past 30° (${tilt30})`);
    await download('warped-download', join(dir, 'W30.stl'));
    await download('job-download', join(dir, 'W30.job.json'));
    slice(join(dir, 'W30.stl'), join(dir, 'W30.gcode'));
    let cliError = null;
    try {
      sh(CLI, ['unwarp', join(dir, 'W30.gcode'), '--job', join(dir, 'W30.job.json'), '--stl', join(dir, 'W30.stl'), '--machine', file, '-o', join(dir, 'C30.out.gcode')]);
    } catch (e) {
      cliError = String(e.stderr ?? e);
    }
    assert(cliError && /outside its travel/.test(cliError), `the CLI refuses conic 30° on the custom machine: ${cliError}`);
    await tid('gcode-input').setInputFiles(join(dir, 'W30.gcode'));
    const err = await shownError();
    assert(err.code === 'machine.axis-limit', `the page refuses it with the code machine.axis-limit: ${JSON.stringify(err)}`);
    await screenshot('custom-machine-limit');
    await tid('machine-custom').uncheck();
    await tid('warp-select').selectOption('conic');
    await tid('flow-ramp-on').uncheck();
    await page.locator('#p-feed').selectOption('xyz');
    await page.locator('#p-flavour').selectOption('');
    await setInput('#p-z_offset', 0);
    await setInput('#p-max_segment', 1);
    await tid('machine-select').selectOption('cartesian');
    await warpSettled();
  });

  await test('settings round-trip: custom machine JSON and every unwarp option survive the URL hash', async () => {
    await tid('machine-select').selectOption('pax-5axis');
    await page.locator('#machine-custom-box').evaluate((d) => (d.open = true));
    await tid('machine-json').fill(JSON.stringify({ ...schema.machines.find((m) => m.name === 'pax-5axis').spec, max_tilt_deg: 40 }));
    await tid('machine-json').dispatchEvent('change');
    await tid('warp-select').selectOption('spherical');
    await setInput('#p-spherical-radius', 15);
    await tid('flow-ramp-on').check();
    await setInput('#p-flow-ramp-x', 0.7);
    await tid('offset-on').check();
    await setInput('#p-offset-x', 3);
    await page.locator('#p-feed').selectOption('all-axes');
    await page.locator('#p-flavour').selectOption('klipper');
    await page.locator('#p-drop_skirt').check();
    await page.locator('#p-drop_skirt').dispatchEvent('change');
    const a = JSON.parse(await download('settings-export', join(TMP, 'settings-a.json')));
    assert(a.machine_json && JSON.parse(a.machine_json).max_tilt_deg === 40, `custom machine exported: ${a.machine_json}`);
    assert(a.warp.kind === 'spherical' && a.warp.radius === 15, `warp exported: ${JSON.stringify(a.warp)}`);
    assert(a.unwarp.flow.ramp[0] === 0.7 && a.unwarp.offset[0] === 3 && a.unwarp.feed === 'all-axes' && a.unwarp.flavour === 'klipper' && a.unwarp.drop_skirt === true, `unwarp options exported: ${JSON.stringify(a.unwarp)}`);
    const hash = await page.evaluate(() => location.hash);
    const page2 = await context.newPage();
    await page2.goto(url + hash);
    await page2.waitForSelector('body[data-ready="1"]');
    const [dl] = await Promise.all([page2.waitForEvent('download'), page2.locator('[data-testid="settings-export"]').click()]);
    await dl.saveAs(join(TMP, 'settings-b.json'));
    const b = JSON.parse(readFileSync(join(TMP, 'settings-b.json')));
    await page2.close();
    assert(JSON.stringify(b) === JSON.stringify(a), `the hash restores every setting:\n${JSON.stringify(a)}\n${JSON.stringify(b)}`);
    // back to the defaults for the tests after this one
    await page.goto(url);
    await page.waitForSelector('body[data-ready="1"]');
    assert((await tid('warp-select').inputValue()) === 'conic' && !(await tid('machine-custom').isChecked()), 'a page without a hash starts from the defaults');
  });

  await test('custom moving-bed machine (open5x-ab JSON, A limit 80°): placed at 0,0 it matches the CLI, and the machine-coordinates view is drawn for it', async () => {
    const ab = schema.machines.find((m) => m.name === 'open5x-ab');
    assert(ab && ab.moving_bed, 'open5x-ab is a moving-bed preset');
    const custom = { ...ab.spec, name: 'ab-custom', a_limit_deg: 80 };
    const dir = join(TMP, 'custom-ab');
    mkdirSync(dir, { recursive: true });
    const file = join(dir, 'ab-custom.json');
    writeFileSync(file, JSON.stringify(custom));
    const p = join(dir, 'cylinder.stl');
    writeFileSync(p, wasm.example_stl('cylinder'));
    await pageVsCli('custom-ab', p, async () => {
      await tid('machine-select').selectOption('open5x-ab');
      await page.locator('#machine-custom-box').evaluate((d) => (d.open = true));
      await tid('machine-json').fill(JSON.stringify(custom));
      await tid('machine-json').dispatchEvent('change');
      await tid('warp-select').selectOption('conic');
      // 15°: the default head clears this cylinder on the table (at 30° its heater block meets
      // the cone and the collision check, on by default, refuses the file)
      await setInput('#p-conic-angle', 15);
      await tid('place-on').check();
      await setInput('#p-place-x', 0);
      await setInput('#p-place-y', 0);
    }, ['--warp', 'conic', '--angle', '15'], ['--machine', file, '--place', '0,0']);
    assert((await tid('machine-info').innerText()).includes('ab-custom'), 'the machine info names the custom machine');
    assert(await tid('machine-frame').isEnabled(), 'the machine-coordinates toggle is on offer for the custom moving-bed machine');
    await tid('machine-frame').check();
    await page.waitForTimeout(200);
    const vp = page.locator('#canvas-wrap');
    assert((await vp.getAttribute('data-frame')) === 'machine' && (await vp.getAttribute('data-bed')), 'the preview is drawn in machine coordinates with the bed placed');
    await screenshot('custom-ab-machine-frame');
    await tid('machine-frame').uncheck();
    await tid('machine-custom').uncheck();
    await tid('place-on').uncheck();
    await tid('machine-select').selectOption('cartesian');
    await warpSettled();
  });

  await test('custom machine JSON described by the core: pax-5axis with max_tilt_deg 20 caps the tilt and warns at 20° (not the preset\'s 90°); a JSON the core refuses shows its code\'s advice and the form keeps the last valid machine', async () => {
    const { ADVICE } = await import(join(WWW, 'js', 'advice.js'));
    const pax = schema.machines.find((m) => m.name === 'pax-5axis');
    const lowered = JSON.stringify({ ...pax.spec, max_tilt_deg: 20 }, null, 2);
    // What the core says of this JSON (node, same wasm): the page's form must follow it.
    const want = JSON.parse(wasm.describe_machine(lowered));
    assert(want.max_tilt_deg === 20 && pax.max_tilt_deg !== 20 && want.name === 'pax-5axis', `the core describes the lowered JSON with its own limit: ${want.max_tilt_deg} (preset ${pax.max_tilt_deg})`);
    const refused = JSON.stringify({ ...pax.spec, max_tilt_deg: 20, nozzle_colour: 'red' }, null, 2); // an unknown field
    let code = null;
    try {
      wasm.describe_machine(refused);
    } catch (e) {
      code = e.code;
    }
    assert(code && code.startsWith('machine.') && ADVICE[code], `the core refuses an unknown field with a machine.* code the page has advice for: ${code}`);
    const dir = join(TMP, 'custom-described');
    mkdirSync(dir, { recursive: true });
    writeFileSync(join(dir, 'cylinder.stl'), wasm.example_stl('cylinder'));
    await tid('model-input').setInputFiles(join(dir, 'cylinder.stl'));
    await warpSettled();
    await tid('machine-select').selectOption('pax-5axis');
    await tid('warp-select').selectOption('conic');
    await page.locator('#machine-custom-box').evaluate((d) => (d.open = true));
    await tid('machine-json').fill(lowered);
    await tid('machine-json').dispatchEvent('change');
    await page.waitForFunction(() => document.querySelector('#p-conic-angle')?.getAttribute('max') === '20', null, { timeout: 30000 }).catch(async () => {
      throw new Error(`the conic angle is not capped at 20 (max ${await page.locator('#p-conic-angle').getAttribute('max')}; ${await tid('machine-info').innerText()})`);
    });
    // The limits: every degree parameter of every warp it prints capped at 20 (the test of every preset's form).
    await machineForm(page, want);
    assert((await tid('machine-info').innerText()).includes('tilt up to 20°'), `the machine info is the core's for this JSON: ${await tid('machine-info').innerText()}`);
    // The warnings: conic 30° is clamped to 20° and within the limit; a tilted warp of 31° is past it.
    await tid('warp-select').selectOption('conic');
    await setInput('#p-conic-angle', 30);
    assert((await page.locator('#p-conic-angle').inputValue()) === '20', `conic 30° capped at 20: ${await page.locator('#p-conic-angle').inputValue()}`);
    await warpSettled();
    const within = await tid('warnings').innerText();
    assert(/Within pax-5axis's tilt limits/.test(within) && Math.abs(Number(await page.locator('#warp-info').getAttribute('data-largest-tilt')) - 20) < 1e-6, `conic 20° is within the custom machine's limits: ${within}`);
    await tid('warp-select').selectOption('tilted');
    await setInput('#p-tilted-strength', 0.6);
    await warpSettled();
    const past = await tid('warnings').innerText();
    assert(/need up to 31\.0° of tilt; pax-5axis reaches 20°/.test(past), `the tilt warning says 20°: ${past}`);
    await screenshot('custom-described-20');
    // A JSON the core refuses: its error and the advice for its code; the form keeps the last
    // machine the core accepted (the cap stays at 20, not the preset's 90).
    await tid('warp-select').selectOption('conic');
    await tid('machine-json').fill(refused);
    await tid('machine-json').dispatchEvent('change');
    const err = await shownError();
    assert(err.code === code && err.key === code && err.advice === `What to do: ${ADVICE[code]}`, `the error box shows ${code} with its advice: ${JSON.stringify(err)}`);
    assert(err.message.includes('nozzle_colour'), `the core's message as it is: ${err.message}`);
    assert((await page.locator('#p-conic-angle').getAttribute('max')) === '20', 'the form keeps the last valid custom machine (cap 20)');
    assert(/refused/.test(await tid('machine-info').innerText()), `the machine info says the JSON is refused: ${await tid('machine-info').innerText()}`);
    await setInput('#p-conic-angle', 15); // the form still works: a re-warp leaves the machine's error shown
    await warpSettled();
    assert((await tid('error').isVisible()) && (await tid('error').getAttribute('data-code')) === code, 'the refusal stays shown while the JSON is refused');
    await screenshot('custom-described-refused');
    // Fixed: the error goes; switched off: the preset again.
    await tid('machine-json').fill(lowered);
    await tid('machine-json').dispatchEvent('change');
    await page.waitForSelector('[data-testid="error"][hidden]', { state: 'attached', timeout: 30000 });
    await tid('machine-custom').uncheck();
    assert((await page.locator('#p-conic-angle').getAttribute('max')) === String(pax.max_tilt_deg), 'switched off: the preset\'s limit');
    await tid('machine-select').selectOption('cartesian');
    await warpSettled();
  });

  await test('the service worker caches every module of the page', async () => {
    const sw = readFileSync(join(WWW, 'sw.js'), 'utf8');
    const mods = readdirSync(join(WWW, 'js')).filter((f) => f.endsWith('.js'));
    assert(mods.length > 5, `the page's modules: ${mods}`);
    for (const f of [...mods.map((m) => `./js/${m}`), './worker.js', './index.html', './style.css']) assert(sw.includes(`'${f}'`), `sw.js caches ${f}`);
    for (const [, f] of sw.matchAll(/'\.\/(js\/[\w-]+\.js)'/g)) assert(existsSync(join(WWW, f)), `sw.js lists ${f}, which exists`);
    const main = await page.evaluate(() => document.querySelector('script[type="module"]').getAttribute('src'));
    assert(main === './js/main.js', `index.html loads the entry module (${main})`);
  });

  await test('service worker: served on localhost it controls the page, and offline (server stopped) the page reloads from its cache and still warps and unwarps, byte-identical to the CLI', async () => {
    await offlineRoundTrip({ www: WWW, cli: CLI, slice, exampleStl: wasm.example_stl('cylinder'), dir: join(TMP, 'offline'), shots: ART });
  });

  await test('service worker: a teacher\'s link offline: the settings in its hash, the STL dropped, "Slice here and unwarp" gives the bytes of `warpslice run --slicer builtin` with those settings', async () => {
    await offlineTeacherLink({ www: WWW, cli: CLI, exampleStl: wasm.example_stl('cylinder'), dir: join(TMP, 'offline-link'), shots: ART });
  });

  await test('error advice is keyed by the core\'s error code: three codes, each with its own advice, unchanged when the message is reworded', async () => {
    const { ADVICE } = await import(join(WWW, 'js', 'advice.js'));
    const codes = new Set(schema.errors.map((e) => e.code));
    for (const k of Object.keys(ADVICE)) assert(k.startsWith('page.') || codes.has(k), `advice for ${k}, a code the core does not have`);
    const dir = join(TMP, 'coded-errors');
    mkdirSync(dir, { recursive: true });
    const stl = join(dir, 'cylinder.stl');
    writeFileSync(stl, wasm.example_stl('cylinder'));
    await tid('model-input').setInputFiles(stl);
    await warpSettled();
    await setConic(30);
    await download('warped-download', join(dir, 'W.stl'));
    await download('job-download', join(dir, 'W.job.json'));
    slice(join(dir, 'W.stl'), join(dir, 'W.gcode'));
    // The slicer's placement, so that a G-code with G91 in the middle gets past registration.
    const run = spawnSync(CLI, ['unwarp', join(dir, 'W.gcode'), '--job', join(dir, 'W.job.json'), '--stl', join(dir, 'W.stl'), '-o', join(dir, 'C.out.gcode')], { encoding: 'utf8' });
    const placed = /registration: translation (\S+) (\S+)/.exec(run.stdout + run.stderr);
    assert(run.status === 0 && placed, `the CLI unwarps the clean G-code: ${run.stderr}`);
    const lines = readFileSync(join(dir, 'W.gcode'), 'utf8').split('\n');
    let at = Math.floor(lines.length * 0.4);
    while (!lines[at].startsWith('G1 ')) at++;
    lines.splice(at, 0, 'G91');
    writeFileSync(join(dir, 'relative.gcode'), lines.join('\n'));
    writeFileSync(join(dir, 'hello.gcode'), 'G28\nG1 X10 Y10 Z0.2 E1 F1200\n');
    writeFileSync(join(dir, 'empty.stl'), '');
    const cases = [
      ['register.no-object-extrusions', () => tid('gcode-input').setInputFiles(join(dir, 'hello.gcode'))],
      ['unwarp.relative-positioning', async () => {
        await tid('offset-on').check();
        await setInput('#p-offset-x', placed[1]);
        await setInput('#p-offset-y', placed[2]);
        await tid('gcode-input').setInputFiles(join(dir, 'relative.gcode'));
      }],
      ['mesh.empty', () => tid('model-input').setInputFiles(join(dir, 'empty.stl'))],
    ];
    const errorWhere = async (pred, arg, what) => {
      await page.waitForFunction(pred, arg, { timeout: 60000 }).catch(async () => {
        throw new Error(`${what}; the page shows ${JSON.stringify(await page.evaluate(() => ({ hidden: document.querySelector('[data-testid="error"]').hidden, text: document.querySelector('[data-testid="error"]').innerText })))}`);
      });
      return shownError();
    };
    const shown = [];
    for (const [code, provoke] of cases) {
      assert(codes.has(code), `${code} is a code of describe().errors`);
      assert(ADVICE[code], `the page has advice for ${code}`);
      await provoke();
      const plain = await errorWhere((c) => { const b = document.querySelector('[data-testid="error"]'); return !b.hidden && b.dataset.code === c; }, code, `an error with the code ${code}`);
      assert(plain.advice === `What to do: ${ADVICE[code]}` && plain.key === code, `${code}: the advice shown is the one for this code: ${JSON.stringify(plain)}`);
      // The same failure with the message reworded on its way from the worker (code kept).
      await page.evaluate(() => {
        const d = Object.getOwnPropertyDescriptor(MessageEvent.prototype, 'data');
        window.__warpsliceData = d;
        Object.defineProperty(MessageEvent.prototype, 'data', {
          configurable: true,
          get() {
            const m = d.get.call(this);
            return m && m.type === 'error' ? { ...m, message: `reworded: something else went wrong (${m.code})` } : m;
          },
        });
      });
      try {
        await provoke();
        const reworded = await errorWhere((c) => { const b = document.querySelector('[data-testid="error"]'); return !b.hidden && b.innerText.includes(`reworded: something else went wrong (${c})`); }, code, `the reworded message of ${code}`);
        assert(reworded.code === code && reworded.advice === plain.advice && reworded.key === code, `${code}: the same advice with the message reworded: ${JSON.stringify(reworded)}`);
        assert(reworded.message !== plain.message, `${code}: the message was reworded (${reworded.message})`);
      } finally {
        await page.evaluate(() => Object.defineProperty(MessageEvent.prototype, 'data', window.__warpsliceData));
      }
      await screenshot(`error-${code}`);
      shown.push(plain.advice);
    }
    assert(new Set(shown).size === cases.length, `each code has its own advice: ${shown.join(' | ')}`);
    await tid('offset-on').uncheck();
  });

  await test('check a G-code: a hand-written cartesian file with a plunge and an X past its travel; findings with their lines, a click moves the preview there, collisions in red, the CLI agrees', async () => {
    const dir = join(TMP, 'check-mode');
    mkdirSync(dir, { recursive: true });
    // a pad of 10 layers of 0.2 mm (lines along Y), then a plunge of the nozzle into it and an
    // X beyond the cartesian preset's travel (X 0…250, read from the schema)
    const xMax = schema.machines.find((m) => m.name === 'cartesian').axes.find((a) => a.name === 'X').max;
    const g = ['M83', ';WIDTH:0.45', 'G1 Z5 F600'];
    for (let k = 1; k <= 10; k++) {
      const z = 0.2 * k;
      g.push(';LAYER_CHANGE');
      for (let x = 10; x < 20; x += 0.45) {
        g.push(`G1 Z${(z + 1).toFixed(3)} F600`, `G1 X${x.toFixed(3)} Y10 F1800`, `G1 Z${z.toFixed(3)} F600`, `G1 X${x.toFixed(3)} Y20 E0.5 F1800`);
      }
    }
    g.push('G1 Z10 F600', 'G1 X15 Y15 F1800');
    const plunge = g.push('G1 Z1.0 F600');
    g.push('G1 Z10 F600');
    const beyond = g.push(`G1 X${xMax + 10} Y15 F1800`);
    const file = join(dir, 'hand.gcode');
    writeFileSync(file, g.join('\n') + '\n');
    const r = spawnSync(CLI, ['check', file, '--machine', 'cartesian', '--json'], { maxBuffer: 1 << 26 });
    assert(r.status === 1, `the CLI exits 1 with findings, not ${r.status}: ${r.stderr}`);
    const rep = JSON.parse(r.stdout.toString());
    await selectMachineSettled({ page, tid, warpSettled }, 'cartesian');
    await tid('check-input').setInputFiles(file);
    await page.waitForFunction(() => document.querySelector('[data-testid="findings"]').dataset.mode === 'check' || !document.querySelector('[data-testid="error"]').hidden, null, { timeout: 120000 });
    assert(!(await tid('error').isVisible()), `the page showed an error: ${await tid('error').innerText()}`);
    const total = rep.counts.reach + rep.counts.collision + rep.counts.speed;
    assert((await tid('findings').getAttribute('data-count')) === String(total), `count ${total}`);
    const items = tid('findings').locator('button[data-line]');
    const lines = await items.evaluateAll((es) => es.map((e) => [Number(e.dataset.line), e.dataset.kind]));
    assert(lines.some(([l, k]) => l === plunge && k === 'collision'), `the plunge (line ${plunge}) is a collision finding: ${JSON.stringify(lines)}`);
    assert(lines.some(([l, k]) => l === beyond && k === 'reach'), `line ${beyond} is a reach finding: ${JSON.stringify(lines)}`);
    assert(Number(await tid('viewport').getAttribute('data-collision-segments')) > 0, 'collisions drawn in red');
    await tid('findings').locator(`button[data-line="${plunge}"][data-kind="collision"]`).first().click();
    assert((await tid('viewport').getAttribute('data-line')) === String(plunge), `the preview moved to line ${plunge}: ${await tid('viewport').getAttribute('data-line')}`);
    await tid('findings').locator(`button[data-line="${beyond}"]`).first().click();
    assert((await tid('viewport').getAttribute('data-line')) === String(beyond), `the preview moved to line ${beyond}`);
    await screenshot('check-mode');
    // unreadable input: the core's code and its advice
    const bad = join(dir, 'bad.gcode');
    writeFileSync(bad, 'G90\nG1 X1 Y1 Z1\nG1 X1.2.3 Y1\n');
    await tid('check-input').setInputFiles(bad);
    const e = await shownError();
    assert(e.code === 'check.bad-number' && e.message.includes('line 3'), `error ${JSON.stringify(e)}`);
  });

  // the head's solids at the current move, every hand-built finding case (tests/head.mjs)
  await headTests({ page, test, tid, assert, CLI, TMP, ROOT, schema, screenshot, warpSettled });

  // Issue 12: the warp step's report warnings (here what the STL reader tolerated: bytes
  // another program appended to a binary STL) are listed on the page as the CLI prints them.
  await test('warp warnings: the page lists the warp report warnings as the CLI prints them', async () => {
    const dir = join(TMP, 'warp-warnings');
    mkdirSync(dir, { recursive: true });
    const p = join(dir, 'cube-tail.stl');
    writeFileSync(p, Buffer.concat([Buffer.from(wasm.example_stl('cube')), Buffer.alloc(73, 'x')]));
    await tid('model-input').setInputFiles(p);
    await warpSettled();
    await setConic(30);
    const cliOut = sh(CLI, ['warp', p, '--warp', 'conic', '--angle', '30', '--direction', 'outward', '-o', join(dir, 'C.stl')]);
    const cliWarnings = cliOut.split('\n').filter((l) => l.startsWith('warning: ')).map((l) => l.slice(9));
    assert(cliWarnings.some((w) => w.includes('73 bytes after the last')), `the CLI warns of the appended bytes: ${cliOut}`);
    const pageWarnings = await tid('warp-warnings').locator('li').allInnerTexts();
    assert(JSON.stringify(pageWarnings) === JSON.stringify(cliWarnings), `page warp warnings ${JSON.stringify(pageWarnings)} vs the CLI's ${JSON.stringify(cliWarnings)}`);
    // a clean model: no warp warnings left from the previous one
    writeFileSync(join(dir, 'cube.stl'), wasm.example_stl('cube'));
    await tid('model-input').setInputFiles(join(dir, 'cube.stl'));
    await warpSettled();
    assert((await tid('warp-warnings').locator('li').count()) === 0, 'no warp warnings for a clean cube');
  });

  // the one-click path: the built-in slicer in the worker, every preset (tests/builtin.mjs)
  await builtinTests({ page, context, url, test, tid, assert, sh, CLI, TMP, wasm, schema, download, warpSettled, screenshot, sha });

  // issue 15: the overhang measure and "Suggest a warp" (tests/suggest.mjs)
  await suggestTests({ page, test, tid, assert, sh, CLI, TMP, wasm, warpSettled, screenshot });

  await test('no request left 127.0.0.1 and no console errors', async () => {
    assert(outside.length === 0, `requests outside 127.0.0.1: ${outside.slice(0, 5).join(', ')}`);
    const bad = consoleErrors.filter((e) => /Content Security Policy|pageerror|Refused/i.test(e));
    assert(bad.length === 0, `console errors: ${bad.slice(0, 5).join(' | ')}`);
  });
} finally {
  await context.close().catch(() => {});
  server.close();
  rmSync(profile, { recursive: true, force: true });
  rmSync(TMP, { recursive: true, force: true });
}



/** The big test's warp: `machine` (a preset brings its own warp), then conic 20° outward, edges ≤ 4 mm. */
async function setBigWarp(machine) {
  await tid('machine-select').selectOption(machine);
  await warpSettled();
  await tid('warp-select').selectOption('conic');
  await page.locator('#p-conic-angle').fill('20');
  await page.locator('#p-conic-angle').dispatchEvent('change');
  await page.locator('#p-conic-direction').selectOption('outward');
  await page.locator('#p-max_edge').fill('4');
  await page.locator('#p-max_edge').dispatchEvent('change');
  await warpSettled();
}

/**
 * The native CLI's `warpslice unwarp` with the page's own command line (its summary's
 * `cli.unwarp`, file names replaced by these paths), under /usr/bin/time: `{ seconds` (wall),
 * `cpu_seconds`, `peak_rss_bytes }`. Throws with the CLI's stderr when it fails.
 */
function timedCliUnwarp(cliUnwarp, { gcode, job, stl, out }) {
  const args = cliUnwarp.slice(2); // after `warpslice unwarp`
  args[0] = gcode;
  const at = (flag, v) => {
    const i = args.indexOf(flag);
    assert(i > 0, `the page's command line has ${flag}: ${cliUnwarp.join(' ')}`);
    args[i + 1] = v;
  };
  at('--job', job);
  at('--stl', stl);
  at('-o', out);
  const timeFile = join(TMP, 'cli.time');
  const ts = Date.now();
  const r = spawnSync('/usr/bin/time', ['-f', '%e %U %S %M', '-o', timeFile, CLI, 'unwarp', ...args], { encoding: 'utf8', maxBuffer: 1 << 26 });
  const wall = (Date.now() - ts) / 1000;
  if (r.status !== 0) throw new Error(`the CLI failed (${r.status}): warpslice unwarp ${args.join(' ')}\n${r.stderr}`);
  const [, user, sys, kib] = readFileSync(timeFile, 'utf8').trim().split(/\s+/).map(Number);
  return { seconds: wall, cpu_seconds: user + sys, peak_rss_bytes: kib * 1024 };
}

/** The longest main-thread task (PerformanceObserver 'longtask') since `since` that overlaps no WebGL frame the page measured (`warpslice-frame`), ms, and the longest overall. */
async function longestTasks(since) {
  return page.evaluate((t0) => {
    const frames = window.__frames.filter((f) => f.end >= t0);
    let outside = 0, all = 0;
    for (const t of window.__tasks) {
      if (t.start < t0) continue;
      all = Math.max(all, t.duration);
      const end = t.start + t.duration;
      if (!frames.some((f) => f.start < end && t.start < f.end)) outside = Math.max(outside, t.duration);
    }
    return { outside: Math.round(outside), all: Math.round(all) };
  }, since);
}

/**
 * The big G-code dropped on the page with the form as it is, then the same unwarp by the native
 * CLI (the page's own command line, its job and warped STL): asserts the two outputs are
 * byte-identical, and returns the figures (printed, not asserted: speed and memory are
 * measured, not tested): browser and CLI seconds and their ratio, the worker's wasm memory
 * above its idle size, the page's longest main-thread task outside WebGL frames.
 */
async function bigRun(label, gcode, dir) {
  const cdp = await context.newCDPSession(page);
  await cdp.send('Performance.enable');
  let peakHeap = 0;
  const sample = async () => {
    const m = await cdp.send('Performance.getMetrics');
    peakHeap = Math.max(peakHeap, m.metrics.find((x) => x.name === 'JSHeapUsedSize')?.value ?? 0);
  };
  // Long tasks on the page's main thread (JS, layout, WebGL command submission), and the WebGL
  // frames the page measures (view.js), to tell the two apart.
  const since = await page.evaluate(() => {
    if (!window.__tasks) {
      window.__tasks = [];
      window.__frames = [];
      new PerformanceObserver((l) => {
        for (const e of l.getEntries()) window.__tasks.push({ start: e.startTime, duration: e.duration });
      }).observe({ type: 'longtask' });
      new PerformanceObserver((l) => {
        for (const e of l.getEntries()) if (e.name === 'warpslice-frame') window.__frames.push({ start: e.startTime, end: e.startTime + e.duration });
      }).observe({ type: 'measure' });
    }
    return performance.now();
  });
  const ts = Date.now();
  let done = false;
  const run = unwarpInBrowser(gcode).finally(() => (done = true));
  let responsiveDuring = 0; // while the worker streams (the first WebGL frame afterwards is separate)
  while (!done) {
    await sample();
    const t = Date.now();
    await page.evaluate(() => 1);
    const rt = Date.now() - t;
    if ((await tid('progress').getAttribute('data-done')) !== '1') responsiveDuring = Math.max(responsiveDuring, rt);
    await new Promise((r) => setTimeout(r, 250));
  }
  await run;
  const browserS = (Date.now() - ts) / 1000;
  await sample();
  const num = async (a) => Number(await tid('progress').getAttribute(a));
  // the worker reports its wasm linear memory (at the end: it never shrinks) + preview buffers,
  // and the module's idle size (right after instantiation; a fresh page, a fresh worker)
  const workerPeak = await num('data-worker-bytes');
  const workerIdle = await num('data-idle-bytes');
  const unwarpMs = await num('data-unwarp-ms');
  const checkMs = await num('data-check-ms');
  const afterMs = await num('data-after-ms');
  await page.waitForTimeout(500);
  const tasks = await longestTasks(since);
  const outPath = join(dir, 'B.out.gcode');
  const [dl] = await Promise.all([page.waitForEvent('download'), tid('result-download').click()]);
  await dl.saveAs(outPath);
  const job = join(dir, 'B.job.json');
  const wstl = join(dir, 'B.stl');
  await download('job-download', job);
  await download('warped-download', wstl);
  const summary = JSON.parse(await download('summary-download', join(dir, 'B.summary.json')));
  const cliOut = join(dir, 'C.out.gcode');
  const cli = timedCliUnwarp(summary.cli.unwarp, { gcode, job, stl: wstl, out: cliOut });
  const [b, c] = [readFileSync(outPath), readFileSync(cliOut)];
  rmSync(outPath);
  rmSync(cliOut);
  assert(b.equals(c), `${label}: the browser's G-code (${b.length} B, ${sha(b)}) is the CLI's (${c.length} B, ${sha(c)}): ${summary.cli.unwarp.join(' ')}`);
  // The summary download lists every collision the file ends with (the page itself gets the
  // long lists cut, the summary has the worker's whole ones spliced in: worker.js pageLists).
  const mark = Buffer.from('\n; warpslice collision: line ');
  let listedInFile = 0;
  for (let at = b.indexOf(mark); at >= 0; at = b.indexOf(mark, at + 1)) listedInFile++;
  const inSummary = summary.report.machine?.collisions?.length ?? 0;
  assert(inSummary === listedInFile, `${label}: the summary lists ${inSummary} collisions, the file ${listedInFile}`);
  const f = {
    cli: summary.cli.unwarp.join(' '), output_bytes: b.length, output_sha: sha(b), collisions_listed: listedInFile,
    browser_s: browserS, browser_unwarp_s: unwarpMs / 1000, browser_check_s: checkMs / 1000, browser_after_done_s: afterMs / 1000,
    native_s: cli.seconds, native_cpu_s: cli.cpu_seconds, native_peak_rss_bytes: cli.peak_rss_bytes,
    ratio: browserS / cli.seconds,
    worker_idle_bytes: workerIdle, worker_peak_bytes: workerPeak, worker_above_idle_bytes: workerPeak - workerIdle,
    peak_page_heap_bytes: peakHeap,
    longest_task_outside_frames_ms: tasks.outside, longest_task_ms: tasks.all, slowest_page_roundtrip_unwarping_ms: responsiveDuring,
  };
  const mib = (x) => (x / 2 ** 20).toFixed(1);
  console.log(`     BIG ${label}: browser ${browserS.toFixed(1)} s (unwarp ${f.browser_unwarp_s.toFixed(1)} s, check ${f.browser_check_s.toFixed(1)} s, preview ${f.browser_after_done_s.toFixed(1)} s), ` +
    `native CLI ${cli.seconds.toFixed(1)} s wall (${cli.cpu_seconds.toFixed(1)} s CPU, ${mib(cli.peak_rss_bytes)} MiB RSS): ×${f.ratio.toFixed(2)}; ` +
    `output ${(b.length / 1e6).toFixed(1)} MB identical; worker ${mib(workerPeak)} MiB = idle ${mib(workerIdle)} + ${mib(f.worker_above_idle_bytes)} MiB; ` +
    `page heap ${mib(peakHeap)} MiB; longest main-thread task outside WebGL frames ${tasks.outside} ms (with frames ${tasks.all} ms); slowest page round-trip while unwarping ${responsiveDuring} ms`);
  return f;
}
function makeCylinder(out, R, H, N) {
  const tris = [];
  const p = (i, z) => [R * Math.cos((2 * Math.PI * (i % N)) / N), R * Math.sin((2 * Math.PI * (i % N)) / N), z];
  for (let i = 0; i < N; i++) {
    const a0 = p(i, 0), a1 = p(i + 1, 0), b0 = p(i, H), b1 = p(i + 1, H);
    tris.push([a0, a1, b1], [a0, b1, b0], [[0, 0, 0], a1, a0], [[0, 0, H], b0, b1]);
  }
  const buf = Buffer.alloc(84 + 50 * tris.length);
  buf.write('warpslice test cylinder', 0);
  buf.writeUInt32LE(tris.length, 80);
  tris.forEach((t, k) => {
    let o = 84 + 50 * k + 12;
    for (const v of t) for (const c of v) {
      buf.writeFloatLE(c, o);
      o += 4;
    }
  });
  writeFileSync(out, buf);
}

console.log(`web tests took ${((Date.now() - t0all) / 1000).toFixed(0)} s`);
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
