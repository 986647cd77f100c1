//! The built-in planar slicer: a mesh → ordinary planar G-code, so the whole STL → machine
//! G-code path runs with nothing else installed (issue 14). It writes what the real slicers
//! write and the unwarp reads (`;LAYER_CHANGE`, `;Z:`, `;TYPE:`, M83/M82, retractions), so
//! nothing downstream has a special case.
//!
//! # Per layer
//! Layer k (0-based) spans `[z_k − h_k, z_k]` above the mesh's lowest point, with
//! `z_k = first_layer_height + k·layer_height`; it is cut at mid-height `z_k − h_k/2`:
//! 1. [`section`]: triangle–plane cuts chained into closed loops (open chains repaired or
//!    dropped and counted), simplified to [`region::RESOLUTION`], united by the nonzero rule
//!    ([`region::union_loops`]);
//! 2. [`walls`]: `perimeters` loops by inward offsetting; the region left inside; [`thin`]
//!    walls along the middle of the parts narrower than a line;
//! 3. [`skins`]: top/bottom solid regions by comparing the layer with the
//!    `top_solid_layers` above and `bottom_solid_layers` below;
//! 4. [`infill`]: rectilinear lines, solid at the line spacing, sparse at
//!    spacing / (`fill_density`/100), at `fill_angle` on even layers and +90° on odd ones
//!    (45°/−45° by default);
//! 5. skirt and brim on the first layer; [`order`]: nearest-neighbour travel, round holes
//!    with `avoid_crossing_perimeters` ([`travel`]);
//!    [`gcode_out`]: the G-code.
//!
//! [`slicing`] runs these one layer per step (progress and cancel between layers).
//!
//! The mesh is moved in X and Y so that the centre of its bounding box is at `center` (the bed
//! centre, as PrusaSlicer and Slic3r place parts; the shift is in [`SliceReport::shift`] and the
//! pipeline's registration finds it exactly); in Z the layers count from its lowest point.
//!
//! # Polygon crate: `i_overlay` 9.1 (MIT OR Apache-2.0)
//! Measured 2026-11-27 on this machine (release build, median of 200 runs, a 1000-vertex
//! star-shaped polygon of radius 20 mm, inward offset 0.4 mm; and its difference with a
//! 1000-vertex polygon overlapping it):
//!
//! | crate | offset | difference | pure Rust, builds for wasm32-unknown-unknown | licence |
//! |---|---|---|---|---|
//! | `i_overlay` 9.1 (bevel / mitre joins) | 2.1 ms / 4.2 ms | 0.45 ms | yes | MIT OR Apache-2.0 |
//! | `geo` 0.33 (`Buffer`, `BooleanOps`: `i_overlay` inside) | 2.1–2.5 ms | 0.36 ms | yes | MIT OR Apache-2.0 |
//! | `clipper2-rust` 1.2 (port of Clipper2) | 1.6–1.9 ms | 0.23 ms | yes | BSL-1.0 |
//! | `clipper2` 0.6, `geo-clipper` 0.9 | — | — | no: C++ Clipper via `cc` | MIT/Apache, ISC |
//!
//! `i_overlay` is chosen: the same licence as this crate, the engine `geo` itself uses (well
//! kept, one small dependency tree: `i_float`, `i_shape`, `i_tree`, `i_key_sort`), robust
//! integer snapping inside a float API, nonzero fill, and offsets with mitre joins; `geo`
//! would add its whole dependency tree for the same engine, and `clipper2-rust` (about 1.5×
//! faster here, a young machine-made port under another licence) is the fallback if the
//! bench's 5 s budget (issue 14) needs it. The timings are from a machine shared with other
//! jobs (± 30 %). It needs Rust 1.88 (`rust-version` in Cargo.toml).

pub mod gcode_out;
pub mod infill;
pub mod order;
pub mod region;
pub mod section;
pub mod settings;
pub mod skins;
pub mod slicing;
pub mod thin;
pub mod travel;
pub mod walls;

pub use settings::Settings;
pub use slicing::{Progress, Slicing};

use crate::mesh::Mesh;

/// What a printed line is, with PrusaSlicer's `;TYPE:` label.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Role {
    /// Perimeter 0 of an island.
    ExternalPerimeter,
    /// Perimeters 1… of an island.
    Perimeter,
    /// Sparse infill.
    InternalInfill,
    /// Solid infill inside the part and on bottom surfaces.
    SolidInfill,
    /// Solid infill open to the air above.
    TopSolidInfill,
    /// Solid infill over air (a bottom surface above the bed), at bridge flow.
    BridgeInfill,
    /// Loops around the first layer, apart from it.
    Skirt,
    /// Loops around the first layer, touching it.
    Brim,
}

