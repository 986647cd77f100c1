// The head's solids on the page (issue 10 §4) and every hand-built finding case of issue 10 §5
// through the page's "Check a G-code".
//
//  - head: at the move a clicked finding selects, the drawn nozzle's tip is that move's tip and
//    its axis the move's tool axis, both computed here from the G-code's own words with the
//    machines' closed-form forward kinematics (docs/machines.md: the B head of seed 000, the A/B
//    table of seed 004), not with the core; the legend lists exactly the head parts the CLI's
//    `warpslice check --json` checked (`head_parts`); the parts of the CLI's findings on that
//    line are drawn red, the others not;
//  - cases: the files of `cargo run --example finding_cases` (the Rust tests' own builders),
//    each dropped into "Check a G-code" with its machine: the page shows exactly the findings
//    (kind, line, part or axis) of `warpslice check --json` of the same file, its preview marks
//    exactly the CLI's collision lines and parts, and "no findings" for the clean files.
//
// Used by tests/run.mjs, which passes its page and helpers (`ctx`).
import { execFileSync, spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { basename, join } from 'node:path';

/** How far the drawn nozzle's tip may be from the move's tip, mm (the preview keeps f32 axes). */
export const TIP_MM = 0.01;
/** How far the drawn nozzle's axis may be from the move's tool axis, degrees. */
export const AXIS_DEG = 0.1;

/**
 * The machine's axis values after file line `line` (1-based) of `text`: G0/G1 words of the
 * machine's letters, absolute (G90) or relative (G91), `G92` shifting what is written from the
 * position (raw = written + offset); missing axes keep their value (0 before the first).
 */
export function axesAtLine(text, letters, line) {
  const raw = letters.map(() => 0), offset = letters.map(() => 0);
  let relative = false;
  const lines = text.split('\n');
  for (let k = 0; k < line && k < lines.length; k++) {
    const code = lines[k].split(';')[0].trim().toUpperCase();
    const words = code.split(/\s+/).filter(Boolean);
    const g = words.find((w) => w[0] === 'G');
    if (!g) continue;
    const num = Number(g.slice(1));
    const vals = letters.map((l) => {
      const w = words.find((x) => x[0] === l);
      return w === undefined ? null : Number(w.slice(1));
    });
    if (num === 90) relative = false;
    else if (num === 91) relative = true;
    else if (num === 92) vals.forEach((v, i) => { if (v !== null) offset[i] = raw[i] - v; });
    else if (num === 0 || num === 1) vals.forEach((v, i) => { if (v !== null) raw[i] = relative ? raw[i] + v : v + offset[i]; });
  }
  return raw;
}

/** v turned by `deg` degrees about the unit axis `k`, right-hand (Rodrigues). */
function rotate(v, k, deg) {
  const t = (deg * Math.PI) / 180, c = Math.cos(t), s = Math.sin(t);
  const dot = v[0] * k[0] + v[1] * k[1] + v[2] * k[2];
  const cross = [k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]];
  return [0, 1, 2].map((i) => v[i] * c + cross[i] * s + k[i] * dot * (1 - c));
}

/**
 * Tip and tool axis (part frame) of the machine `spec` (its JSON: `describe().machines[].spec`)
 * at `axes`, docs/machines.md's closed forms:
 *  - b-head: p = (X − r sin B, Y, Z − r cos B + r), n = (sin B, 0, cos B);
 *  - ab-table: the nozzle vertical, the table turned by A about (a_pos, a_dir) carrying B's
 *    turn about (b_pos, b_dir): p = T_B(−B) T_A(−A) (X, Y, Z) − part_offset,
 *    n = R(b_dir, −B) R(a_dir, −A) e_z (no Z wobble: asserted).
 */
