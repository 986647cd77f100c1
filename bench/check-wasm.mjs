// The collision check's cost in Node wasm (not a test): the wasm API's streaming unwarp
// (`UnwarpStream`, the page worker's) of one G-code with a machine, the check off and on
// (`allow_collisions`: the whole file is walked, as `check_cost`'s native figures), alternately,
// the best of ROUNDS each, and the check's share (`on / off − 1`, issue 10's target ≤ +50 %).
//
//   wasm-pack build --release --target nodejs --out-dir $CARGO_TARGET_DIR/pkg-node-b
//   node bench/check-wasm.mjs $CARGO_TARGET_DIR/pkg-node-b GCODE JOB [ROUNDS] [preset,preset…]
//
// e.g. the bench's ball (`cargo run --release --example bench` leaves it in
// target/bench-inputs/): GCODE target/bench-inputs/ball.gcode, JOB target/bench-inputs/ball.job.json.
// The presets that turn the part about the origin (Open5x, core-r-theta) need `place` and
// are not in the default list.
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const [pkg, gcodePath, jobPath, roundsArg, presetsArg] = process.argv.slice(2);
if (!pkg || !gcodePath || !jobPath) {
  console.error('usage: node bench/check-wasm.mjs PKG GCODE JOB [ROUNDS] [presets]');
  process.exit(2);
}
const ws = require(pkg);
const gcode = readFileSync(gcodePath);
const job = readFileSync(jobPath, 'utf8');
const rounds = Math.max(1, Number(roundsArg) || 2);
const presets = (presetsArg || 'pax-5axis,fullcontrol-prusa-b,ratrig-vcore3-3z,cartesian').split(',');
const CHUNK = 1 << 20;

/** One unwarp of the whole file through the stream: seconds and the findings listed. */
function unwarp(machine, check) {
  const options = JSON.stringify({ machine, check_collisions: check, allow_collisions: true });
  const t0 = performance.now();
  const s = new ws.UnwarpStream(job, options);
  for (let o = 0; o < gcode.length; o += CHUNK) s.scan(gcode.subarray(o, o + CHUNK));
  s.endScan();
  for (let o = 0; o < gcode.length; o += CHUNK) { s.push(gcode.subarray(o, o + CHUNK)); s.takeOutput(); }
  const r = s.finish();
  s.takeOutput();
  s.free();
  const findings = r.machine && r.machine.collisions ? r.machine.collisions.length : 0;
  return [(performance.now() - t0) / 1000, findings];
}

console.log(`wasm (Node ${process.version}), ${gcodePath}: wall s, best of ${rounds}, check off / on alternately`);
for (const p of presets) {
  let off = Infinity, on = Infinity, findings = 0;
  for (let k = 0; k < rounds; k++) {
    off = Math.min(off, unwarp(p, false)[0]);
    const [t, f] = unwarp(p, true);
    on = Math.min(on, t);
    findings = f;
  }
  console.log(`${p}: check off ${off.toFixed(2)} s, on ${on.toFixed(2)} s: +${(100 * (on / off - 1)).toFixed(0)} % (${findings} findings)`);
}
