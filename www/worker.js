// The heavy work, off the page's thread: warping, the streaming two-pass unwarp of a G-code
// File read in slices (never one big string; the core checks its collisions as it streams), and
// `warpslice check` of a machine G-code (reach and speeds after a machine unwarp, and the page's
// "Check a G-code" mode). Messages in: {id, op, ...}; out: {id, type, ...}.
import init, * as ws from './pkg/warpslice.js';

const ready = init({ module_or_path: new URL('./pkg/warpslice_bg.wasm', import.meta.url) });
let wasmMemory = null;
/** The wasm linear memory right after instantiation, bytes: the module's idle size. */
let idleBytes = 0;
ready.then((exports) => {
  wasmMemory = exports.memory;
  idleBytes = wasmBytes();
});
/** Bytes the worker holds outside its JS heap: the wasm linear memory (never shrinks). */
const wasmBytes = () => (wasmMemory ? wasmMemory.buffer.byteLength : 0);

/**
 * Bytes per chunk read from the G-code File. The wasm memory's high-water mark grows with it
 * (a chunk's output, its toolpath points and their f64 copy are held at once, and wasm memory
 * never shrinks): the 105 MB test G-code's 3-axis unwarp left the worker 87 MiB above the
 * module's idle size with 4 MiB chunks, 33 MiB with 1 MiB (Node, the same calls, no time lost).
 */
const CHUNK = 1 << 20;
/** Most toolpath points kept for the preview (the download always has every line). */
const PREVIEW_POINTS = 250_000;
/**
 * The preview's next capacity, points: doubled up to PREVIEW_POINTS, then a quarter more at a
 * time (the stride is picked for about PREVIEW_POINTS; a G-code denser than BYTES_PER_POINT
 * goes a little over, and doubling there would hold up to twice the buffers it needs: the 105 MB
 * test G-code keeps about 274 000 points, in 2^19 slots of 37 bytes by doubling, 327 680 now).
 */
function nextCap(cap) {
  return cap < PREVIEW_POINTS ? cap * 2 : Math.ceil(cap * 1.25);
}
/** Approximate bytes of G-code per toolpath point, to pick the decimation stride up front. */
const BYTES_PER_POINT = 28;

/** An error as the page gets it: the core's stable `code` (null when it has none) and its text. */
function errReply(e) {
  return { code: typeof e?.code === 'string' ? e.code : null, message: e && e.message ? e.message : String(e) };
}

/** An Error with a stable code, for what the worker itself refuses. */
function coded(code, message) {
  return Object.assign(new Error(message), { code });
}

