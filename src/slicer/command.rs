//! The command line of each slicer, as in `shared/tools/slice.sh`.

use super::{EMode, SliceOptions, SlicerError, SlicerKind};
use std::path::Path;

/// Bed/machine size given to CuraEngine, mm (x = y = z), as in `slice.sh`.
pub const CURA_MACHINE_SIZE: f64 = 200.0;

/// Arguments and extra environment for one slicer run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Invocation {
    /// Command-line arguments (without the executable).
    pub args: Vec<String>,
    /// Environment variables set for the child only.
    pub env: Vec<(String, String)>,
}

/// Checks the options and the STL path before anything runs.
pub fn validate(stl_path: &Path, opts: &SliceOptions) -> Result<(), SlicerError> {
    let lengths = [
        ("layer-height", opts.layer_height),
        ("nozzle-diameter", opts.nozzle_diameter),
        ("filament-diameter", opts.filament_diameter),
    ];
    for (option, value) in lengths {
        if !(value.is_finite() && value > 0.0) {
            return Err(SlicerError::InvalidOption {
                option,
                value: value.to_string(),
                expected: "a length in mm greater than 0",
            });
        }
    }
    if !(opts.resolution.is_finite() && opts.resolution >= 0.0) {
        return Err(SlicerError::InvalidOption {
            option: "resolution",
            value: opts.resolution.to_string(),
            expected: "a length in mm, 0 or more (0: full resolution)",
        });
    }
    let is_stl = stl_path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("stl"));
    if !is_stl {
        return Err(SlicerError::InvalidOption {
            option: "STL path",
            value: stl_path.display().to_string(),
            expected: "a file name ending in .stl (the slicers choose their reader by extension)",
        });
    }
    Ok(())
}

