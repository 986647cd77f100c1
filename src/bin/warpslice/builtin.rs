//! `run --slicer builtin`: the built-in slicer's settings from the flags, and `--keep-sliced`.

use std::path::Path;

use warpslice::pipeline::files::{job_path, RunFiles};
use warpslice::planar::{Settings, SliceReport};

use crate::out::{read_text, say, write};

/// The settings: the warp's layer height for both layer heights and `relative_e` for the E
/// mode, then `--slicer-settings FILE` (keys it names), then each `--set key=value` in order.
pub fn settings(
    layer_height: f64,
    file: Option<&Path>,
    sets: &[String],
    relative_e: bool,
) -> Result<Settings, String> {
    let mut s = Settings {
        use_relative_e_distances: relative_e,
        ..Settings::for_layers(layer_height)
    };
    if let Some(f) = file {
        s.apply_json(&read_text(f)?)
            .map_err(|e| format!("{}: {e}", f.display()))?;
    }
    for a in sets {
        s.set(a).map_err(|e| e.to_string())?;
    }
    Ok(s)
}

/// `--keep-sliced FILE`: copy the planar G-code of the run to FILE and its job to
/// FILE.job.json.
pub fn keep_sliced(output: &Path, keep: Option<&Path>) -> Result<(), String> {
    let Some(keep) = keep else { return Ok(()) };
    let files = RunFiles::next_to(output);
    let gcode =
        std::fs::read(&files.sliced).map_err(|e| format!("{}: {e}", files.sliced.display()))?;
    write(keep, &gcode)?;
    let job = read_text(&job_path(&files.warped))?;
    let mut job_file = keep.as_os_str().to_owned();
    job_file.push(".job.json");
    write(Path::new(&job_file), job.as_bytes())?;
    say!(
        "kept the planar G-code as {} with its job {}",
        keep.display(),
        Path::new(&job_file).display()
    );
    Ok(())
}

/// The built-in slicer's report.
pub fn print_report(stl: &Path, gcode: &Path, r: &SliceReport) {
    say!(
        "sliced {} with the built-in slicer → {} ({} layers, {:.1} mm³ in {:.1} mm of filament, {} retractions)",
        stl.display(),
        gcode.display(),
        r.layers,
        r.volume_mm3,
        r.filament_mm,
        r.retractions
    );
    if r.repaired_loops + r.dropped_chains > 0 {
        say!(
            "slicer repairs: {} open cross-sections closed (gaps ≤ {} mm), {} left out",
            r.repaired_loops,
            warpslice::planar::section::REPAIR_GAP,
            r.dropped_chains,
        );
    }
    if r.thin_walls + r.thin_unprinted > 0 {
        say!(
            "thin walls: {} lines, {:.1} mm, along parts narrower than a line; {} thin parts narrower than {} mm left out",
            r.thin_walls,
            r.thin_wall_mm,
            r.thin_unprinted,
            warpslice::planar::thin::MIN_THIN_WIDTH
        );
    }
}