self.onmessage = async (ev) => {
  const msg = ev.data;
  try {
    await ready;
    if (msg.op === 'init') {
      self.postMessage({ id: msg.id, type: 'done', schema: JSON.parse(ws.describe()) });
    } else if (msg.op === 'describe-machine') {
      // A machine (preset name or machine JSON) as the core reads it: one `describe().machines` entry.
      self.postMessage({ id: msg.id, type: 'done', machine: JSON.parse(ws.describe_machine(msg.machine)) });
    } else if (msg.op === 'example') {
      const stl = ws.example_stl(msg.name);
      self.postMessage({ id: msg.id, type: 'done', stl }, [stl.buffer]);
    } else if (msg.op === 'inspect') {
      const report = ws.stl_report(new Uint8Array(msg.stl));
      self.postMessage({ id: msg.id, type: 'done', report });
    } else if (msg.op === 'warp') {
      const out = ws.warp(new Uint8Array(msg.stl), JSON.stringify(msg.options));
      const surfaces = new Float32Array(ws.layer_surfaces(out.job, msg.every || 5, msg.grid || 48));
      self.postMessage({ id: msg.id, type: 'done', stl: out.stl, job: out.job, report: out.report, surfaces }, [out.stl.buffer, surfaces.buffer]);
    } else if (msg.op === 'unwarp') {
      await unwarpFile(msg);
    } else if (msg.op === 'builtin') {
      await sliceHereAndUnwarp(msg);
    } else if (msg.op === 'overhangs') {
      // `warpslice overhangs`: planar and under the warp of `options` ('' for planar), per facet
      const report = ws.overhangs(new Uint8Array(msg.stl), msg.options, msg.angle);
      self.postMessage({ id: msg.id, type: 'done', report });
    } else if (msg.op === 'suggest') {
      // `warpslice suggest`: the ranked admissible warps for the machine
      const report = ws.suggest(new Uint8Array(msg.stl), msg.machine, msg.options);
      self.postMessage({ id: msg.id, type: 'done', report });
    } else if (msg.op === 'cancel') {
      // between two layers of a running `builtin` slice, that slice stops (`sliceHereAndUnwarp`)
      cancelled.add(msg.target);
    } else if (msg.op === 'head') {
      // The head's solids at one preview point's axes, placed by the collision check's own code.
      self.postMessage({ id: msg.id, type: 'done', head: ws.head_pose(msg.machine, new Float64Array(msg.axes)) });
    } else if (msg.op === 'check') {
      // Check a G-code (any tool's) for a machine: the report, and the preview with file lines.
      const t0 = performance.now();
      const out = await checkFile(msg.file, msg.machine, true, (done, total) =>
        self.postMessage({ id: msg.id, type: 'progress', phase: 'check', done, total, workerBytes: wasmBytes() }));
      const pv = out.preview;
      const transfer = [pv.pos.buffer, pv.tilt.buffer, pv.axis.buffer, pv.layer.buffer, pv.flags.buffer, pv.line.buffer, pv.hit.buffer, pv.maxes.buffer];
      self.postMessage({ id: msg.id, type: 'done', report: out.report, preview: pv, ms: performance.now() - t0 }, transfer);
    }
  } catch (e) {
    self.postMessage({ id: msg.id, type: 'error', ...errReply(e) });
  }
};

async function readSlice(file, start, end) {
  return new Uint8Array(await file.slice(start, end).arrayBuffer());
}

/**
 * The File's CHUNK slices in order as `[offset, bytes]`, the next one already being read
 * (off this thread) while the caller's wasm works on this one.
 */
async function* slices(file) {
  let next = readSlice(file, 0, CHUNK);
  for (let off = 0; off < file.size; off += CHUNK) {
    const bytes = await next;
    if (off + CHUNK < file.size) next = readSlice(file, off + CHUNK, off + 2 * CHUNK);
    yield [off, bytes];
  }
}

/**
 * The preview buffer: positions (f32 xyz), axes (f32 xyz), layer (u32), flags (u8: feature |
 * travel<<7); for a checked G-code also the file line of each point (u32, `line`), whether a
 * collision was found on it and which parts (`hit`, `hitSets`: set by `markHits`); for a machine's file the machine's axis values of each point (f32,
 * `axisCount` per point, `maxes`: the pose the head is drawn at, `head` op) and the machine
 * they belong to (`headMachine`, a preset name or JSON text).
 */
