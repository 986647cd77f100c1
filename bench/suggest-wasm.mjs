// What `suggest` costs in Node wasm (issue 15: "state what it costs in wasm"), on the bench
// sphere that `cargo run --release --example suggest_bench -- --stl-out FILE` writes and then
// measures natively from the same file:
//   wasm-pack build --release --target nodejs --out-dir target/pkg-node
//   node bench/suggest-wasm.mjs "$(pwd)/target/pkg-node/warpslice.js" FILE [ROUNDS]
// Prints, per preset, the best wall time of ROUNDS (default 1) and that run's process CPU time
// (user + system: the machine is shared, CPU time is what the work costs), the warps measured
// and the best suggestion, in the native bench's words.
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const [pkg, stlPath, roundsArg] = process.argv.slice(2);
if (!pkg || !stlPath) {
  console.error('usage: node bench/suggest-wasm.mjs PKG/warpslice.js SPHERE.stl [ROUNDS]');
  process.exit(2);
}
const ws = require(pkg);
const stl = readFileSync(stlPath);
const rounds = Number(roundsArg ?? 1);

for (const machine of ['ratrig-vcore3-3z', 'pax-5axis']) {
  for (const [what, options] of [['', '{}'], [' without the field', '{"families":"conic,belt,curved,tilted"}']]) {
    let best = { wall: Infinity, cpu: 0, r: null };
    for (let i = 0; i < rounds; i++) {
      const c0 = process.cpuUsage();
      const t0 = performance.now();
      const r = ws.suggest(stl, machine, options);
      const wall = (performance.now() - t0) / 1000;
      const c = process.cpuUsage(c0);
      if (wall < best.wall) best = { wall, cpu: (c.user + c.system) / 1e6, r };
    }
    const top = best.r.suggestions[0];
    console.log(
      `  wasm suggest${what} on ${machine}: ${best.wall.toFixed(3)} s wall, ${best.cpu.toFixed(2)} s CPU, ` +
        `${best.r.measured} warps measured; best: ${top ? `${top.flags.slice(0, 90)} → ${top.overhang_area_mm2.toFixed(1)} mm²` : '(planar)'}`,
    );
  }
}
