// The benchmark's work in Node wasm (run by scripts/bench-wasm.sh after `cargo run --release
// --example bench`, which leaves its inputs in target/bench-inputs/).
import { existsSync, readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const pkg = process.argv[2];
const dir = process.argv[3];
const ws = require(pkg);

const mib = (b) => (b / 1048576).toFixed(0) + ' MiB';
let peakRss = 0;
const sample = () => { peakRss = Math.max(peakRss, process.memoryUsage().rss); };

function best(n, f) {
  let t = Infinity, r;
  for (let i = 0; i < n; i++) { const s = performance.now(); r = f(); t = Math.min(t, performance.now() - s); sample(); }
  return [t / 1000, r];
}

const stl = readFileSync(`${dir}/sphere225k.stl`);
const opts = JSON.stringify({ warp: { spec: { kind: 'conic', angle: 30, direction: 'outward', center: [0, 0] }, base: null } });
const [tw, w] = best(3, () => ws.warp(stl, opts));
console.log(`wasm warp_model: ${tw.toFixed(3)} s, ${w.report.mesh.triangles} → ${w.report.triangles_out} triangles; peak RSS ${mib(peakRss)}`);

const job = readFileSync(`${dir}/ball.job.json`, 'utf8');
const gcode = readFileSync(`${dir}/ball.gcode`);
const CHUNK = 1 << 20;
/**
 * The page's streaming unwarp (the worker's `UnwarpStream`: scan, endScan, push + takeOutput,
 * finish) of the bench G-code with the options JSON `opts`: `{ r: report, out: [chunks],
 * bytes }`, or the core's error thrown (a collision refusal).
 */
function streamUnwarp(opts) {
  const s = new ws.UnwarpStream(job, opts);
  try {
    for (let o = 0; o < gcode.length; o += CHUNK) s.scan(gcode.subarray(o, o + CHUNK));
    s.endScan();
    const out = [];
    let bytes = 0;
    const take = () => { const c = s.takeOutput(); out.push(c); bytes += c.length; };
    for (let o = 0; o < gcode.length; o += CHUNK) { s.push(gcode.subarray(o, o + CHUNK)); take(); sample(); }
    const r = s.finish();
    take();
    return { r, out, bytes };
  } finally {
    s.free();
  }
}
const [tu, res] = best(3, () => streamUnwarp('{}'));
const mb = gcode.length / 1e6;
console.log(`wasm unwarp (streaming): ${mb.toFixed(1)} MB → ${(res.bytes / 1e6).toFixed(1)} MB (${res.r.lines_out} lines) in ${tu.toFixed(3)} s = ${(mb / tu).toFixed(1)} MB/s input, ${(res.r.lines_out / tu / 1e6).toFixed(2)} M lines/s; peak RSS ${mib(peakRss)}`);

// `unwarp --machine` per preset, as examples/bench.rs's step 3 does natively (its presets, its
// placements, both interpolation modes with the collision check off, then once with it on), by
// the page's streaming API: the time and its ratio to the wasm 3-axis unwarp above. The lines
// are counted after the timing, as natively.
const PRESETS = [['cartesian', null], ['fullcontrol-prusa-b', null], ['rtn-slicer4rtn', null], ['pax-5axis', null], ['open5x-ab', [0, 0]], ['ratrig-vcore3-3z', null]];
const MODES = [['0.02 mm / 0.1°', null], ['0.02 mm / 0.1°, caps 1 mm / 1°', [1, 1]]];
const only = process.env.PRESETS?.split(',');
const lines = (chunks) => chunks.reduce((n, c) => n + c.reduce((k, b) => k + (b === 10), 0), 0);
for (const [name, place] of PRESETS) {
  if (only && !only.includes(name)) continue;
  const opts = (caps, check) => JSON.stringify({ machine: name, ...(place ? { place } : {}), check_collisions: check, ...(caps ? { interpolation_caps: caps } : {}) });
  let tDefault = NaN;
  for (const [mode, caps] of MODES) {
    let t, m;
    try {
      [t, m] = best(1, () => streamUnwarp(opts(caps, false)));
    } catch (e) {
      console.log(`wasm unwarp --machine ${name} [${mode}]: refused: ${e.message ?? e}`);
      continue;
    }
    if (!caps) tDefault = t;
    const n = lines(m.out);
    console.log(`wasm unwarp --machine ${name} [${mode}]: ${t.toFixed(2)} s = ×${(t / tu).toFixed(1)} the wasm 3-axis unwarp; ${n} lines, ${(n / t / 1e6).toFixed(2)} M lines/s; peak RSS ${mib(peakRss)}`);
  }
  const ts = performance.now();
  let verdict = 'passed: no collision';
  try {
    streamUnwarp(opts(null, true));
  } catch (e) {
    verdict = `refused: ${String(e.message ?? e).slice(0, 110)}`;
  }
  const tOn = (performance.now() - ts) / 1000;
  sample();
  console.log(`wasm unwarp --machine ${name} with the collision check: ${tOn.toFixed(2)} s (×${(tOn / tDefault).toFixed(2)} of the check off); ${verdict}; peak RSS ${mib(peakRss)}`);
}

// The built-in slicer on the warped sphere of examples/builtin_bench.rs (60 mm, 225 000 triangles,
// conic 30° outward and subdivided), stepped one layer at a time as the web worker does.
const bstl = `${dir}/builtin-sphere-conic30.stl`;
if (existsSync(bstl)) {
  const wstl = readFileSync(bstl);
  const bjob = readFileSync(`${dir}/builtin-sphere-conic30.job.json`, 'utf8');
  const [tb, sliced] = best(1, () => {
    const s = new ws.BuiltinSlice(wstl, bjob, '');
    let p;
    do p = s.step(); while (p.done < p.total);
    const out = s.finish();
    s.free();
    return { layers: p.layers, bytes: out.gcode.length };
  });
  console.log(`wasm builtin slice: ${tb.toFixed(3)} s, ${(wstl.length - 84) / 50} triangles, ${sliced.layers} layers, ${(sliced.bytes / 1e6).toFixed(1)} MB of G-code; peak RSS ${mib(peakRss)}`);
} else {
  console.log('wasm builtin slice: not run (no target/bench-inputs/builtin-sphere-conic30.stl: run `cargo run --release --example builtin_bench` first)');
}