class Preview {
  /** `thinned`: the points come already decimated 1:`stride` (the core's `toolpath_every`). */
  constructor(stride, thinned = false) {
    this.stride = stride;
    this.thinned = thinned;
    this.count = 0;
    this.seen = 0;
    this.cap = 1 << 16;
    this.alloc(this.cap);
  }
  alloc(cap) {
    const grow = (Old, k) => {
      const a = new Old(cap * k);
      return a;
    };
    const pos = grow(Float32Array, 3), axis = grow(Float32Array, 3), layer = grow(Uint32Array, 1), flags = grow(Uint8Array, 1);
    const tilt = grow(Float32Array, 1);
    const line = grow(Uint32Array, 1);
    const maxes = grow(Float32Array, this.axisCount ?? 0);
    if (this.pos) {
      maxes.set(this.maxes.subarray(0, this.count * (this.axisCount ?? 0)));
      line.set(this.line.subarray(0, this.count));
      tilt.set(this.tilt.subarray(0, this.count));
      pos.set(this.pos.subarray(0, this.count * 3));
      axis.set(this.axis.subarray(0, this.count * 3));
      layer.set(this.layer.subarray(0, this.count));
      flags.set(this.flags.subarray(0, this.count));
    }
    Object.assign(this, { pos, axis, layer, flags, tilt, line, maxes, cap });
  }
  /**
   * `tp`: 10 numbers per point (the core's toolpath layout); `lines`: the file line of each
   * (check); `axes`: the machine's `k` axis values of each (check).
   */
  add(tp, lines = null, axes = null, k = 0) {
    if (axes && k && this.axisCount !== k) {
      // the first points with axes: the buffer learns the machine's axis count
      this.axisCount = k;
      this.maxes = new Float32Array(this.cap * k);
    }
    for (let i = 0; i + 9 < tp.length; i += 10) {
      const keep = this.thinned || this.seen % this.stride === 0;
      this.seen++;
      // Keep every point of a layer change so the layer ranges stay exact.
      const layer = tp[i + 7];
      const newLayer = this.count > 0 && this.layer[this.count - 1] !== layer;
      if (!keep && !newLayer) continue;
      if (this.count === this.cap) this.alloc(nextCap(this.cap));
      const c = this.count++;
      this.pos[c * 3] = tp[i]; this.pos[c * 3 + 1] = tp[i + 1]; this.pos[c * 3 + 2] = tp[i + 2];
      this.axis[c * 3] = tp[i + 3]; this.axis[c * 3 + 1] = tp[i + 4]; this.axis[c * 3 + 2] = tp[i + 5];
      this.layer[c] = layer;
      this.tilt[c] = (Math.acos(Math.max(-1, Math.min(1, tp[i + 5]))) * 180) / Math.PI;
      this.flags[c] = (tp[i + 9] & 0x7f) | (tp[i + 8] ? 0x80 : 0);
      this.line[c] = lines ? lines[i / 10] : 0;
      if (axes && k) for (let j = 0; j < k; j++) this.maxes[c * k + j] = axes[(i / 10) * k + j];
    }
  }
  result() {
    const n = this.count;
    return {
      count: n, stride: this.stride, seen: this.seen,
      bytes: this.cap * 37, pos: this.pos.slice(0, n * 3), tilt: this.tilt.slice(0, n), axis: this.axis.slice(0, n * 3), layer: this.layer.slice(0, n), flags: this.flags.slice(0, n),
      line: this.line.slice(0, n),
      axisCount: this.axisCount ?? 0, maxes: this.maxes.slice(0, n * (this.axisCount ?? 0)),
    };
  }
}

/** Add `part` to the parts in collision on file line `line` (`parts`: line → part names). */
function addHit(parts, line, part) {
  if (!parts.has(line)) parts.set(line, []);
  if (!parts.get(line).includes(part)) parts.get(line).push(part);
}

/**
 * Flag every preview point whose file line has a part in collision (`parts`: line → part
 * names, every collision of the check, not only the findings its report lists): `hit[i]` is 0,
 * or 1 + the index in `hitSets` of the names of the parts in collision there. Typed and
 * transferred, so the page's main thread gets no map of every line to clone.
 */
function markHits(pv, parts) {
  const index = new Map();
  pv.hitSets = [];
  pv.hit = new Uint32Array(pv.count);
  for (let i = 0; i < pv.count; i++) {
    const names = parts.get(pv.line[i]);
    if (!names) continue;
    const key = names.join('\n');
    let k = index.get(key);
    if (k === undefined) {
      k = pv.hitSets.length;
      index.set(key, k);
      pv.hitSets.push(names.slice());
    }
    pv.hit[i] = k + 1;
  }
}

/**
 * `warpslice check` of a File or Blob for `machine` (a preset name or a machine JSON text),
 * streamed in CHUNK slices: `{ report, preview }` (the preview only with `withPath`: points with
 * their file lines, collisions flagged). `onProgress(done, total)` after each slice;
 * `skipCollisions`: reach and speeds only; `collisions`: with it, the collisions the unwarp that
 * wrote the file found (its report's `machine.collisions`), listed as the check's own.
 */
