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
const [tu, res] = best(3, () => {
  const s = new ws.UnwarpStream(job, '{}');
  for (let o = 0; o < gcode.length; o += CHUNK) s.scan(gcode.subarray(o, o + CHUNK));
  s.endScan();
  let bytes = 0;
  for (let o = 0; o < gcode.length; o += CHUNK) { s.push(gcode.subarray(o, o + CHUNK)); bytes += s.takeOutput().length; sample(); }
  const r = s.finish();
  bytes += s.takeOutput().length;
  s.free();
  return { r, bytes };
});
const mb = gcode.length / 1e6;
console.log(`wasm unwarp (streaming): ${mb.toFixed(1)} MB → ${(res.bytes / 1e6).toFixed(1)} MB (${res.r.lines_out} lines) in ${tu.toFixed(3)} s = ${(mb / tu).toFixed(1)} MB/s input, ${(res.r.lines_out / tu / 1e6).toFixed(2)} M lines/s; peak RSS ${mib(peakRss)}`);

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
