// Step 3's one-click path: "Slice here and unwarp" — the warped mesh sliced by the core's
// built-in planar slicer in the worker (one layer per step: progress, and Cancel between layers),
// then the same unwarp, preview, checks and downloads as a G-code dropped in step 4
// (`runToResult`). The CLI's equivalent: `warpslice run MODEL --slicer builtin [--set k=v…]
// <warp and unwarp flags>` (the summary's command line).
import { state } from './state.js';
import { baseName } from './dom.js';
import { call, cancelCall, cancelWorker } from './worker-client.js';
import { slicerSettings } from './slicer-form.js';
import { runToResult } from './steps.js';

/** Slices the warped model here and unwarps it. */
export async function doSliceHere() {
  const settings = slicerSettings();
  const run = { id: null, phase: 'slice', cancelAsked: false };
  state.slice = run;
  try {
    await runToResult({
      what: `slice “${state.stlName}” here and unwarp it`,
      request: (args, onEvent) => call('builtin', { ...args, settings, slicedName: `${baseName(state.stlName)}.sliced.gcode` }, [], onEvent),
      again: doSliceHere,
      onEvent: (ev) => {
        if (ev.type === 'started') run.id = ev.id;
        if (ev.type === 'sliced') {
          run.phase = 'unwarp';
          // a cancel that came after the last layer: the unwarp has no steps, stop the worker
          if (run.cancelAsked) cancelWorker();
        }
      },
    });
  } finally {
    if (state.slice === run) state.slice = null;
  }
}

/**
 * The Cancel button: a built-in slice stops between two layers (the worker stays); anything
 * else (an unwarp, a check) stops by ending the worker.
 */
export function cancelRun() {
  const run = state.slice;
  if (run && run.phase === 'slice' && run.id != null) {
    run.cancelAsked = true;
    cancelCall(run.id);
  } else {
    cancelWorker();
  }
}