async function checkFile(file, machine, withPath, onProgress = () => {}, skipCollisions = false, collisions = null) {
  const total = file.size;
  const stream = new ws.CheckStream(machine, JSON.stringify({ path: withPath, skip_collisions: skipCollisions }));
  const preview = withPath ? new Preview(Math.max(1, Math.ceil(total / BYTES_PER_POINT / PREVIEW_POINTS))) : null;
  // the parts in collision per file line: the check's own (its path), or the unwarp's handed over
  const hits = new Map();
  for (const c of collisions ?? []) addHit(hits, c.line, c.part);
  const drain = () => {
    if (!preview) return;
    const p = stream.takePath();
    preview.add(p.points, p.lines, p.axes, p.axisCount);
    for (const [line, parts] of p.collisions) for (const part of parts) addHit(hits, line, part);
  };
  try {
    for await (const [off, bytes] of slices(file)) {
      stream.push(bytes);
      drain();
      onProgress(Math.min(total, off + CHUNK), total);
    }
    const report = collisions ? stream.finishWithCollisions(collisions) : stream.finish();
    drain();
    let pv = null;
    if (preview) {
      pv = preview.result();
      pv.headMachine = machine;
      markHits(pv, hits);
    }
    return { report, preview: pv };
  } finally {
    stream.free();
  }
}

/** The `machine` of unwarp options as `CheckStream` takes it: a preset name or a JSON text. */
function machineText(m) {
  return typeof m === 'string' ? m : JSON.stringify(m);
}

/** The preview's points as the core's kinematics take them: 6 numbers per point (p, n). */
function tipsAndAxes(pv) {
  const pts = new Float64Array(pv.count * 6);
  for (let i = 0; i < pv.count; i++) {
    for (let j = 0; j < 3; j++) {
      pts[i * 6 + j] = pv.pos[i * 3 + j];
      pts[i * 6 + 3 + j] = pv.axis[i * 3 + j];
    }
  }
  return pts;
}

/**
 * The preview in machine coordinates (moving-bed machines): the core's `machine_view` gives, per
 * preview point (tip p, tool axis n), the head position H(p) in the machine frame and the columns
 * H(p + e_k) − H(p) of the part → machine rotation, from the machine's own inverse kinematics.
 * The rigid map part → machine at move i is q ↦ mpos_i + R_i (q − p_i).
 */
function machineFrame({ machine, name }, pv) {
  const n = pv.count;
  const v = ws.machine_view(machine, tipsAndAxes(pv));
  const mpos = new Float32Array(n * 3), mrot = new Float32Array(n * 9);
  for (let i = 0; i < n; i++) {
    for (let j = 0; j < 3; j++) mpos[i * 3 + j] = v[i * 12 + j];
    for (let k = 0; k < 9; k++) mrot[i * 9 + k] = v[i * 12 + 3 + k];
  }
  return { mpos, mrot, machine: name };
}