export function tipAndAxis(spec, axes) {
  if (spec.kind === 'b-head') {
    const r = spec.pivot_to_tip_mm, b = (axes[3] * Math.PI) / 180;
    return { p: [axes[0] - r * Math.sin(b), axes[1], axes[2] - r * Math.cos(b) + r], n: [Math.sin(b), 0, Math.cos(b)] };
  }
  if (spec.kind === 'ab-table') {
    if (spec.z_wobble_mm) throw new Error('the test kinematics leave out the Z wobble');
    const sub = (a, b) => a.map((x, i) => x - b[i]), add = (a, b) => a.map((x, i) => x + b[i]);
    const [a, b] = [axes[3], axes[4]];
    const y = add(spec.a_pos, rotate(sub(axes.slice(0, 3), spec.a_pos), spec.a_dir, -a));
    const p = sub(add(spec.b_pos, rotate(sub(y, spec.b_pos), spec.b_dir, -b)), spec.part_offset);
    return { p, n: rotate(rotate([0, 0, 1], spec.a_dir, -a), spec.b_dir, -b) };
  }
  throw new Error(`no test kinematics for kind ${spec.kind}`);
}

/** Waits until the head drawn is the one asked for last; the drawn parts (`data-head`). */
export async function drawnHead(page) {
  await page.waitForFunction(() => {
    const vp = document.getElementById('canvas-wrap');
    return vp.dataset.headAsked && vp.dataset.headAsked === vp.dataset.headDone;
  }, null, { timeout: 30000 });
  const h = await page.locator('#canvas-wrap').getAttribute('data-head');
  return h ? JSON.parse(h) : null;
}

/** Angle between two vectors, degrees. */
function angleDeg(u, v) {
  const dot = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
  const nu = Math.hypot(...u), nv = Math.hypot(...v);
  return (Math.acos(Math.max(-1, Math.min(1, dot / (nu * nv)))) * 180) / Math.PI;
}

/**
 * The head drawn at the preview's current move (check mode: the viewport's `data-line`) against
 * the G-code `file` read here: the nozzle's tip and axis, the legend, the red parts. `report`:
 * the CLI's `warpslice check --json` of the file.
 */
export async function assertHeadAtMove(ctx, { file, machine, report }) {
  const { page, tid, assert } = ctx;
  const parts = await drawnHead(page);
  assert(parts, `a head is drawn (legend: ${await tid('head-legend').innerText()})`);
  const line = Number(await tid('viewport').getAttribute('data-line'));
  assert(line > 0, `the preview is at a file line: ${line}`);
  const spec = ctx.schema.machines.find((m) => m.name === machine).spec;
  const letters = spec.axis_names.map((a) => a[0].toUpperCase());
  const axes = axesAtLine(readFileSync(file, 'utf8'), letters, line);
  const want = tipAndAxis(spec, axes);
  const nozzle = parts.find((p) => p.name === 'nozzle');
  assert(nozzle && nozzle.kind === 'frustum', `a nozzle frustum is drawn: ${JSON.stringify(parts)}`);
  const off = Math.hypot(...nozzle.base.map((x, i) => x - want.p[i]));
  assert(off <= TIP_MM, `line ${line} (${letters.join(' ')} = ${axes.join(' ')}): the drawn nozzle's tip ${nozzle.base} is ${off.toFixed(4)} mm from the move's tip ${want.p.map((x) => x.toFixed(4))}`);
  const along = nozzle.top.map((x, i) => x - nozzle.base[i]);
  const deg = angleDeg(along, want.n);
  assert(deg <= AXIS_DEG, `line ${line}: the drawn nozzle's axis is ${deg.toFixed(3)}° from the move's tool axis ${want.n.map((x) => x.toFixed(4))}`);
  // the legend: exactly the head parts the check tested, in order
  const legend = await tid('head-legend').locator('[data-part]').evaluateAll((es) => es.map((e) => e.dataset.part));
  assert(JSON.stringify(legend) === JSON.stringify(report.head_parts), `the legend lists ${JSON.stringify(legend)}, the check's head parts are ${JSON.stringify(report.head_parts)}`);
  assert(JSON.stringify(parts.map((p) => p.name)) === JSON.stringify(report.head_parts), `drawn parts ${parts.map((p) => p.name)} vs ${report.head_parts}`);
  // red: exactly the parts of the CLI's collision findings on this line
  const hit = [...new Set(report.findings.filter((f) => f.kind === 'collision' && f.line === line).map((f) => f.collision.part))].sort();
  const red = parts.filter((p) => p.hit && p.color === '#ff0000').map((p) => p.name).sort();
  assert(JSON.stringify(red) === JSON.stringify(hit), `line ${line}: red parts ${JSON.stringify(red)}, the check's findings there ${JSON.stringify(hit)}`);
  const legendRed = await tid('head-legend').locator('[data-hit="1"]').evaluateAll((es) => es.map((e) => e.dataset.part).sort());
  assert(JSON.stringify(legendRed) === JSON.stringify(hit), `the legend marks ${JSON.stringify(legendRed)} in collision`);
  return { line, parts, hit };
}

