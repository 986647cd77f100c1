//! Named tolerances and defaults. Each constant says what it bounds.

/// Default longest triangle edge after subdivision, mm (`--max-edge`).
pub const DEFAULT_MAX_EDGE: f64 = 1.0;
/// Default chord tolerance, mm (`--tolerance`): the largest distance between a warped/unwarped
/// polyline and the exact image of the straight edge or move it replaces.
pub const DEFAULT_TOLERANCE: f64 = 0.01;
/// Default longest extruding segment after unwarping, mm (`--max-segment`).
pub const DEFAULT_MAX_SEGMENT: f64 = 1.0;
/// Finest `--tolerance` accepted, mm: the output's coordinates have 3 decimals (0.0005 mm
/// rounding), so a finer tolerance cannot show in the file, and it bounds the pieces per move
/// (`1e-12` made a 1 MB chunk's output overflow memory).
pub const MIN_TOLERANCE: f64 = 0.001;
/// Shortest `--max-segment` accepted, mm: ten steps of the written 0.001 mm resolution (pieces
/// per move ≤ length / 0.01).
pub const MIN_MAX_SEGMENT: f64 = 0.01;
/// Largest |x| or |y| of `--place` and `--offset`, mm: no printer's bed reaches 10 m, and the
/// travel planner samples the bed between the part and the placement (`--place 1e9,0` spun for
/// minutes).
pub const MAX_PLACEMENT_MM: f64 = 10_000.0;
/// The smallest model `warp` accepts: its width (x or y, the larger) and its height must reach
/// this, mm — a line of a 0.4 mm nozzle (0.45 mm wide) and two 0.2 mm layers; a smaller model
/// prints nothing (a 1 µm model, an STL in metres, failed later in the slicer).
pub const MIN_MODEL_SIZE: f64 = 0.45;
/// Default intended layer height, mm (written to the job; the slicer's actual first layer and
/// layer height are read back from the G-code).
pub const DEFAULT_LAYER_HEIGHT: f64 = 0.2;
/// Registration: the largest accepted mismatch between the G-code's object-extrusion bounding
/// box and the warped mesh's, mm. Above it the G-code is taken to be of another model.
pub const MAX_REGISTRATION_RESIDUAL: f64 = 1.0;
/// A machine that cannot realise the requested tool axis (a B head beyond its range or
/// across its tilt plane, the polar and lathe presets, a 3-axis printer) prints with another
/// one; beyond this angle between the two, degrees, the unwarp's report warns with the count
/// of such moves and the largest angle. At 1° a nozzle face 1 mm wide rises
/// 0.5 mm · sin 1° ≈ 0.009 mm at its edge: below the shape check's 0.02 mm
/// ([`crate::unwarp::shape::SHAPE_TOLERANCE_NORMAL`]); more is a visible difference.
pub const DROPPED_TILT_WARN_DEG: f64 = 1.0;
/// Accuracy of the inverse of a warp with a 1-D numeric solve (the `--base` blend), mm.
pub const INVERSE_SOLVE_TOLERANCE: f64 = 1e-12;
/// Below this distance two points or lengths are taken to be equal, mm.
pub const LENGTH_EPSILON: f64 = 1e-9;
/// Chord tolerance for linearising G2/G3 arcs when reading G-code, mm.
pub const ARC_CHORD_TOLERANCE: f64 = 0.005;
/// Travel: clearance kept above everything printed so far, mm.
pub const DEFAULT_TRAVEL_CLEARANCE: f64 = 1.0;
/// Travel: retraction added when the slicer did not retract before a lifted travel, mm of filament.
pub const DEFAULT_RETRACT_LENGTH: f64 = 0.8;
/// Lowest z any output point may have, mm (the bed is z = 0; see `unwarp` for the clamp).
pub const BED_Z: f64 = 0.0;
/// The deepest negative `--z-offset`, as a fraction of the job's layer height: deeper pushes the
/// whole first layer into the bed (points below the bed are clamped to it after every offset,
/// their E reduced by the depth).
pub const BED_CLAMP_MAX_LAYER_FRACTION: f64 = 0.5;

/// `--resolution` given to PrusaSlicer and Slic3r by `warpslice run`, mm: the slicer may simplify
/// its sliced polygons by this much (half the subdivision tolerance [`DEFAULT_TOLERANCE`]). Their
/// default, 0 (full resolution), keeps every vertex of the subdivided warped mesh and is 2–3×
/// slower on it (measured: a warped gear wheel in Slic3r 27.8 s → 8.4 s, a warped cylinder in
/// PrusaSlicer 16.0 s → 6.5 s). CuraEngine simplifies by default.
pub const SLICER_RESOLUTION: f64 = 0.005;