async function unwarpFile(msg) {
  const { id, file, job } = msg;
  const total = file.size;
  // The preview's decimation is done by the core as the points are made (`toolpath_every`):
  // only the kept points cross into JS.
  const stride = Math.max(1, Math.ceil(total / BYTES_PER_POINT / PREVIEW_POINTS));
  const options = { ...msg.options, collect_toolpath: true, toolpath_every: stride };
  let preview = null;
  const post = (phase, done) => self.postMessage({ id, type: 'progress', phase, done, total: total * 2, workerBytes: wasmBytes() + (preview ? preview.cap * 37 : 0) });
  const head = await readSlice(file, 0, Math.min(total, 16));
  if (head.length >= 4 && head[0] === 0x47 && head[1] === 0x43 && head[2] === 0x44 && head[3] === 0x45) {
    throw coded('gcode.binary', 'this is a binary G-code (.bgcode): export plain-text G-code instead (PrusaSlicer: Printer settings → General → “Supports binary G-code” off)');
  }
  const t0 = performance.now();
  const stream = new ws.UnwarpStream(job, JSON.stringify(options));
  try {
    // Register to the bead: the printed walls against the warped STL's cross-sections (the
    // CLI's `unwarp --stl`); the page always has the STL the job was written with.
    if (msg.warpedStl) stream.setWarpedStl(new Uint8Array(msg.warpedStl));
    for await (const [off, bytes] of slices(file)) {
      stream.scan(bytes);
      post('scan', Math.min(total, off + CHUNK));
    }
    const registration = stream.endScan();
    self.postMessage({ id, type: 'registration', registration });
    const parts = [];
    preview = new Preview(stride, true);
    let outBytes = 0;
    const drain = () => {
      const out = stream.takeOutput();
      if (out.length) {
        parts.push(out);
        outBytes += out.length;
      }
      preview.add(stream.takeToolpath());
    };
    for await (const [off, bytes] of slices(file)) {
      stream.push(bytes);
      drain();
      // Fold the pieces into a Blob now and then: Blob storage lives outside the JS heap.
      if (parts.length > 16) parts.splice(0, parts.length, new Blob(parts));
      post('unwarp', total + Math.min(total, off + CHUNK));
    }
    // The core's collision check ran on the output as it streamed (the CLI's code): a collision
    // throws its `machine.collision` error here unless `allow_collisions`, which lists the
    // findings at the end of the file and in `report.machine.collisions`.
    const report = stream.finish();
    drain();
    const blob = new Blob(parts, { type: 'text/x-gcode' });
    const unwarpMs = performance.now() - t0;
    // The machine file through `warpslice check` for reach and axis speeds (the collisions are
    // the unwarp's, handed over, not walked twice): the findings with the output's line numbers,
    // for the page. Its path (file lines, collisions flagged) is a second preview the page
    // switches to when a finding is clicked (the unwarp's own preview has no output lines).
    let check = null;
    let checkError = null;
    let checkPreview = null;
    const tc = performance.now();
    if (options.machine) {
      try {
        const found = report.machine?.collisions_checked ? report.machine.collisions : null;
        ({ report: check, preview: checkPreview } = await checkFile(blob, machineText(options.machine), true, () => {}, true, found));
      } catch (e) {
        checkError = errReply(e);
      }
    }
    const checkMs = performance.now() - tc;
    const pv = preview.result();
    const transfer = [pv.pos.buffer, pv.tilt.buffer, pv.axis.buffer, pv.layer.buffer, pv.flags.buffer, pv.line.buffer];
    if (options.machine) {
      // the machine's axes of each preview point (its inverse kinematics, the previous point
      // picking the branch, as the machine-coordinates view): the poses the head is drawn at.
      // Optional as that view: a point it cannot solve leaves the head undrawn.
      try {
        const ax = ws.machine_axes(machineText(options.machine), tipsAndAxes(pv));
        pv.axisCount = pv.count ? ax.length / pv.count : 0;
        pv.maxes = new Float32Array(ax);
        pv.headMachine = machineText(options.machine);
        transfer.push(pv.maxes.buffer);
      } catch (e) {
        pv.headError = String(e?.message ?? e);
      }
    }
    if (msg.machineFrame) {
      // The machine-coordinates view is optional: a preview point it cannot place (the preview
      // keeps f32 axes, so a tilt exactly at the machine's limit may round past it) leaves the
      // toggle off instead of failing the unwarp, whose G-code is complete and checked.
      try {
        Object.assign(pv, machineFrame(msg.machineFrame, pv));
        transfer.push(pv.mpos.buffer, pv.mrot.buffer);
      } catch (e) {
        pv.machineFrameError = String(e?.message ?? e);
      }
    }
    // The firmware configuration this machine G-code needs (the CLI's --config-out): a second
    // download; none for 3-axis output.
    const config = msg.options.machine ? ws.firmware_config(JSON.stringify(msg.options)) : null;
    if (checkPreview) {
      const c = checkPreview;
      transfer.push(c.pos.buffer, c.tilt.buffer, c.axis.buffer, c.layer.buffer, c.flags.buffer, c.line.buffer, c.hit.buffer, c.maxes.buffer);
    }
    // the worker's memory: the wasm module's idle size and, at the end (wasm memory never
    // shrinks), its size now plus the preview buffers; the unwarp's and the check's times
    const memory = { idleBytes, workerBytes: wasmBytes() + preview.cap * 37 + (checkPreview ? checkPreview.bytes : 0) };
    const listed = pageLists(report, check);
    self.postMessage({ id, type: 'done', blob, ...listed, registration, config, checkError, checkPreview, bytes: outBytes, ms: performance.now() - t0, unwarpMs, checkMs, ...memory, preview: pv }, transfer);
  } finally {
    stream.free();
  }
}

