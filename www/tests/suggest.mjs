// Issue 15 in the page: the overhang measure and "Suggest a warp" against the CLI's
// `warpslice overhangs --json` and `warpslice suggest --json` of the same model and machine.
//
//  - planar: the page's overhang area is the CLI's, and the view colours exactly the CLI's
//    overhanging facets (their count);
//  - "Suggest a warp" on pax-5axis lists the CLI's suggestions in its order (flags and areas);
//  - "Apply" on the best one puts its warp into the form (the page re-warps): the page's warped
//    overhang area and coloured facets are then the CLI's `overhangs` under those flags;
//  - the tilt map: with a warp applied, each facet is coloured by the tool tilt at its centroid
//    that `warpslice overhangs … --json` gives (`warped_tilts_deg`: count, Σ (i + 1)·tilt and
//    the largest the same), facets beyond the machine's limit counted alike, the limit in the
//    legend;
//  - the field warp's expression box: a typed expression is checked as it is typed, and the
//    overhang area shown under the box is the CLI's `overhangs --warp field --expr … --json`;
//    an expression the core refuses shows the core's error code under the box.
//
// Used by tests/run.mjs, which passes its page and helpers (`ctx`).
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';

/** The machine the suggestions are asked for (a tilt limit of 90°: every family admissible). */
const MACHINE = 'pax-5axis';
/** The tilt map's warp: a bowl with its low point off centre (tilts from 0° to ~40° on the part). */
const TILT_MAP_EXPR = '0.02*(x^2 + y^2) - 0.5*x';
/** Areas compare to the CLI's within this, mm²: the same core, native vs wasm (bit-equal here). */
const AREA_TOL = 1e-6;

