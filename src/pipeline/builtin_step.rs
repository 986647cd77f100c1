//! The built-in slicer as a pipeline step: the warped STL of a job → planar G-code
//! ([`crate::planar`]), on bytes, so the CLI and the web worker run the same code. The worker
//! steps it ([`start_builtin`], then [`Slicing::step`] per layer: progress and cancel between
//! layers); the CLI runs it to the end ([`slice_builtin`]).

use super::{warped_mesh, Error};
use crate::job::Job;
use crate::planar::{PlanarError, Settings, Sliced, Slicing};

/// Layer heights that differ by less than this are the same, mm: the settings and the job
/// write them with at most 3 decimals (0.0005 mm rounding).
pub const LAYER_HEIGHT_MATCH: f64 = 1e-6;

/// The settings of a slice of `job`'s warped STL from a settings JSON object (the CLI's
/// `--slicer-settings` file; `""` for none): the defaults with both layer heights the job's
/// ([`Settings::for_layers`], as `warpslice run` starts), then the keys the JSON names. Unknown
/// keys, wrong types and values out of range are [`PlanarError`]s.
pub fn builtin_settings(job: &Job, json: &str) -> Result<Settings, Error> {
    let mut s = Settings::for_layers(job.layer_height);
    if !json.trim().is_empty() {
        s.apply_json(json)?;
    }
    Ok(s)
}

/// Start slicing the warped STL `stl` of `job` with the built-in slicer. The layers must be
/// the warp's: `layer_height` and `first_layer_height` equal to the job's layer height, else
/// [`PlanarError::LayerHeight`] (the warp and its anchor were built for layers of the job's
/// height; other layers would not lie on the warped layer surfaces).
pub fn start_builtin(stl: &[u8], job: &Job, settings: &Settings) -> Result<Slicing, Error> {
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
    Ok(Slicing::new(&mesh, settings, &header)?)
}

/// Slice the warped STL `stl` of `job` with the built-in slicer ([`start_builtin`] run to the
/// end).
pub fn slice_builtin(stl: &[u8], job: &Job, settings: &Settings) -> Result<Sliced, Error> {
    Ok(start_builtin(stl, job, settings)?.finish()?)
}
