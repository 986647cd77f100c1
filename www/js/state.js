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
  /** The worker and its pending requests (`worker-client.js`). */
  rpc: { worker: null, nextId: 1, pending: new Map() },
  /** three.js handles (`view.js`): renderer, scene, camera, controls, groups, `dirty`. */
  view: {},
  /** The toolpath preview (`preview.js`): the worker's buffers, the built geometry, layers. */
  tp: { data: null, built: null, layers: [], firstBuild: false },
};