export async function suggestTests(ctx) {
  const { page, test, tid, assert, sh, CLI, TMP, wasm, warpSettled, screenshot } = ctx;
  const stl = join(TMP, 'overhang.stl');
  writeFileSync(stl, wasm.example_stl('overhang'));
  const cli = (args) => JSON.parse(sh(CLI, args).toString());
  const shown = async (attr) => page.locator('[data-testid="overhang-info"]').getAttribute(`data-${attr}`);
  const colouredFacets = async () => Number(await page.locator('#canvas-wrap').getAttribute('data-overhang-facets'));
  const ones = (flags) => flags.reduce((a, b) => a + b, 0);

  await test('overhangs: the page measures and colours the planar overhang as `warpslice overhangs`', async () => {
    await tid('machine-select').selectOption(MACHINE);
    await tid('model-input').setInputFiles(stl);
    await warpSettled();
    await page.waitForFunction(() => document.querySelector('[data-testid="overhang-info"]').dataset.planarMm2, null, { timeout: 60000 });
    const planar = cli(['overhangs', stl, '--json']);
    const got = Number(await shown('planar-mm2'));
    assert(Math.abs(got - planar.planar.area_mm2) <= AREA_TOL, `planar overhang: page ${got} mm², CLI ${planar.planar.area_mm2} mm²`);
    assert(planar.planar.area_mm2 > 0, 'the overhang part overhangs planar');
  });

  await test('overhangs: "Suggest a warp" lists `warpslice suggest`\'s warps in order, and Apply re-warps with the best one', async () => {
    await tid('suggest-button').click();
    await page.waitForFunction(() => document.querySelector('[data-testid="suggestions"]').dataset.done === '1', null, { timeout: 120000 });
    const want = cli(['suggest', stl, '--machine', MACHINE, '--json']);
    const items = await tid('suggestions').locator('li').evaluateAll((ls) => ls.map((l) => ({ flags: l.dataset.flags, area: Number(l.dataset.areaMm2) })));
    assert(want.length > 0, 'the CLI suggests at least one warp for the overhang part');
    assert(items.length === want.length, `page lists ${items.length} suggestions, CLI ${want.length}`);
    items.forEach((it, i) => {
      assert(it.flags === want[i].flags, `suggestion ${i + 1}: page “${it.flags}”, CLI “${want[i].flags}”`);
      assert(Math.abs(it.area - want[i].overhang_area_mm2) <= AREA_TOL, `suggestion ${i + 1}: page ${it.area} mm², CLI ${want[i].overhang_area_mm2} mm²`);
    });
    await screenshot('suggestions');
    await tid('suggestion-apply-1').click();
    await warpSettled();
    await page.waitForFunction((f) => document.querySelector('[data-testid="overhang-info"]').dataset.flags === f, want[0].flags, { timeout: 60000 });
    const under = cli(['overhangs', stl, ...want[0].flags.split(' '), '--json']);
    const got = Number(await shown('warped-mm2'));
    assert(Math.abs(got - under.warped.area_mm2) <= AREA_TOL, `after Apply: page ${got} mm² left, CLI overhangs ${want[0].flags}: ${under.warped.area_mm2} mm²`);
    assert(Math.abs(got - want[0].overhang_area_mm2) <= AREA_TOL, `after Apply: page ${got} mm², suggestion 1 said ${want[0].overhang_area_mm2} mm²`);
    const n = await colouredFacets();
    assert(n === ones(under.warped_facets), `coloured facets ${n}, CLI's overhanging facets under the warp ${ones(under.warped_facets)}`);
    assert(ones(under.warped_facets) < ones(under.planar_facets), 'the best warp leaves fewer overhanging facets than planar');
    await screenshot('suggestion-applied');
    // switched off, nothing is coloured
    await tid('show-overhangs').setChecked(false);
    assert((await page.locator('#canvas-wrap').getAttribute('data-overhang-facets')) === null, 'colouring off');
    await tid('show-overhangs').setChecked(true);
  });

  await test('overhangs: the tilt map colours each facet by the tool tilt `warpslice overhangs --json` gives it, the machine\'s limit in the legend', async () => {
    // a bowl field: the tilt differs from facet to facet (a cone's is the same everywhere)
    await tid('warp-select').selectOption('field');
    await tid('param-expr').fill(TILT_MAP_EXPR);
    await page.locator('#warp-params').dispatchEvent('change');
    await warpSettled();
    await page.waitForFunction(() => document.querySelector('[data-testid="overhang-info"]').dataset.flags?.includes('--warp field'), null, { timeout: 60000 });
    const flags = await shown('flags');
    const want = cli(['overhangs', stl, '--warp', 'field', '--expr', TILT_MAP_EXPR, '--json']).warped_tilts_deg;
    assert(flags.includes(TILT_MAP_EXPR), `the page applied ${flags}`);
    assert(new Set(want.map((t) => t.toFixed(3))).size > 10, 'the test warp tilts the facets differently');
    await tid('show-tilt-map').setChecked(true);
    await page.waitForFunction(() => document.querySelector('#canvas-wrap').dataset.tiltFacets, null, { timeout: 60000 });
    const d = await page.locator('#canvas-wrap').evaluate((w) => ({ ...w.dataset }));
    assert(Number(d.tiltFacets) === want.length, `tilt map: ${d.tiltFacets} facets coloured, CLI ${want.length}`);
    // Σ (i + 1)·tilt_i: each facet's own tilt, in the STL's order
    const sum = want.reduce((a, t, i) => a + (i + 1) * t, 0);
    assert(Math.abs(Number(d.tiltChecksum) - sum) <= 1e-9 * Math.max(1, sum), `tilt map: page Σ(i+1)·tilt ${d.tiltChecksum}, CLI ${sum}`);
    assert(Math.abs(Number(d.tiltMax) - Math.max(...want)) <= 1e-9, `largest facet tilt: page ${d.tiltMax}°, CLI ${Math.max(...want)}°`);
    assert(Math.max(...want) > 1, `the applied warp tilts the tool (${Math.max(...want)}°)`);
    const limit = JSON.parse(readFileSync(new URL(`../../presets/${MACHINE}.json`, import.meta.url), 'utf8')).max_tilt_deg;
    const beyond = want.filter((t) => t > limit + 1e-6).length;
    assert(Number(d.tiltOverLimit) === beyond, `facets beyond the ${limit}° limit: page ${d.tiltOverLimit}, CLI ${beyond}`);
    const legend = await tid('legend-tilt-limit').textContent();
    assert(legend.includes(`machine limit ${limit}°`), `legend: “${legend}”`);
    // the overhang colouring is replaced while the map is on, and back when it is off
    assert(d.overhangFacets === undefined, 'tilt map on: no overhang colouring');
    await screenshot('tilt-map');
    await tid('show-tilt-map').setChecked(false);
    assert((await page.locator('#canvas-wrap').getAttribute('data-tilt-facets')) === null, 'tilt map off');
  });

  await test('overhangs: the field warp\'s expression box shows the CLI\'s overhang area, or the core\'s error code', async () => {
    await tid('warp-select').selectOption('field');
    const box = tid('param-expr');
    const status = page.locator('[data-testid="field-check"]');
    // the check of exactly `expr` has answered
    const settle = async (expr) => page.waitForFunction((e) => {
      const d = document.querySelector('[data-testid="field-check"]')?.dataset;
      return d && d.expr === e && d.state !== 'checking';
    }, expr, { timeout: 60000 });
    // a bowl that tilts the ledges of the overhang part: the area differs from planar
    const expr = '0.02*(x^2 + y^2) - 0.5*x';
    await box.fill(expr);
    await settle(expr);
    assert((await status.getAttribute('data-state')) === 'ok', `field ${expr}: ${await status.textContent()}`);
    const want = cli(['overhangs', stl, '--warp', 'field', '--expr', expr, '--json']);
    const got = Number(await status.getAttribute('data-warped-mm2'));
    assert(Math.abs(got - want.warped.area_mm2) <= AREA_TOL, `field ${expr}: page ${got} mm², CLI ${want.warped.area_mm2} mm²`);
    assert(Math.abs(want.warped.area_mm2 - want.planar.area_mm2) > 1, `the test's field changes the overhang (${want.warped.area_mm2} vs planar ${want.planar.area_mm2} mm²)`);
    await screenshot('field-expression');
    for (const [bad, code] of [['0.02*(x^2 + y', 'warp.expression-unparsable'], ['x*t', 'warp.expression-unknown-variable'], ['40*x', 'warp.field-too-steep']]) {
      await box.fill(bad);
      await settle(bad);
      const shownCode = await status.getAttribute('data-code');
      const text = await status.textContent();
      assert(shownCode === code && text.startsWith(code), `field ${bad}: under the box “${text}” (code ${shownCode}), want ${code}`);
    }
  });
}
