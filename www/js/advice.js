// What to do about an error, keyed by the core's stable error code (`describe().errors`; the
// worker passes `{code, message}`). The message is shown as it is and never read here: a
// reworded message changes nothing. A code without its own entry gets its area's advice (the
// part before the dot). Codes `page.*` are the page's own. No DOM here (the tests import it).

/** Advice by code. */
export const ADVICE = {
  'mesh.empty': 'The file is empty: export the STL again from your CAD program.',
  'mesh.not-stl': 'This file is not an STL (an image, a UTF-16 text, an archive or a 3MF project): export the model as STL from your CAD program.',
  'mesh.too-small': 'The model is smaller than a printed line: it is probably in metres or inches — scale it (×1000 or ×25.4) and export again.',
  'mesh.truncated': 'The file was cut short (an interrupted download or copy?): export or copy the STL again.',
  'mesh.face-count': 'The binary STL is damaged (its face count disagrees with its size): export it again.',
  'mesh.syntax': 'The ASCII STL has a line that does not parse (the message says which): export it again, or as binary STL.',
  'mesh.non-finite': 'The model has NaN or infinite coordinates: repair it in your CAD program and export again.',
  'mesh.no-triangles': 'The file holds no triangles: export the part itself, not an empty sketch or assembly.',
  'warp.bad-parameter': 'A warp parameter is outside its range: the message names it; change it and warp again.',
  'warp.not-monotonic': 'The flat base blends into the warp too steeply: make the base range (z0 … z1) longer or lower the warp.',
  'warp.inverse-failed': 'Part of the model lies where this warp is not defined: move the warp\'s centre or axis, or change its radius.',
  'warp.base-not-supported': 'This warp cannot blend into a flat base: switch the flat base off.',
  'register.no-object-extrusions': 'This G-code prints nothing of the model: slice the warped STL downloaded in step 3 (not the original) and open the slicer\'s output.',
  'register.mismatch': 'The placement is always detected here: slice the warped STL downloaded in step 3, not the original model, with first layer height = layer height.',
  'register.cut-short': 'The G-code stops before the top of the part and its end is missing: the file was cut short (an interrupted export, copy or download). Export it from the slicer again.',
  'register.undetermined': 'The printed walls do not pin the part\'s placement (a part without walls in some direction?): give the slicer\'s placement (“Slicer placement dx,dy”) or slice with walls.',
  'register.features-dropped': 'The slicer left part of the model unprinted (a feature thinner than a line), so the box cannot place the part: load the warped STL of step 3 with the G-code, or give the slicer\'s placement (“Slicer placement dx,dy”).',
  'register.more-than-the-model': 'The G-code prints more than the warped part: copies or other objects on the plate (slice the warped STL of step 3 alone, one copy), or, in a file without feature labels, a wipe/prime tower or brim (turn them off, or use a slicer that writes ;TYPE: or ; FEATURE: labels).',
  'register.anchor-layer': 'Slice with first layer height = layer height (the value under “Slicing”): the first layer is the anchor slab.',
  'gcode.bad-arc': 'Turn off arc fitting in the slicer (PrusaSlicer: Printer settings → Arc fitting: disabled) and export again.',
  'gcode.bad-word': 'A move word on the line named has no plain decimal number or appears twice (exponent notation such as 1e-05, NaN): a firmware would misread it. Export the G-code from the slicer again, or fix that line.',
  'gcode.cr-line-ends': 'The G-code\'s lines end with CR alone (old Mac line ends): convert them to LF or CR LF in an editor and load it again.',
  'gcode.binary': 'Export plain-text G-code (PrusaSlicer: Printer settings → General → “Supports binary G-code” off).',
  'planar.settings-json': 'A built-in slicer setting is not one the slicer knows (a misspelt key, from a link or a loaded file): the message lists the keys it takes; correct or remove it under “Built-in slicer settings” (step 3).',
  'planar.setting': 'A built-in slicer setting is out of range: the message names it and what it takes; change it under “Built-in slicer settings” (step 3).',
  'planar.layer-height': 'The built-in slicer slices at the warp\'s layer height: remove layer_height / first_layer_height from the slicer settings, and set the layer height under “Slicing” (step 2) instead.',
  'planar.empty': 'The warped model has no closed cross-section to print (a surface without volume, or a part thinner than a layer): check the model in step 1.',
  'job.format': 'The job file is from another warpslice version: warp the model again here.',
  'job.parse': 'The job file is not a warpslice job: warp the model again.',
  'job.stl-mismatch': 'The warped STL is not this job\'s: warp the model again and slice the STL of that warp.',
  'job.hash': 'Use the job file of this exact warped STL; warp again if in doubt.',
  'machine.axis-limit': 'The part needs more travel than an axis has: lower the warp, place the part elsewhere (“place”), or pick a machine with the range.',
  'machine.travel': 'A move would leave an axis\'s travel (the message gives the output and input line, the axis and its limit): place the part elsewhere (“place”), print a smaller part or use another warp, or correct the travel in the custom machine JSON.',
  'machine.unreachable-orientation': 'The machine cannot tilt the nozzle that far here: lower the warp or pick a warp this machine prints.',
  'machine.mandrel-mismatch': 'Set the cylindrical warp\'s axis to the machine\'s mandrel axis.',
  'machine.bad-json': 'The custom machine JSON does not parse: fix it or switch it off (the message says where).',
  'machine.bad-spec': 'A parameter of the machine is unusable: fix the custom machine JSON (the message names it).',
  'unwarp.axis-reset': 'The slicer resets X/Y/Z with G92 inside the print: remove G92 X/Y/Z from its start and layer-change G-code (G92 E0 is fine).',
  'unwarp.inches': 'Set the slicer to millimetres (G21): inch units (G20) inside the print are not unwarped.',
  'unwarp.shape-mismatch': 'This G-code does not fit this job\'s part: it was sliced from another warp (angle, direction, centre) or another model, or the slicer placement given is wrong. Slice the warped STL of step 3 with these warp settings, or leave “Slicer placement” empty.',
  'unwarp.bad-place': 'Give “place” as two numbers x,y in mm, or switch it off.',
  'unwarp.option': 'An unwarp option is outside its range: the message names it; change it in step 4.',
  'machine.bad-option': 'A machine option is outside its range (the message says which and what it takes): correct it in step 4 (interpolation bounds are two numbers mm,degrees from 0.001 to 10).',
  'machine.unsupported-flavour': 'This firmware cannot drive this machine\'s axes: choose another firmware (flavour) in step 4, or the machine\'s default.',
  'unwarp.probe-in-region': 'The slicer homes Z or probes the bed (G28, G29, G30) in the middle of the print, where the part stands: move that command to the start G-code, or home only X and Y (G28 X Y).',
  'machine.pose-lost': 'A command in the middle of the print (G28 X Y, G27, a tool change) moves the head where the G-code does not say, and this machine cannot come back safely: move it to the start or end G-code, or unwarp for a 3-axis printer.',
  'unwarp.outside-relative': 'The slicer\'s start G-code moves relatively (G91) before X, Y and Z are all known (after homing), which this machine\'s axes cannot follow: write those moves as absolute moves (G90), or give X, Y and Z first.',
  'unwarp.outside-arc': 'The slicer\'s start or end G-code has an arc (G2/G3), which cannot be converted to this machine\'s axes: use straight G1 moves there, or remove the prime line.',
  'unwarp.outside-axis-reset': 'The slicer\'s start or end G-code resets X/Y/Z with G92, which this machine\'s axes cannot follow: remove it (G92 E0 is fine).',
  'unwarp.outside-inches': 'Set the slicer to millimetres (G21): inch units (G20) cannot be converted to this machine\'s axes.',
  'unwarp.outside-partial-extrusion': 'After homing, the slicer\'s start G-code extrudes with a move that gives only some of X, Y, Z, and this machine needs all three: give X, Y and Z in the first move after homing, or remove the prime line.',
  'unwarp.relative-positioning': 'Set the slicer to absolute XYZ positioning (G90); relative extrusion (M83) is fine.',
  'check.bad-number': 'A word of a G line is not a number (the message gives the line): correct that line of the G-code and check it again.',
  'check.no-moves': 'No move of this G-code names the machine\'s axes: pick the machine the file was written for in step 2 (or its custom JSON), or check that the file is plain-text G-code.',
  'options.invalid': 'An option is outside its range: the message names it; change it and try again.',
  'page.machine-json': 'The custom machine JSON is not a JSON object: fix it or switch “custom machine” off.',
  'page.no-warp': 'The G-code is unwarped with the job of the warped model: open a model and warp it first (steps 1–2).',
  'page.settings': 'This file is not warpslice settings: export the settings again from the page (“Export settings”).',
  'page.worker-stopped': 'The background worker stopped (out of memory?): reload the page and try again.',
};

