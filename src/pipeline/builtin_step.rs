//! The built-in slicer as a pipeline step: the warped STL of a job → planar G-code
//! ([`crate::planar`]), on bytes, so the CLI and (later) the web worker run the same code.

use super::{warped_mesh, Error};
use crate::job::Job;
use crate::planar::{slice, PlanarError, Settings, Sliced};

/// Layer heights that differ by less than this are the same, mm: the settings and the job
/// write them with at most 3 decimals (0.0005 mm rounding).
pub const LAYER_HEIGHT_MATCH: f64 = 1e-6;

/// Slice the warped STL `stl` of `job` with the built-in slicer. The layers must be the
/// warp's: `layer_height` and `first_layer_height` equal to the job's layer height, else
/// [`PlanarError::LayerHeight`] (the warp and its anchor were built for layers of the job's
/// height; other layers would not lie on the warped layer surfaces).
pub fn slice_builtin(stl: &[u8], job: &Job, settings: &Settings) -> Result<Sliced, Error> {
    for (key, value) in [
        ("layer_height", settings.layer_height),
        ("first_layer_height", settings.first_layer_height),
    ] {
        if (value - job.layer_height).abs() > LAYER_HEIGHT_MATCH {
            return Err(PlanarError::LayerHeight {
                key,
                value,
                warp: job.layer_height,
            }
            .into());
        }
    }
    let mesh = warped_mesh(job, stl)?;
    let header = format!("warped STL of job {}", job.hash);
    Ok(slice(&mesh, settings, &header)?)
}
