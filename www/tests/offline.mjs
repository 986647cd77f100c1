// The service worker, for real: the page registers it only on https or http://localhost, so
// this test serves www/ on http://localhost:PORT (its own server and browser, apart from the
// 127.0.0.1 run of tests/run.mjs), waits until the worker controls the page, stops the server
// (the network is gone: nothing answers on the port), reloads, and checks that the app starts
// from the cache and still does its job offline: warps the generated cylinder (conic 30°) and
// unwarps the G-code prusa-slicer made of it, byte-identical to the CLI.
//
// The teacher's link, offline (issue 14): the same served-then-stopped page sets a machine, a
// warp and built-in slicer settings; the link it writes (settings in the URL hash) opens in a
// fresh tab with the network gone, the generated cylinder is dropped on it, "Slice here and
// unwarp" runs, and the planar and machine G-code are byte-identical to `warpslice run
// --slicer builtin` with the same settings (`--set key=value`, `--keep-sliced`).
//
// Used by tests/run.mjs (tests 'service worker: …'); alone:
//   node www/tests/offline.mjs      (needs www/pkg, www/vendor, the CLI in $CARGO_TARGET_DIR)
import { chromium } from 'playwright-core';
import { execFileSync } from 'node:child_process';
import { mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { startServer } from '../scripts/serve.mjs';
import { setSlicer, sliceHereOn } from './builtin.mjs';

function assert(cond, msg) {
  if (!cond) throw new Error(`assertion failed: ${msg}`);
}

/**
 * Serves `www` on localhost in a browser of its own until the service worker controls the page,
 * stops the server, reloads the page offline and runs `fn({ context, page, tid, download })` on
 * it; then checks that no request reached the server after it stopped and that the page raised
 * no error.
 */
async function offlinePage(www, shots, fn) {
  const { server, port } = await startServer(www, 0);
  let served = 0;
  server.on('request', () => served++);
  const url = `http://localhost:${port}/`;
  const profile = mkdtempSync(join(tmpdir(), 'warpslice-sw-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    acceptDownloads: true,
    serviceWorkers: 'allow',
    viewport: { width: 1280, height: 720 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
      '--disable-sync', '--no-first-run', '--disable-quic'],
  });
  let serverUp = true;
  const stopServer = async () => {
    if (!serverUp) return;
    serverUp = false;
    server.closeAllConnections();
    await new Promise((r) => server.close(r));
  };
  try {
    const page = context.pages()[0] ?? (await context.newPage());
    const errors = [];
    page.on('pageerror', (e) => errors.push(`pageerror: ${e.message}`));
    const tid = (id) => page.locator(`[data-testid="${id}"]`);
    const download = async (testid, dest) => {
      const [dl] = await Promise.all([page.waitForEvent('download'), tid(testid).click()]);
      await dl.saveAs(dest);
      return readFileSync(dest);
    };

    // Online: the page loads and its service worker takes control.
    await page.goto(url);
    await page.waitForSelector('body[data-ready="1"]', { timeout: 60000 });
    await page.waitForFunction(() => navigator.serviceWorker?.controller?.state === 'activated', null, { timeout: 60000 })
      .catch(() => { throw new Error(`the service worker never controlled ${url}`); });
    const onlineHits = served;
    assert(onlineHits > 0, 'the page was served');

    // The network goes away: nothing listens on the port any more.
    await stopServer();
    const refused = await fetch(url).then(() => false, () => true);
    assert(refused, `${url} still answers after the server stopped`);

    // Offline: the reload comes from the service worker's cache, and the app starts.
    await page.reload();
    await page.waitForSelector('body[data-ready="1"]', { timeout: 60000 }).catch(async () => {
      const err = await page.evaluate(() => document.querySelector('[data-testid="error"]')?.innerText ?? '');
      throw new Error(`the app did not start offline (the page shows: ${JSON.stringify(err)})`);
    });
    assert(await page.evaluate(() => navigator.serviceWorker.controller !== null), 'the reloaded page is controlled by the service worker');
    if (shots) await page.screenshot({ path: join(shots, 'offline-loaded.png') });
    await fn({ context, page, tid, download });
    assert(served === onlineHits, `no request reached the server after it stopped (${served - onlineHits})`);
    assert(errors.length === 0, `no page errors offline: ${errors.slice(0, 3).join(' | ')}`);
  } finally {
    await context.close().catch(() => {});
    await stopServer();
    rmSync(profile, { recursive: true, force: true });
  }
}

/** Waits until the page's warp is done and no debounced re-warp is pending. */
async function warpSettled(page) {
  await page.waitForFunction(() => {
    const a = document.querySelector('[data-testid="warped-download"]');
    return a && !a.classList.contains('disabled') && document.getElementById('warp-info').textContent !== 'warping…';
  }, null, { timeout: 120000 });
  await page.waitForTimeout(450); // a debounced re-warp may still be scheduled
  await page.waitForFunction(() => !document.querySelector('[data-testid="warped-download"]').classList.contains('disabled'), null, { timeout: 120000 });
}

/** Sets the cartesian machine and the conic 30° outward warp in `page`. */
async function conic30(page) {
  const tid = (id) => page.locator(`[data-testid="${id}"]`);
  await tid('machine-select').selectOption('cartesian');
  await tid('warp-select').selectOption('conic');
  await page.locator('#p-conic-angle').fill('30');
  await page.locator('#p-conic-angle').dispatchEvent('change');
  await page.locator('#p-conic-direction').selectOption('outward');
  await warpSettled(page);
}

/**
 * Runs the offline check. `www`: the app's folder; `cli`: the warpslice binary; `slice(stl,
 * gcode)`: slices with prusa-slicer; `exampleStl`: the bytes of the generated cylinder;
 * `dir`: a scratch folder; `shots`: where screenshots go (or null).
 */
export async function offlineRoundTrip({ www, cli, slice, exampleStl, dir, shots = null }) {
  mkdirSync(dir, { recursive: true });
  await offlinePage(www, shots, async ({ page, tid, download }) => {
    // Its main job, offline: warp the generated cylinder with a conic 30° warp…
    await tid('example-select').selectOption('cylinder');
    await conic30(page);
    const wStl = await download('warped-download', join(dir, 'W.stl'));
    const wJob = await download('job-download', join(dir, 'W.job.json'));
    writeFileSync(join(dir, 'cylinder.stl'), exampleStl);
    execFileSync(cli, ['warp', join(dir, 'cylinder.stl'), '--warp', 'conic', '--angle', '30', '--direction', 'outward', '-o', join(dir, 'C.stl')]);
    assert(wStl.equals(readFileSync(join(dir, 'C.stl'))), `offline: the warped STL (${wStl.length} B) is the CLI's`);
    assert(JSON.stringify(JSON.parse(wJob)) === JSON.stringify(JSON.parse(readFileSync(join(dir, 'C.job.json')))), 'offline: the job is the CLI\'s');

    // …and unwarp the slicer's G-code of it in the worker.
    slice(join(dir, 'W.stl'), join(dir, 'W.gcode'));
    execFileSync(cli, ['unwarp', join(dir, 'W.gcode'), '--job', join(dir, 'C.job.json'), '--stl', join(dir, 'C.stl'), '-o', join(dir, 'C.out.gcode')]);
    await tid('gcode-input').setInputFiles(join(dir, 'W.gcode'));
    await page.waitForFunction(() => {
      const p = document.querySelector('[data-testid="progress"]');
      const err = document.querySelector('[data-testid="error"]');
      return p.dataset.done === '1' || !err.hidden;
    }, null, { timeout: 300000 });
    if (await tid('error').isVisible()) throw new Error(`offline: the page showed an error: ${await tid('error').innerText()}`);
    const out = await download('result-download', join(dir, 'B.out.gcode'));
    const want = readFileSync(join(dir, 'C.out.gcode'));
    assert(out.length > 100000 && out.equals(want), `offline: the unwarped G-code (${out.length} B) is byte-identical to the CLI's (${want.length} B)`);
    if (shots) await page.screenshot({ path: join(shots, 'offline-unwarped.png') });
  });
}

/** The slicer settings of the teacher's link (not the defaults), and as the CLI's arguments. */
const LINK_SETTINGS = { fill_density: 30, perimeters: 3, skirts: 0 };

/**
 * The teacher's link offline (see the top of the file): `www`, `cli`, `exampleStl`, `dir`,
 * `shots` as for `offlineRoundTrip`.
 */
export async function offlineTeacherLink({ www, cli, exampleStl, dir, shots = null }) {
  mkdirSync(dir, { recursive: true });
  const stl = join(dir, 'cylinder.stl');
  writeFileSync(stl, exampleStl);
  const sets = Object.entries(LINK_SETTINGS).flatMap(([k, v]) => ['--set', `${k}=${v}`]);
  execFileSync(cli, ['run', stl, '--slicer', 'builtin', ...sets, '--warp', 'conic', '--angle', '30', '--direction', 'outward',
    '--keep-sliced', join(dir, 'C.sliced.gcode'), '-o', join(dir, 'C.gcode')], { stdio: ['ignore', 'pipe', 'pipe'] });
  await offlinePage(www, shots, async ({ context, page }) => {
    // the teacher, offline: the model, then machine, warp and slicer settings; the page writes
    // them to its hash (a warp needs a model: without one the form is never settled)
    await page.locator('[data-testid="model-input"]').setInputFiles(stl);
    await warpSettled(page);
    await conic30(page);
    await setSlicer(page, LINK_SETTINGS);
    const link = page.url();
    assert(link.includes('#') && link.includes('fill_density'), `the page's link carries the settings: ${link}`);
    // a student's fresh tab opens the link with the network gone
    const fresh = await context.newPage();
    try {
      await fresh.goto(link);
      await fresh.waitForSelector('body[data-ready="1"]', { timeout: 60000 });
      assert(await fresh.evaluate(() => navigator.serviceWorker.controller !== null), 'the link\'s page is controlled by the service worker');
      const tid = (id) => fresh.locator(`[data-testid="${id}"]`);
      await tid('model-input').setInputFiles(stl);
      await warpSettled(fresh);
      await sliceHereOn(fresh);
      if (await tid('error').isVisible()) throw new Error(`the link's page showed an error: ${await tid('error').innerText()}`);
      const get = async (testid, dest) => {
        const [dl] = await Promise.all([fresh.waitForEvent('download'), tid(testid).click()]);
        await dl.saveAs(dest);
        return readFileSync(dest);
      };
      const planar = await get('sliced-download', join(dir, 'B.sliced.gcode'));
      const cliPlanar = readFileSync(join(dir, 'C.sliced.gcode'));
      assert(planar.length > 10000 && planar.equals(cliPlanar), `offline link: the planar G-code (${planar.length} B) is the CLI's --keep-sliced (${cliPlanar.length} B)`);
      const out = await get('result-download', join(dir, 'B.gcode'));
      const want = readFileSync(join(dir, 'C.gcode'));
      assert(out.length > 10000 && out.equals(want), `offline link: the machine G-code (${out.length} B) is byte-identical to \`warpslice run --slicer builtin\` (${want.length} B)`);
      if (shots) await fresh.screenshot({ path: join(shots, 'offline-teacher-link.png') });
    } finally {
      await fresh.close();
    }
  });
}

// Alone: node www/tests/offline.mjs
if (import.meta.url === pathToFileURL(process.argv[1]).href) {
  const www = resolve(dirname(fileURLToPath(import.meta.url)), '..');
  const root = resolve(www, '..');
  const target = process.env.CARGO_TARGET_DIR ? resolve(process.env.CARGO_TARGET_DIR) : join(root, 'target');
  const cli = process.env.WARPSLICE_CLI ? resolve(process.env.WARPSLICE_CLI) : join(target, 'release', 'warpslice');
  const wasm = await import(join(www, 'pkg', 'warpslice.js'));
  await wasm.default({ module_or_path: readFileSync(join(www, 'pkg', 'warpslice_bg.wasm')) });
  const dir = mkdtempSync(join(tmpdir(), 'warpslice-offline-'));
  const t0 = Date.now();
  try {
    await offlineRoundTrip({
      www, cli, dir, exampleStl: wasm.example_stl('cylinder'),
      slice: (stl, gcode) => execFileSync('bash', [resolve(root, '..', 'shared', 'tools', 'slice.sh'), 'prusaslicer', 'rel', stl, gcode], { stdio: ['ignore', 'pipe', 'pipe'] }),
    });
    console.log(`ok   service worker: offline round trip (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
    await offlineTeacherLink({ www, cli, dir: join(dir, 'link'), exampleStl: wasm.example_stl('cylinder') });
    console.log(`ok   service worker: a teacher's link offline (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
    console.log('2 passed, 0 failed');
  } catch (e) {
    console.log(`FAIL service worker: ${e.stack || e}`);
    console.log('0 passed, 1 failed');
    process.exitCode = 1;
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}