/** Advice by area, for a code without its own entry. */
export const AREA_ADVICE = {
  mesh: 'Check that the file is an STL exported from a CAD program (ASCII or binary) and not empty; re-export it if it was cut short.',
  warp: 'Lower the warp strength or angle, or change the flat base; then press Warp again.',
  register: 'Check that this G-code was sliced from the warped STL downloaded in step 3 with these settings (same layer height, first layer height = layer height).',
  gcode: 'Check that this is the slicer\'s plain-text G-code of the warped STL.',
  job: 'Use the job file written with this warped STL; warp again if in doubt.',
  machine: 'Check the machine and its limits; lower the warp or place the part elsewhere.',
  unwarp: 'Check that this G-code was sliced from the warped STL downloaded in step 3 with these settings (same layer height, first layer height = layer height), and that it is plain text.',
  options: 'Check the options of steps 2 and 4.',
  check: 'Check that the file is a plain-text G-code of the machine chosen in step 2.',
};

/**
 * The advice for an error code: `{ key, text }`, `key` being the code or `area:<area>` for an
 * area's advice; null for no code or an unknown area.
 */
export function adviceFor(code) {
  if (typeof code !== 'string' || !code) return null;
  if (ADVICE[code]) return { key: code, text: ADVICE[code] };
  const area = code.split('.')[0];
  return AREA_ADVICE[area] ? { key: `area:${area}`, text: AREA_ADVICE[area] } : null;
}