fn path_arg(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

fn strs(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

/// Builds the invocation. `cura_res` is the Cura resources folder (CuraEngine only).
pub fn build(
    stl_path: &Path,
    gcode_out: &Path,
    opts: &SliceOptions,
    cura_res: Option<&Path>,
) -> Invocation {
    let lh = opts.layer_height.to_string();
    let nozzle = opts.nozzle_diameter.to_string();
    let filament = opts.filament_diameter.to_string();
    let resolution = opts.resolution.to_string();
    let relative = opts.e_mode == EMode::Relative;
    let mut env = Vec::new();
    let mut args: Vec<String> = match opts.slicer {
        SlicerKind::PrusaSlicer => {
            let mut a = strs(&["--loglevel", "1", "--export-gcode"]);
            a.extend(strs(&["--layer-height", &lh, "--first-layer-height", &lh]));
            a.extend(strs(&["--nozzle-diameter", &nozzle]));
            a.extend(strs(&["--filament-diameter", &filament]));
            a.extend(strs(&["--gcode-flavor", "marlin2"]));
            a.extend(strs(&["--resolution", &resolution]));
            if relative {
                // PrusaSlicer refuses relative E unless every layer resets E.
                a.extend(strs(&[
                    "--use-relative-e-distances",
                    "--layer-gcode",
                    "G92 E0",
                ]));
            }
            a.extend(opts.extra_args.iter().cloned());
            a.extend(["--output".to_string(), path_arg(gcode_out)]);
            a.push(path_arg(stl_path));
            a
        }
        SlicerKind::Slic3r => {
            let mut a = strs(&["--layer-height", &lh, "--first-layer-height", &lh]);
            a.extend(strs(&["--nozzle-diameter", &nozzle]));
            a.extend(strs(&["--filament-diameter", &filament]));
            a.extend(strs(&["--gcode-flavor", "reprap"]));
            a.extend(strs(&["--resolution", &resolution]));
            if relative {
                a.push("--use-relative-e-distances".to_string());
            }
            a.extend(opts.extra_args.iter().cloned());
            a.extend(["--output".to_string(), path_arg(gcode_out)]);
            a.push(path_arg(stl_path));
            a
        }
        SlicerKind::CuraEngine => {
            let res = cura_res.unwrap_or(Path::new("."));
            let defs = res.join("definitions");
            let extruders = res.join("extruders");
            env.push((
                "CURA_ENGINE_SEARCH_PATH".to_string(),
                format!("{}:{}", defs.display(), extruders.display()),
            ));
            let size = CURA_MACHINE_SIZE.to_string();
            let mut a = vec![
                "slice".to_string(),
                "-j".to_string(),
                path_arg(&defs.join("fdmprinter.def.json")),
            ];
            let mut set = |kv: String| {
                a.push("-s".to_string());
                a.push(kv);
            };
            set(format!("machine_width={size}"));
            set(format!("machine_depth={size}"));
            set(format!("machine_height={size}"));
            set("center_object=true".to_string());
            set(format!("layer_height={lh}"));
            set(format!("layer_height_0={lh}"));
            set(format!("infill_sparse_thickness={lh}"));
            set(format!("machine_nozzle_size={nozzle}"));
            set(format!("material_diameter={filament}"));
            set(format!("relative_extrusion={relative}"));
            a.extend(opts.extra_args.iter().cloned());
            // `-s` after `-e0` applies to extruder 0, whose material_diameter defaults to 2.85.
            a.push("-e0".to_string());
            a.extend(strs(&["-s", &format!("material_diameter={filament}")]));
            a.extend(strs(&["-s", &format!("machine_nozzle_size={nozzle}")]));
            a.extend(["-l".to_string(), path_arg(stl_path)]);
            a.extend(["-o".to_string(), path_arg(gcode_out)]);
            a
        }
    };
    args.shrink_to_fit();
    Invocation { args, env }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts(slicer: SlicerKind, e_mode: EMode) -> SliceOptions {
        SliceOptions {
            slicer,
            e_mode,
            ..SliceOptions::default()
        }
    }

    #[test]
    fn prusaslicer_relative_resets_e_every_layer() {
        let inv = build(
            Path::new("a.stl"),
            Path::new("a.gcode"),
            &opts(SlicerKind::PrusaSlicer, EMode::Relative),
            None,
        );
        let joined = inv.args.join(" ");
        assert!(joined.contains("--use-relative-e-distances --layer-gcode G92 E0"));
        assert!(joined.contains("--layer-height 0.2 --first-layer-height 0.2"));
        assert!(joined.contains("--loglevel 1"));
        assert!(joined.contains("--resolution 0.005"), "{joined}");
        assert_eq!(inv.args.last().map(String::as_str), Some("a.stl"));
    }

    #[test]
    fn absolute_e_has_no_relative_flag() {
        for kind in [SlicerKind::PrusaSlicer, SlicerKind::Slic3r] {
            let inv = build(
                Path::new("a.stl"),
                Path::new("a.gcode"),
                &opts(kind, EMode::Absolute),
                None,
            );
            assert!(!inv.args.iter().any(|a| a == "--use-relative-e-distances"));
        }
    }

    #[test]
    fn curaengine_sets_extruder_filament_after_e0_and_search_path() {
        let inv = build(
            Path::new("a.stl"),
            Path::new("a.gcode"),
            &opts(SlicerKind::CuraEngine, EMode::Absolute),
            Some(Path::new("/res")),
        );
        let joined = inv.args.join(" ");
        assert!(joined.contains("-s relative_extrusion=false"));
        assert!(joined.contains("-e0 -s material_diameter=1.75"));
        assert!(joined.contains("-j /res/definitions/fdmprinter.def.json"));
        assert_eq!(
            inv.env,
            vec![(
                "CURA_ENGINE_SEARCH_PATH".to_string(),
                "/res/definitions:/res/extruders".to_string()
            )]
        );
    }

    #[test]
    fn layer_height_is_passed_for_first_layer_too() {
        let mut o = opts(SlicerKind::CuraEngine, EMode::Relative);
        o.layer_height = 0.25;
        let inv = build(
            Path::new("a.stl"),
            Path::new("b.gcode"),
            &o,
            Some(Path::new("/r")),
        );
        let joined = inv.args.join(" ");
        assert!(joined.contains("layer_height=0.25"));
        assert!(joined.contains("layer_height_0=0.25"));
    }

    #[test]
    fn validate_rejects_bad_lengths_and_non_stl_names() {
        let mut o = SliceOptions::default();
        assert!(validate(Path::new("x.STL"), &o).is_ok());
        assert!(matches!(
            validate(Path::new("x.bin"), &o),
            Err(SlicerError::InvalidOption { .. })
        ));
        assert!(validate(Path::new("x"), &o).is_err());
        o.layer_height = f64::NAN;
        assert!(validate(Path::new("x.stl"), &o).is_err());
        o.layer_height = 0.2;
        o.nozzle_diameter = 0.0;
        assert!(validate(Path::new("x.stl"), &o).is_err());
    }
}
