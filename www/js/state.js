// The page's state, in one place. Every module reads and writes this object; no other module
// keeps mutable state of its own (constants and lookup tables only).

export const state = {
  /** The core's self-description (`describe()`): warps, options, machines, features, errors. */
  schema: null,
  /** The model: its bytes, file name and `stl_report`. */
  stl: null,
  stlName: '',
  modelReport: null,
  /** The last warp's result `{ stl, job, report, surfaces }`, or null. */
  warped: null,
  /** The last unwarp's result (`worker.js` `done` message), or null. */
  result: null,
  /** An unwarp is running. */
  busy: false,
  /** Sequence number of the newest warp request (older answers are dropped). */
  warpSeq: 0,
  /** The debounce timer of a scheduled re-warp. */
  warpTimer: 0,
  /**
   * The custom machine as the core describes it (`describe_machine` in the worker), keyed by the
   * JSON text asked about: `text` the newest text answered, `machine` its `describe().machines`-
   * shaped entry or null, `error` `{code, message}` when the core refused it; `valid` the last
   * text the core accepted `{text, machine}` (the form keeps it while a newer text is refused);
   * `seq` the newest request (older answers are dropped), `pending` its promise, `timer` the
   * debounce of an edit.
   */
  custom: { text: null, machine: null, error: null, valid: null, seq: 0, pending: null, timer: 0 },
  /** The model's overhang (`overhangs` in the worker: planar and under the last warp), or null. */
  overhangs: null,
  /** Sequence number of the newest overhang request (older answers are dropped). */
  overhangSeq: 0,
  /** The field expression check's sequence number (a newer keystroke wins). */
  fieldSeq: 0,
  /** The last "Suggest a warp" answer (`suggest` in the worker), or null. */
  suggestions: null,
  /**
   * The running one-click slice (`builtin.js`): `id` of its worker call, `phase` (`slice`, then
   * `unwarp`), `cancelAsked`; null when none runs.
   */
  slice: null,
  /** Built-in slicer settings the form has no row for, sent as given (`slicer-form.js`). */
  slicerExtra: {},
  /** The worker, its pending requests and how many were started (`worker-client.js`). */
  rpc: { worker: null, nextId: 1, pending: new Map(), starts: 0 },
  /** three.js handles (`view.js`): renderer, scene, camera, controls, groups, `dirty`. */
  view: {},
  /** The toolpath preview (`preview.js`): the worker's buffers, the built geometry, layers. */
  tp: { data: null, built: null, layers: [], firstBuild: false },
};
