//! The options of the unwarp step.

use serde::{Deserialize, Serialize};

use super::{Flow, UnwarpError};
use crate::schema::{Param, ParamDefault, ParamType};
use crate::tolerance::{
    DEFAULT_MAX_SEGMENT, DEFAULT_RETRACT_LENGTH, DEFAULT_TOLERANCE, DEFAULT_TRAVEL_CLEARANCE,
    MAX_PLACEMENT_MM, MIN_MAX_SEGMENT, MIN_TOLERANCE,
};

/// Options of the unwarp step (CLI: `warpslice unwarp`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct UnwarpOptions {
    /// `--tolerance`, mm.
    pub tolerance: f64,
    /// `--max-segment`, mm.
    pub max_segment: f64,
    /// `--flow`, `--ramp`.
    pub flow: Flow,
    /// `--z-offset`, mm: added to every output z (seed 000 §4.3.2 uses +0.2 … +0.3 mm).
    pub z_offset: f64,
    /// `--drop-skirt`.
    pub drop_skirt: bool,
    /// `--offset dx,dy`: the slicer's placement, instead of finding it.
    pub offset: Option<[f64; 2]>,
    /// `--place x,y`: where the model frame's origin (the centre of the part's footprint) goes
    /// in the output, instead of the slicer's placement.
    pub place: Option<[f64; 2]>,
    /// Clearance above printed material on lifted travels, mm.
    pub travel_clearance: f64,
    /// Retraction added before a lifted travel when the slicer did not retract, mm.
    pub retract_length: f64,
    /// Keep the toolpath in memory (for the machines and the preview).
    pub collect_toolpath: bool,
    /// With `collect_toolpath`: keep one point in `toolpath_every` (counted over every point
    /// of the run) and every point on another layer than the last one kept, so that each
    /// layer's first point is kept (the page's preview decimation, done where the points are
    /// made instead of after copying every one out of wasm); 0 and 1 keep every point. See
    /// [`crate::toolpath::Thinning`].
    pub toolpath_every: u32,
}

impl Default for UnwarpOptions {
    fn default() -> Self {
        UnwarpOptions {
            tolerance: DEFAULT_TOLERANCE,
            max_segment: DEFAULT_MAX_SEGMENT,
            flow: Flow::default(),
            z_offset: 0.0,
            drop_skirt: false,
            offset: None,
            place: None,
            travel_clearance: DEFAULT_TRAVEL_CLEARANCE,
            retract_length: DEFAULT_RETRACT_LENGTH,
            collect_toolpath: false,
            toolpath_every: 1,
        }
    }
}

impl UnwarpOptions {
    /// Check the values; names the bad option and what is allowed.
    pub fn validate(&self) -> Result<(), UnwarpError> {
        for (name, v) in [
            ("tolerance", self.tolerance),
            ("max-segment", self.max_segment),
            ("flow", self.flow.factor),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(UnwarpError::Option {
                    name,
                    value: v.to_string(),
                    allowed: "a positive number",
                });
            }
        }
        if self.tolerance < MIN_TOLERANCE {
            return Err(UnwarpError::Option {
                name: "tolerance",
                value: self.tolerance.to_string(),
                allowed: "at least 0.001 mm (the file's coordinates have 3 decimals)",
            });
        }
        if self.max_segment < MIN_MAX_SEGMENT {
            return Err(UnwarpError::Option {
                name: "max-segment",
                value: self.max_segment.to_string(),
                allowed: "at least 0.01 mm (the file's coordinates have 3 decimals)",
            });
        }
        for (name, v) in [("place", self.place), ("offset", self.offset)] {
            if let Some([x, y]) = v {
                if [x, y]
                    .iter()
                    .any(|c| c.is_finite() && c.abs() > MAX_PLACEMENT_MM)
                {
                    return Err(UnwarpError::Option {
                        name,
                        value: format!("{x},{y}"),
                        allowed: "x,y within ±10000 mm (a position on a printer's bed)",
                    });
                }
            }
        }
        if !self.z_offset.is_finite() {
            return Err(UnwarpError::Option {
                name: "z-offset",
                value: self.z_offset.to_string(),
                allowed: "a finite number (mm)",
            });
        }
        if let Some([f0, zr]) = self.flow.ramp {
            if !(f0.is_finite() && f0 > 0.0 && zr.is_finite() && zr > 0.0) {
                return Err(UnwarpError::Option {
                    name: "ramp",
                    value: format!("{f0},{zr}"),
                    allowed: "f0,z_ramp with f0 > 0 and z_ramp > 0 mm",
                });
            }
        }
        Ok(())
    }

    /// [`UnwarpOptions::validate`], and what needs the job: a negative `z_offset` deeper than
    /// [`crate::tolerance::BED_CLAMP_MAX_LAYER_FRACTION`] of the layer height would push the
    /// whole first layer into the bed (the clamp would flatten it with E scaled toward 0).
    pub fn validate_for(&self, job: &crate::job::Job) -> Result<(), UnwarpError> {
        self.validate()?;
        let limit = crate::tolerance::BED_CLAMP_MAX_LAYER_FRACTION * job.layer_height;
        if self.z_offset < -limit {
            return Err(UnwarpError::Option {
                name: "z-offset",
                value: self.z_offset.to_string(),
                allowed: "at least minus half the job's layer height: a deeper offset pushes the first layer into the bed",
            });
        }
        Ok(())
    }
}

/// The unwarp's parameters as the CLI and the page show them ([`crate::describe`]); keys are
/// those of [`UnwarpOptions`] (dotted: nested).
pub const PARAMS: &[Param] = &[
    Param::number("tolerance", "--tolerance", "Tolerance")
        .unit("mm")
        .range(Some(MIN_TOLERANCE), None, (false, false))
        .step(0.001)
        .default(ParamDefault::Number(DEFAULT_TOLERANCE))
        .help("split each move until the mapped polyline stays this close to the exact image"),
    Param::number("max_segment", "--max-segment", "Max segment")
        .unit("mm")
        .range(Some(MIN_MAX_SEGMENT), None, (false, false))
        .step(0.1)
        .default(ParamDefault::Number(DEFAULT_MAX_SEGMENT))
        .help("longest object extrusion segment after unwarping (skirt and brim stay as sliced)"),
    Param::number("flow.factor", "--flow", "Flow")
        .range(Some(0.0), None, (true, false))
        .step(0.01)
        .default(ParamDefault::Number(1.0))
        .help("global flow factor"),
    Param::number("flow.ramp", "--ramp", "Flow ramp f0,z")
        .of(ParamType::Pair)
        .optional()
        .help("flow rises from f0 at z = 0 to 1 at z (seed 000 §4.3.2: 0.8,1.2)"),
    Param::number("z_offset", "--z-offset", "Z offset")
        .unit("mm")
        .step(0.05)
        .default(ParamDefault::Number(0.0))
        .help("added to every output z (seed 000 uses +0.2 … +0.3 mm)"),
    Param::number("drop_skirt", "--drop-skirt", "Drop skirt")
        .of(ParamType::Bool)
        .default(ParamDefault::Bool(false))
        .help("drop skirt and brim instead of printing them flat"),
    Param::number("offset", "--offset", "Slicer placement dx,dy")
        .of(ParamType::Pair)
        .unit("mm")
        .optional()
        .help("where the slicer put the part, instead of finding it"),
    Param::number("place", "--place", "Place x,y")
        .of(ParamType::Pair)
        .unit("mm")
        .optional()
        .help("put the part's footprint centre here in the output (e.g. 0,0 on an A/B table)"),
];