/**
 * Most entries of a findings list (the unwarp report's `machine.collisions`, the check's
 * `findings`) the page gets as objects: it shows the first FINDINGS_SHOWN (js/check.js).
 */
const FINDINGS_TO_PAGE = 1000;

/**
 * The unwarp's `report` and `check` as the page gets them: with a findings list longer than
 * FINDINGS_TO_PAGE (the big pax-5axis test lists 88 261 collisions in each), the lists are
 * cut there and `lists` has the whole report and check as JSON text (each as it sits in the
 * page's summary, one level deep, 2-space indent), for the summary download. Cloning every
 * finding into the page was a main-thread task of 0.45–0.77 s.
 */
function pageLists(report, check) {
  const collisions = report.machine?.collisions;
  const long = (collisions?.length ?? 0) > FINDINGS_TO_PAGE || (check?.findings?.length ?? 0) > FINDINGS_TO_PAGE;
  if (!long) return { report, check, lists: null };
  const lists = { report: nestedJson(report), check: check ? nestedJson(check) : null };
  const cut = (a) => (a && a.length > FINDINGS_TO_PAGE ? a.slice(0, FINDINGS_TO_PAGE) : a);
  return {
    report: collisions ? { ...report, machine: { ...report.machine, collisions: cut(collisions) } } : report,
    check: check ? { ...check, findings: cut(check.findings) } : check,
    lists,
  };
}

/** `v` as JSON text one level deep in a `JSON.stringify(…, null, 2)` object, in a Blob. */
function nestedJson(v) {
  const t = JSON.stringify({ v }, null, 2); // '{\n  "v": …\n}'
  return new Blob([t.slice(t.indexOf(': ') + 2, -2)]);
}

// ── The one-click path: the built-in slicer, then the unwarp above ──────────────────────────

/** Ids of `builtin` requests the page cancelled (`cancel` op); checked between layers. */
const cancelled = new Set();
/** Longest the slice runs without letting a message (a cancel) in, ms. */
const YIELD_EVERY_MS = 40;

/**
 * `builtin` op: the warped STL and its job (`warpedStl`, `job`) sliced by the core's built-in
 * slicer with `settings` (the JSON object of the CLI's `--slicer-settings`, sent as it is: the
 * core names unknown keys and bad values), one layer per step with a `progress` message (phase
 * `slice`) after each; a `cancel` for this id stops it between layers (reply `cancelled`). The
 * planar G-code (a File, the CLI's `run --keep-sliced`) and the slicer's report go to the page
 * in a `sliced` message; then it goes through `unwarpFile` as a dropped G-code does.
 */
async function sliceHereAndUnwarp(msg) {
  const { id } = msg;
  const t0 = performance.now();
  const slicer = new ws.BuiltinSlice(new Uint8Array(msg.warpedStl), msg.job, JSON.stringify(msg.settings ?? {}));
  let out;
  try {
    let rested = performance.now();
    for (;;) {
      if (cancelled.delete(id)) {
        self.postMessage({ id, type: 'cancelled' });
        return;
      }
      const p = slicer.step();
      self.postMessage({ id, type: 'progress', phase: 'slice', done: p.done, total: p.total, layers: p.layers, workerBytes: wasmBytes() });
      if (p.done >= p.total) break;
      if (performance.now() - rested > YIELD_EVERY_MS) {
        await new Promise((r) => setTimeout(r, 0)); // a queued `cancel` runs here
        rested = performance.now();
      }
    }
    out = slicer.finish();
  } finally {
    slicer.free();
  }
  const sliced = new File([out.gcode], msg.slicedName || 'sliced.gcode', { type: 'text/x-gcode' });
  // the planar G-code (the CLI's `run --keep-sliced`) and the slicer's report, then the unwarp
  self.postMessage({ id, type: 'sliced', sliced, report: out.report, ms: performance.now() - t0 });
  await unwarpFile({ ...msg, file: sliced });
}
