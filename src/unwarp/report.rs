//! What the unwarp step did.

use serde::{Deserialize, Serialize};

use crate::emit::MachineReport;

/// What unwarp did.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct UnwarpReport {
    /// STL → G-code translation found (or given), mm.
    pub translation: [f64; 3],
    /// Residual of the bounding-box match, mm ([`crate::register`]; not checked with `--offset`).
    pub residual: f64,
    /// The fine registration against the warped mesh, when it was given.
    #[serde(default)]
    pub fit: Option<crate::register::FitReport>,
    /// Translation from model-frame coordinates to the output's X Y Z.
    pub model_to_output: [f64; 3],
    /// Lines of the slicer's G-code read (the last line number).
    pub lines_in: u64,
    /// Lines written to the output G-code.
    pub lines_out: u64,
    /// Object extrusion moves split into more than one piece.
    pub moves_split: u64,
    /// Extrusion segments written.
    pub segments_out: u64,
    /// Filament of all extrusions read, mm.
    pub e_in: f64,
    /// Filament of all extrusions written, mm.
    pub e_out: f64,
    /// Filament of the anchor layer (dropped), mm.
    pub e_anchor: f64,
    /// Filament of skirt/brim/custom extrusions (kept flat or dropped), mm.
    pub e_skirt: f64,
    /// "flat" or "dropped".
    pub skirt: String,
    /// Largest angle between tool axis and vertical on an extrusion, degrees.
    pub largest_tilt_deg: f64,
    /// Points clamped to the bed.
    pub clamped_points: u64,
    /// Object points written (the extrusion pieces' ends): what `clamped_points` is a share of.
    #[serde(default)]
    pub object_points: u64,
    /// How far the deepest clamped point was mapped below the bed, mm (0: none).
    #[serde(default)]
    pub deepest_below_bed: f64,
    /// The shape check ([`crate::unwarp::shape`]): the object point farthest outside the job's
    /// part, less what is allowed there, mm (negative: every point inside with this much room).
    #[serde(default)]
    pub shape_margin_mm: f64,
    /// The shape check by cross-section (with the warped mesh): the worst point's distance
    /// outside the mesh's cut at its layer's mid-height less its allowance, mm (refused above
    /// 0; `None` without the mesh).
    #[serde(default)]
    pub shape_section_margin_mm: Option<f64>,
    /// Object points beyond the shape check's tolerance (at most
    /// [`crate::unwarp::shape::SHAPE_OUTLIERS`] are accepted).
    #[serde(default)]
    pub shape_outliers: u64,
    /// Travels lifted over printed material.
    pub lifts: u64,
    /// Retractions added around lifted travels.
    pub retracts_added: u64,
    /// The machine emitter's measurements (`--machine`).
    pub machine: Option<MachineReport>,
    /// What the user should look at although the output was written (a file that looks cut
    /// short: see [`crate::register::ending`]).
    #[serde(default)]
    pub warnings: Vec<String>,
}

impl UnwarpReport {
    /// The warning for a machine that printed moves with a tool axis more than
    /// [`crate::tolerance::DROPPED_TILT_WARN_DEG`] from the requested one.
    pub fn dropped_tilt_warning(m: &crate::emit::MachineReport) -> Option<String> {
        (m.dropped_moves > 0).then(|| format!(
            "machine {}: {} moves printed with the tool axis up to {:.2}° away from the layer's normal (more than {}°): this machine cannot tilt that way (a B head beyond its range or across its tilt plane, a polar or lathe machine, a 3-axis printer), so those layers are printed with the nozzle off their surface normal; choose a machine that realises the warp's tilt, or a gentler warp",
            m.machine,
            m.dropped_moves,
            m.worst_dropped_deg,
            crate::tolerance::DROPPED_TILT_WARN_DEG
        ))
    }

    /// The warnings of a registration's findings: the file's end, region markers that leave
    /// object extrusions out.
    pub fn end_warnings(reg: &crate::register::Registration) -> Vec<String> {
        let mut w = Vec::new();
        if let Some([n, first]) = reg.outside_markers {
            w.push(format!(
                "{n} object extrusions lie outside the ;WARPSLICE_BEGIN/;WARPSLICE_END region (the first on line {first}): they are written as the slicer printed them, flat and not placed by the warp; move the markers so the region holds every layer of the part"
            ));
        }
        if let Some(n) = reg.unterminated_line {
            w.push(format!(
                "the G-code's last line ({n}) has no line end: the file may be cut short (a copy or download that did not finish), its last move perhaps in the middle of a number; export or copy it again"
            ));
        }
        if reg.end_gcode_missing {
            w.push(format!(
                "nothing after the last layer (line {}) ends the print — no heater off (M104 S0), no motors off (M84), no end macro (END_PRINT): the file may be cut short, or the slicer's end G-code is empty, and the heaters would stay on; check the end of the G-code",
                reg.region[1]
            ));
        }
        w
    }
}
