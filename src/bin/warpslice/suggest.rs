//! `warpslice overhangs`, `warpslice suggest` and `warpslice warp --suggested N` (issue 15):
//! the flags come from the core's `suggest::PARAMS`, the work from `warpslice::suggest`.

use std::path::Path;

use clap::{ArgMatches, Command};
use warpslice::pipeline::WarpOptions;
use warpslice::schema::Param;
use warpslice::suggest::{self, Model, SuggestOptions, SuggestReport};

use crate::args::machine_spec;
use crate::out::{put, say};
use crate::schema_args::{add, options_of};

/// Which of `suggest::PARAMS` a command takes.
pub mod which {
    /// `suggest`: all of them.
    pub const ALL: u8 = 0;
    /// `warp --suggested N`: the overhang angle and the families (`--layer-height` is the
    /// warp's own, N picks the entry).
    pub const SUGGESTED: u8 = 1;
    /// `overhangs`: the overhang angle.
    pub const ANGLE: u8 = 2;
}

fn params(which: u8) -> impl Iterator<Item = &'static Param> {
    suggest::PARAMS.iter().filter(move |p| match which {
        which::SUGGESTED => matches!(p.key, "overhang_angle" | "families"),
        which::ANGLE => p.key == "overhang_angle",
        _ => true,
    })
}

/// The `suggest` options a command's flags give.
#[derive(Debug)]
pub struct SuggestArgs<const WHICH: u8> {
    /// The options (defaults for the flags the command does not take).
    pub options: SuggestOptions,
}

impl<const WHICH: u8> clap::Args for SuggestArgs<WHICH> {
    fn augment_args(cmd: Command) -> Command {
        params(WHICH).fold(cmd, |c, p| add(c, p, &[]))
    }
    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

impl<const WHICH: u8> clap::FromArgMatches for SuggestArgs<WHICH> {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        Ok(SuggestArgs {
            options: options_of(m, params(WHICH))?,
        })
    }
    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

fn model(path: &Path) -> Result<Model, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    suggest::model_of(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// `warpslice overhangs MODEL [--warp …] [--overhang-angle θ] [--json]`.
pub fn overhangs(
    path: &Path,
    warp: Option<&WarpOptions>,
    angle: f64,
    json: bool,
) -> Result<(), String> {
    let m = model(path)?;
    let r = suggest::overhangs(&m, warp.map(|o| &o.warp), angle, json)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if json {
        put(&(serde_json::to_string(&r).map_err(|e| e.to_string())? + "\n"));
        return Ok(());
    }
    say!(
        "{}: {} triangles, surface {:.2} mm², overhang angle {}°",
        path.display(),
        r.triangles,
        r.planar.surface_mm2,
        r.overhang_angle_deg
    );
    say!(
        "planar: {:.2} mm² overhanging ({:.2} % of the surface, {} facets)",
        r.planar.area_mm2,
        r.planar.percent,
        r.planar.facets
    );
    if let (Some(w), Some(f)) = (&r.warped, &r.flags) {
        say!(
            "{f}: {:.2} mm² overhanging ({:.2} %, {} facets), largest tool tilt {:.2}°",
            w.area_mm2,
            w.percent,
            w.facets,
            w.largest_tilt_deg
        );
    }
    Ok(())
}

/// `warpslice suggest MODEL --machine M […]`.
pub fn suggest(
    path: &Path,
    machine: &str,
    options: &SuggestOptions,
    json: bool,
) -> Result<(), String> {
    let m = model(path)?;
    let spec = machine_spec(machine)?;
    let r = suggest::suggest(&m, &spec, options).map_err(|e| format!("{}: {e}", path.display()))?;
    if json {
        put(&(serde_json::to_string_pretty(&r.suggestions).map_err(|e| e.to_string())? + "\n"));
        return Ok(());
    }
    print_table(path, machine, &r);
    Ok(())
}

fn print_table(path: &Path, machine: &str, r: &SuggestReport) {
    say!(
        "{} on {}: planar overhang {:.2} mm² ({:.2} % of the surface) at θ = {}°; {} warps measured",
        path.display(),
        r.machine,
        r.planar.area_mm2,
        r.planar.percent,
        r.overhang_angle_deg,
        r.measured
    );
    if r.suggestions.is_empty() {
        say!("no admissible warp of these families leaves less overhang than planar printing on this machine");
        return;
    }
    say!(
        "{:>3}  {:>12}  {:>6}  {:>6}  {:>6}  {:>10}  flags",
        "#",
        "overhang mm²",
        "%",
        "tilt°",
        "layers",
        "triangles"
    );
    for (i, s) in r.suggestions.iter().enumerate() {
        say!(
            "{:>3}  {:>12.2}  {:>6.2}  {:>6.2}  {:>6}  {:>10}  {}",
            i + 1,
            s.overhang_area_mm2,
            s.overhang_percent,
            s.largest_tilt_deg,
            s.layers,
            s.triangles_estimate,
            s.flags
        );
    }
    say!(
        "apply one: warpslice warp {} --suggested N --machine {machine} -o OUT.stl",
        path.display()
    );
}

/// `warpslice warp MODEL --suggested N --machine M`: the options with entry N's warp.
pub fn suggested(
    path: &Path,
    machine: Option<&str>,
    n: usize,
    options: &SuggestOptions,
    mut warp: WarpOptions,
) -> Result<WarpOptions, String> {
    let machine = machine.ok_or("--suggested needs --machine (the search is per machine)")?;
    let m = model(path)?;
    let spec = machine_spec(machine)?;
    let options = SuggestOptions {
        layer_height: warp.layer_height,
        ..options.clone()
    };
    let s = suggest::suggested(&m, &spec, &options, n)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    say!(
        "suggestion {n} on {}: {} ({:.2} mm² overhang left, largest tilt {:.2}°)",
        spec.name,
        s.flags,
        s.overhang_area_mm2,
        s.largest_tilt_deg
    );
    warp.warp = s.warp;
    Ok(warp)
}