impl Role {
    /// PrusaSlicer's `;TYPE:` label.
    pub fn label(self) -> &'static str {
        match self {
            Role::ExternalPerimeter => "External perimeter",
            Role::Perimeter => "Perimeter",
            Role::InternalInfill => "Internal infill",
            Role::SolidInfill => "Solid infill",
            Role::TopSolidInfill => "Top solid infill",
            Role::BridgeInfill => "Bridge infill",
            Role::Skirt => "Skirt",
            Role::Brim => "Brim",
        }
    }
}

/// One printed line: a closed loop or an open polyline, mm in the mesh's XY.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    /// What it is.
    pub role: Role,
    /// Its points; a closed loop does not repeat its first point until [`order`] readies it.
    pub points: Vec<[f64; 2]>,
    /// Whether it is a closed loop.
    pub closed: bool,
    /// The line's cross-section at each point, mm² (a segment deposits the mean of its two
    /// ends' per mm: a thin wall's `t·h`, [`thin`]); empty: [`Settings::line_area`] throughout.
    pub section: Vec<f64>,
}

/// What the slicer did and had to repair.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct SliceReport {
    /// Layers written.
    pub layers: usize,
    /// How far the mesh was moved in X and Y to centre it on `center`, mm.
    pub shift: [f64; 2],
    /// Open chains of the cuts closed across a gap (the mesh has open edges).
    pub repaired_loops: usize,
    /// Open chains of the cuts that could not be closed and were left out.
    pub dropped_chains: usize,
    /// Thin walls printed: lines along the middle of parts narrower than a line ([`thin`]).
    pub thin_walls: usize,
    /// Their length, mm.
    pub thin_wall_mm: f64,
    /// Thin parts left unprinted: narrower than [`thin::MIN_THIN_WIDTH`] or too short.
    pub thin_unprinted: usize,
    /// Filament fed by extrusions, mm.
    pub filament_mm: f64,
    /// Extruded volume, mm³ (filament × its cross-section).
    pub volume_mm3: f64,
    /// Retractions written.
    pub retractions: usize,
}

/// The G-code and its report.
#[derive(Clone, Debug, PartialEq)]
pub struct Sliced {
    /// The planar G-code.
    pub gcode: String,
    /// What was done.
    pub report: SliceReport,
}

/// An error of the built-in slicer.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum PlanarError {
    /// A setting's value is out of range.
    Setting {
        /// The setting's key.
        key: String,
        /// The value given.
        value: String,
        /// What is allowed.
        allowed: &'static str,
    },
    /// The settings JSON does not parse, or names an unknown key.
    SettingsJson {
        /// serde's message (with line and column) or the unknown key.
        message: String,
    },
    /// The settings' layer heights differ from the warp's (`warpslice run`).
    LayerHeight {
        /// `layer_height` or `first_layer_height`.
        key: &'static str,
        /// The settings' value, mm.
        value: f64,
        /// The warp's layer height, mm.
        warp: f64,
    },
    /// No layer of the mesh has anything to print.
    NothingToPrint {
        /// Layers cut.
        layers: usize,
    },
}

impl std::fmt::Display for PlanarError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlanarError::Setting {
                key,
                value,
                allowed,
            } => write!(
                f,
                "slicer setting {key} = {value} is not allowed: {allowed}"
            ),
            PlanarError::SettingsJson { message } => write!(
                f,
                "slicer settings: {message} (keys are PrusaSlicer's option names; `warpslice run --help` lists them)"
            ),
            PlanarError::LayerHeight { key, value, warp } => write!(
                f,
                "slicer setting {key} = {value} mm differs from the warp's layer height {warp} mm: the warped layers are {warp} mm apart; give --layer-height {value} instead, or leave {key} out"
            ),
            PlanarError::NothingToPrint { layers } => write!(
                f,
                "the built-in slicer found nothing to print in {layers} layers: the mesh has no closed cross-section (is it a surface without volume?)"
            ),
        }
    }
}

impl std::error::Error for PlanarError {}

crate::error_codes!(PlanarError, ERROR_CODES, "planar" {
    Setting => "planar.setting", "a built-in slicer setting out of range";
    SettingsJson => "planar.settings-json", "the slicer settings JSON does not parse or names an unknown key";
    LayerHeight => "planar.layer-height", "slicer layer heights that differ from the warp's";
    NothingToPrint => "planar.empty", "the mesh has no cross-section to print";
} wraps {});

/// Top of layer `k` above the mesh's lowest point, mm (`first + k·h`, by multiplication so
/// that every `;Z:` is on the grid however many layers there are).
pub fn layer_top(s: &Settings, k: usize) -> f64 {
    s.first_layer_height + k as f64 * s.layer_height
}

/// Slice `mesh` with `settings`; `header` goes into the file's first comment lines (the
/// steps of [`Slicing`] run to the end).
pub fn slice(mesh: &Mesh, settings: &Settings, header: &str) -> Result<Sliced, PlanarError> {
    Slicing::new(mesh, settings, header)?.finish()
}
