// The worker RPC: `call(op, args)` posts `{id, op, ...args}` to worker.js and resolves with its
// `done` message. A failure rejects with an Error carrying the core's stable `.code` beside its
// `.message`. Cancel = terminate the worker and start a fresh one (the wasm state goes with it),
// or, for an op that stops between steps (`builtin`), ask it to (`cancelCall`).
import { state } from './state.js';

function startWorker() {
  const rpc = state.rpc;
  const worker = new Worker(new URL('../worker.js', import.meta.url), { type: 'module' });
  worker.onmessage = (ev) => {
    const m = ev.data;
    const p = rpc.pending.get(m.id);
    if (!p) return;
    if (m.type === 'progress' || m.type === 'registration' || m.type === 'sliced') {
      p.onEvent?.(m);
    } else if (m.type === 'cancelled') {
      rpc.pending.delete(m.id);
      p.reject(Object.assign(new Error('cancelled'), { cancelled: true }));
    } else if (m.type === 'error') {
      rpc.pending.delete(m.id);
      p.reject(Object.assign(new Error(m.message), { code: m.code ?? null }));
    } else {
      rpc.pending.delete(m.id);
      p.resolve(m);
    }
  };
  worker.onerror = (ev) => {
    for (const [, p] of rpc.pending) p.reject(Object.assign(new Error(`the worker stopped: ${ev.message || 'unknown error'}`), { code: 'page.worker-stopped' }));
    rpc.pending.clear();
  };
  rpc.worker = worker;
  // how many workers this page started (a cancel that ends the worker starts a new one next)
  document.body.dataset.workerStarts = String(++rpc.starts);
}

/**
 * Runs `op` in the worker; `onEvent` gets its progress / registration / sliced messages (and,
 * first, `{ type: 'started', id }`: the id `cancelCall` takes).
 */
export function call(op, args = {}, transfer = [], onEvent = null) {
  const rpc = state.rpc;
  if (!rpc.worker) startWorker();
  const id = rpc.nextId++;
  onEvent?.({ type: 'started', id });
  return new Promise((resolve, reject) => {
    rpc.pending.set(id, { resolve, reject, onEvent });
    rpc.worker.postMessage({ id, op, ...args }, transfer);
  });
}

/**
 * Asks the worker to stop call `id` at its next step (the `builtin` slice, between layers): it
 * rejects with `.cancelled`, the worker and its wasm state stay. A call that has no steps
 * finishes as if not asked (`cancelWorker` stops anything).
 */
export function cancelCall(id) {
  state.rpc.worker?.postMessage({ id: 0, op: 'cancel', target: id });
}

/** Stops whatever the worker does; pending calls reject with `.cancelled`. */
export function cancelWorker() {
  const rpc = state.rpc;
  rpc.worker?.terminate();
  rpc.worker = null;
  for (const [, p] of rpc.pending) p.reject(Object.assign(new Error('cancelled'), { cancelled: true }));
  rpc.pending.clear();
}