/** Findings the CLI's JSON lists here (its default 1000 cuts the rotate-around's collision off). */
const LISTED = 100000;

/**
 * `warpslice check FILE --machine M --json --max-findings LISTED`: the report (exit 0 clean or
 * speed only, 1 findings).
 */
export function cliCheck(CLI, file, machine) {
  const r = spawnSync(CLI, ['check', file, '--machine', machine, '--json', '--max-findings', String(LISTED)], { maxBuffer: 1 << 28 });
  if (r.status !== 0 && r.status !== 1) throw new Error(`warpslice check ${file}: exit ${r.status}: ${r.stderr}`);
  return JSON.parse(r.stdout.toString());
}

/** The hand-built cases' files (`cargo run --example finding_cases -- DIR`) and their list. */
export function findingCases(ROOT, dir) {
  execFileSync('cargo', ['run', '--release', '--quiet', '--example', 'finding_cases', '--', dir], { cwd: ROOT, stdio: ['ignore', 'inherit', 'inherit'] });
  return JSON.parse(readFileSync(join(dir, 'cases.json'), 'utf8'));
}

/**
 * Selects the preset `machine`; a loaded model is re-warped for it: waits for that warp, whose
 * result would otherwise reset a check's preview (or clear its error) when it lands.
 */
export async function selectMachineSettled(ctx, machine) {
  const { page, tid, warpSettled } = ctx;
  await tid('machine-select').selectOption(machine);
  if (await page.evaluate(() => import('./js/state.js').then(({ state }) => !!state.stl))) await warpSettled();
}

/** Drops `file` into "Check a G-code" for `machine`; waits for its report. */
export async function checkOnPage(ctx, file, machine) {
  const { page, tid, assert } = ctx;
  await selectMachineSettled(ctx, machine);
  await tid('check-input').setInputFiles(file);
  const name = basename(file);
  await page.waitForFunction((n) => {
    const t = document.querySelector('[data-testid="check-progress"]').textContent;
    return t.startsWith(`${n} checked`) || !document.querySelector('[data-testid="error"]').hidden;
  }, name, { timeout: 300000 });
  assert(!(await tid('error').isVisible()), `${name}: the page showed an error: ${await tid('error').innerText()}`);
}

/** A finding as the page and the CLI both name it: kind, line, and the part or the axis. */
export const findingKey = (f) => `${f.kind}:${f.line}:${f.kind === 'collision' ? `${f.collision.part}/${f.collision.obstacle}` : f.axis}`;

export async function headTests(ctx) {
  const { page, test, tid, assert, CLI, TMP, ROOT, screenshot } = ctx;
  const dir = join(TMP, 'finding-cases');
  let cases = null;
  const theCases = () => (cases ??= findingCases(ROOT, dir));

  await test('every hand-built finding case through the page: the findings and lines of warpslice check --json, "no findings" for the clean files', async () => {
    const shown = await page.evaluate(() => import('./js/check.js').then((m) => m.FINDINGS_SHOWN));
    for (const c of theCases()) {
      const rep = cliCheck(CLI, c.file, c.machine);
      const cli = rep.findings.map(findingKey);
      // the case is what its builder says: its lines among the CLI's findings (none: clean)
      if (c.lines) {
        const lines = new Set(rep.findings.map((f) => f.line));
        assert(c.lines.every((l) => lines.has(l)), `${c.name}: the CLI finds lines ${[...lines].slice(0, 20)}…, the case is built for ${c.lines}`);
        if (c.lines.length === 0) assert(rep.findings.length === 0, `${c.name}: the clean file has findings ${cli}`);
      } else {
        assert(rep.findings.length > 0, `${c.name}: the CLI finds nothing`);
      }
      await checkOnPage(ctx, c.file, c.machine);
      const total = rep.counts.reach + rep.counts.collision + rep.counts.speed;
      assert((await tid('findings').getAttribute('data-count')) === String(total), `${c.name}: the page counts ${await tid('findings').getAttribute('data-count')}, the CLI ${total}`);
      const page_ = await tid('findings').locator('[data-line]').evaluateAll((es) => es.map((e) => {
        const d = e.dataset;
        return `${d.kind}:${d.line}:${d.kind === 'collision' ? `${d.part}/${d.obstacle}` : d.axis}`;
      }));
      const want = cli.slice(0, shown);
      assert(JSON.stringify(page_) === JSON.stringify(want), `${c.name} (${c.machine}): the page lists\n  ${page_.join(' ')}\nwarpslice check --json\n  ${want.join(' ')}`);
      // the preview's collisions (red, and the head's red parts): every line and part of the
      // CLI's collision findings, however many findings come before them
      const cliHits = new Map();
      for (const f of rep.findings.filter((x) => x.kind === 'collision')) cliHits.set(f.line, [...new Set([...(cliHits.get(f.line) ?? []), f.collision.part])]);
      const asText = (m) => [...m].map(([l, ps]) => `${l}:${[...ps].sort().join(',')}`).sort().join(' ');
      // what the preview draws: each point flagged (`hit`), the file line it is on and the
      // names of the parts in collision there (`hitSets`)
      const pageHits = await page.evaluate(() => import('./js/state.js').then(({ state }) => {
        const d = state.tp.data;
        const m = new Map();
        for (let i = 0; i < (d?.count ?? 0); i++) if (d.hit?.[i]) m.set(d.line[i], d.hitSets[d.hit[i] - 1]);
        return [...m];
      }));
      assert(asText(pageHits) === asText(cliHits), `${c.name}: the preview's collisions ${asText(pageHits)}, warpslice check's ${asText(cliHits)}`);
      // the counts by kind (a case whose first findings shown are of another kind — the
      // rotate-around's A beyond the RTN's range before its collision — still counts it)
      const text = await tid('findings-count').innerText();
      if (total === 0) assert(/no findings/.test(text), `${c.name}: the page says ${text}`);
      else assert(text.endsWith(`${rep.counts.reach} reach, ${rep.counts.collision} collision, ${rep.counts.speed} speed`), `${c.name}: the page says ${text}, the CLI ${JSON.stringify(rep.counts)}`);
      console.log(`     ${c.name} (${c.machine}): ${total} finding(s) ${want.slice(0, 4).join(' ')}${want.length > 4 ? ' …' : ''}`);
    }
  });

  await test('head solids: the B head beside the 20 mm wall (fullcontrol-prusa-b), at the clicked finding\'s move the nozzle is at the tip along the tool axis, the legend lists the head\'s parts, the colliding ones red', async () => {
    const c = theCases().find((x) => x.name === 'b-head-wall');
    const rep = cliCheck(CLI, c.file, c.machine);
    await checkOnPage(ctx, c.file, c.machine);
    // the approach: heater block and heat sink into the wall, the nozzle clear
    const approach = c.lines[0];
    await tid('findings').locator(`button[data-line="${approach}"]`).first().click();
    const { hit } = await assertHeadAtMove(ctx, { file: c.file, machine: c.machine, report: rep });
    assert(hit.length === 2 && !hit.includes('nozzle'), `the approach's colliding parts: ${hit}`);
    await screenshot('head-b-wall');
    // another move (a printed bead of the wall, no finding): nothing red, the tip still right
    await page.locator('#move-slider').evaluate((el) => {
      el.value = '0';
      el.dispatchEvent(new Event('input', { bubbles: true }));
    });
    const other = await assertHeadAtMove(ctx, { file: c.file, machine: c.machine, report: rep });
    assert(other.line !== approach, `the slider moved off line ${approach}`);
  });
}
