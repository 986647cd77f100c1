//! Unwarp regressions, each named after what it caught (synthetic slicer G-code, no slicer
//! needed; they run under wasm too).

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

#[path = "common/synthetic.rs"]
mod synthetic;

use warpslice::gcode::{ReadOptions, Reader};
use warpslice::machine::MachineOptions;
use warpslice::pipeline::{unwarp, UnwarpSettings};
use warpslice::pipeline::{warp_model, WarpOptions};
use warpslice::unwarp::UnwarpOptions;
use warpslice::warp::{WarpParams, WarpSpec};

use synthetic::conic_cube;

/// Sum of E over the extruding moves of a G-code, read back with the crate's reader.
fn extruded(gcode: &[u8]) -> f64 {
    let mut e = 0.0;
    let mut r = Reader::new(ReadOptions::default());
    let mut sink = |l: warpslice::gcode::Line<'_>,
                    _: &warpslice::gcode::State|
     -> Result<(), warpslice::gcode::GcodeError> {
        e += l
            .moves
            .iter()
            .filter(|m| m.is_extrusion())
            .map(|m| m.e)
            .sum::<f64>();
        Ok(())
    };
    r.push(gcode, &mut sink).unwrap();
    r.finish(&mut sink).unwrap();
    e
}

/// Found on PrusaSlicer's absolute-E files: the slicer retracts (`G1 E-2`) before the first
/// object extrusion; the output's E words must continue from the firmware's E there, or the
/// first extrusion pushes the retraction back in one blob.
#[test]
fn absolute_e_continues_from_the_slicers_e_at_the_region_start() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, false, 2.0).replacen(
        ";TYPE:Skirt/Brim",
        "G1 E-2 F2400\n;TYPE:Skirt/Brim",
        1,
    );
    let u = unwarp(g.as_bytes(), &w.job, &UnwarpSettings::default()).unwrap();
    let read_back = extruded(&u.gcode);
    assert!(
        (read_back - u.report.e_out).abs() < 1e-3,
        "written E {read_back} vs report {}",
        u.report.e_out
    );
}

/// Relative files must not get a `G92 E` at the end of the region (it means nothing there and
/// surprised a reader of the output).
#[test]
fn relative_e_gets_no_resync_line() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let u = unwarp(g.as_bytes(), &w.job, &UnwarpSettings::default()).unwrap();
    assert!(!String::from_utf8_lossy(&u.gcode).contains("back to the slicer's E"));
    assert!((extruded(&u.gcode) - u.report.e_out).abs() < 1e-3);
}

/// The G-code of the unwarped model (or another model) is refused by registration.
#[test]
fn gcode_of_the_unwarped_model_is_refused() {
    let w = conic_cube();
    let mut job = w.job.clone();
    // pretend the slicer was given the original 20 mm cube: its bbox is 8 mm lower
    job.warped_bbox.max.z -= 8.0;
    let g = synthetic::gcode(&job, true, 2.0);
    let e = unwarp(g.as_bytes(), &w.job, &UnwarpSettings::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("does not match the warped model"), "{e}");
}

/// Binary G-code is refused with the advice to export text.
#[test]
fn binary_gcode_is_refused() {
    let w = conic_cube();
    let e = unwarp(b"GCDE\x01\x00\x00\x00", &w.job, &UnwarpSettings::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("binary G-code"), "{e}");
}

/// `place` (for machines turning about fixed lines, e.g. an A/B table's origin) moves the part
/// and its flat skirt by the same shift, keeps E and the tool axes, and leaves the start G-code
/// where the slicer wrote it. Caught by the machine matrix: the part must sit on the table's
/// axes, not where the slicer centred it.
#[test]
fn place_moves_part_and_skirt_but_not_the_start_gcode() {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0).replacen(
        "G28\n",
        "G28\nG1 X5 Y5 Z0.3 F3000 ; purge start\n",
        1,
    );
    let opts = UnwarpOptions {
        collect_toolpath: true,
        ..UnwarpOptions::default()
    };
    let at = unwarp(g.as_bytes(), &w.job, &opts.clone().into()).unwrap();
    let placed = unwarp(
        g.as_bytes(),
        &w.job,
        &UnwarpOptions {
            place: Some([-30.0, 12.5]),
            ..opts.clone()
        }
        .into(),
    )
    .unwrap();
    let m2o = placed.report.model_to_output;
    assert_eq!([m2o[0], m2o[1]], [-30.0, 12.5]);
    let shift = glam::DVec3::new(
        -30.0 - at.report.model_to_output[0],
        12.5 - at.report.model_to_output[1],
        0.0,
    );
    assert!(
        shift.length() > 50.0,
        "the synthetic slicer centres at (100, 100)"
    );
    // the extrusions, one for one (the placed part starts with one more travel: from where
    // the start G-code left the head)
    let ext = |t: &[warpslice::toolpath::ToolPoint]| {
        t.iter().filter(|t| !t.travel).cloned().collect::<Vec<_>>()
    };
    let (a_ext, p_ext) = (ext(&at.toolpath), ext(&placed.toolpath));
    assert_eq!(a_ext.len(), p_ext.len());
    // and the travels: one more, and two more points per lift and per retraction added (on the
    // shifted travel grid a travel that passes a printed cell's edge within rounding may lift
    // in one run and not the other: 250 and 249 lifts here)
    let d = |a: u64, b: u64| b as i64 - a as i64;
    assert_eq!(
        placed.toolpath.len() as i64 - at.toolpath.len() as i64,
        1 + 2 * d(at.report.lifts, placed.report.lifts)
            + 2 * d(at.report.retracts_added, placed.report.retracts_added)
    );
    for (a, b) in a_ext.iter().zip(&p_ext) {
        assert!(
            (b.p - (a.p + shift)).length() < 1e-9,
            "{:?} vs {:?}",
            a.p,
            b.p
        );
        assert_eq!((a.n, a.e, a.feature), (b.n, b.e, b.feature));
    }
    assert!(placed
        .toolpath
        .iter()
        .any(|t| t.feature == warpslice::toolpath::Feature::Skirt));
    let text = String::from_utf8(placed.gcode).unwrap();
    assert!(text.contains("G1 X5 Y5 Z0.3 F3000 ; purge start"));
    assert!(
        text.contains("; warpslice model_to_output = -30 12.5 0"),
        "{}",
        &text[..600]
    );
    let bad = unwarp(
        g.as_bytes(),
        &w.job,
        &UnwarpOptions {
            place: Some([f64::NAN, 0.0]),
            ..opts
        }
        .into(),
    )
    .unwrap_err()
    .to_string();
    assert!(bad.contains("is not a position"), "{bad}");
}

/// A cylindrical job on the mandrel machine must have its layer axis on the mandrel's, or the
/// layers are wound round the wrong line (found by hand: the lathe preset turns about z = 0
/// while the warp's default axis lies one radius under the part).
#[test]
fn cylindrical_job_off_the_mandrel_axis_is_refused() {
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "t");
    let p = WarpParams {
        spec: WarpSpec::Cylindrical {
            radius: 20.0,
            axis: [0.0, -20.0],
        },
        base: None,
    };
    let w = warp_model(&stl, &WarpOptions::new(p)).unwrap();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let mut lathe = warpslice::machine::preset("lathe-a").unwrap();
    let opts = UnwarpSettings {
        unwarp: UnwarpOptions {
            place: Some([0.0, 0.0]),
            ..UnwarpOptions::default()
        },
        output: MachineOptions {
            machine: Some(lathe.clone()),
            ..MachineOptions::default()
        },
    };
    let e = unwarp(g.as_bytes(), &w.job, &opts).unwrap_err().to_string();
    assert!(
        e.contains("y = 0, z = -20") && e.contains("\"axis_z_mm\": -20") && e.contains("lathe-a"),
        "{e}"
    );
    if let warpslice::machine::spec::Kinematics::LatheA(l) = &mut lathe.kinematics {
        l.axis_z_mm = -20.0;
    }
    // the slicer's placement (100, 100) is off the mandrel too
    let e = unwarp(
        g.as_bytes(),
        &w.job,
        &UnwarpSettings::with_machine(UnwarpOptions::default(), lathe.clone()),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("turns about y = 0, z = -20"), "{e}");
    let ok = unwarp(
        g.as_bytes(),
        &w.job,
        &UnwarpSettings::with_machine(
            UnwarpOptions {
                place: Some([0.0, 0.0]),
                ..UnwarpOptions::default()
            },
            lathe,
        ),
    );
    assert!(ok.is_ok(), "{:?}", ok.err().map(|e| e.to_string()));
}

/// Found by the flavour tests: a refused unwarp (here Klipper asked for G93 inverse time) left an empty
/// G-code under the output's name. The file is written beside it and renamed when complete, so
/// a refusal leaves nothing behind, and an older output of the same name is kept.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn a_refused_unwarp_leaves_no_output_file() {
    use warpslice::pipeline::files::{unwarp_file, Observer};
    struct Quiet;
    impl Observer for Quiet {}
    let w = conic_cube();
    let dir = std::env::temp_dir().join(format!("warpslice-refused-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let g = dir.join("in.gcode");
    std::fs::write(&g, synthetic::gcode(&w.job, true, 2.0)).unwrap();
    let klipper = UnwarpSettings {
        unwarp: UnwarpOptions::default(),
        output: MachineOptions {
            machine: Some(warpslice::machine::preset("pax-5axis").unwrap()),
            flavour: Some(warpslice::machine::Flavour::Klipper),
            feed: warpslice::emit::FeedMode::InverseTime,
            ..MachineOptions::default()
        },
    };
    let fresh = dir.join("fresh.gcode");
    let e = unwarp_file(&g, &w.job, &klipper, None, &fresh, &mut Quiet).unwrap_err();
    assert!(e.to_string().contains("Klipper"), "{e}");
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["in.gcode"], "left behind: {names:?}");
    // an older file of that name survives a refused run; a good run replaces it
    std::fs::write(&fresh, "old").unwrap();
    assert!(unwarp_file(&g, &w.job, &klipper, None, &fresh, &mut Quiet).is_err());
    assert_eq!(std::fs::read_to_string(&fresh).unwrap(), "old");
    let ok = UnwarpSettings {
        unwarp: UnwarpOptions {
            offset: Some([100.0, 100.0]),
            ..UnwarpOptions::default()
        },
        output: MachineOptions::default(),
    };
    unwarp_file(&g, &w.job, &ok, None, &fresh, &mut Quiet).unwrap();
    assert!(std::fs::read_to_string(&fresh)
        .unwrap()
        .starts_with("; generated by warpslice"));
    assert!(!dir.join("fresh.gcode.partial").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The 3-axis unwarp of the synthetic slicer's G-code of [`conic_cube`] with `o`, placed where
/// the synthetic slicer put it (`--offset 100,100`) unless `o` gives another offset.
fn synthetic_conic_cube(
    o: UnwarpOptions,
) -> Result<warpslice::unwarp::UnwarpOutput, warpslice::pipeline::Error> {
    let w = conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let s = UnwarpSettings {
        unwarp: UnwarpOptions {
            offset: o.offset.or(Some([100.0, 100.0])),
            ..o
        },
        output: MachineOptions::default(),
    };
    unwarp(g.as_bytes(), &w.job, &s)
}

/// Issue 12 item 2: "never below the bed" was not enforced: `--z-offset` was added after the
/// clamp (−50 mm wrote every move below Z 0 and reported nothing clamped). The clamp now comes
/// after every offset, and a negative z-offset deeper than half a layer is refused by name.
#[test]
fn nothing_is_written_below_the_bed_whatever_the_z_offset() {
    use warpslice::error::Coded;
    let run = |z_offset: f64| {
        synthetic_conic_cube(UnwarpOptions {
            z_offset,
            ..UnwarpOptions::default()
        })
    };
    for z_offset in [-50.0, -0.11] {
        let e = run(z_offset).unwrap_err();
        assert_eq!(e.code(), "unwarp.option", "{z_offset}: {e}");
        assert!(e.to_string().contains("z-offset"), "{e}");
    }
    // a shallow negative z-offset (less than half a layer) is taken, clamped at the bed
    let lowest = |gcode: &[u8]| {
        String::from_utf8_lossy(gcode)
            .lines()
            .filter(|l| l.starts_with("G1") || l.starts_with("G0"))
            .flat_map(|l| l.split_whitespace().map(str::to_owned).collect::<Vec<_>>())
            .filter_map(|w| w.strip_prefix('Z').map(|v| v.parse::<f64>().unwrap()))
            .fold(f64::INFINITY, f64::min)
    };
    let base = run(0.0).unwrap();
    let low = run(-0.09).unwrap();
    let (lb, ll) = (lowest(&base.gcode), lowest(&low.gcode));
    assert!(ll >= 0.0, "a move at Z {ll}");
    // the offset lowered the lowest move by 0.09 mm, or onto the bed
    assert!(
        (ll - (lb - 0.09).max(0.0)).abs() < 1e-3,
        "lowest Z {lb} → {ll}"
    );
}

/// Issue 12, hangs: `--place 1e9,0` spun for minutes in the travel planner, and
/// `--max-segment 0.001` or `--tolerance 1e-12` aborted on memory. Such options are refused by
/// name before any work; the smallest accepted values still run.
#[test]
fn absurd_options_are_refused_before_any_work() {
    use warpslice::error::Coded;
    let run = synthetic_conic_cube;
    let d = UnwarpOptions::default;
    for (o, name) in [
        (
            UnwarpOptions {
                place: Some([1e9, 0.0]),
                ..d()
            },
            "place",
        ),
        (
            UnwarpOptions {
                offset: Some([100.0, -1e12]),
                ..d()
            },
            "offset",
        ),
        (
            UnwarpOptions {
                max_segment: 0.001,
                ..d()
            },
            "max-segment",
        ),
        (
            UnwarpOptions {
                tolerance: 1e-12,
                ..d()
            },
            "tolerance",
        ),
    ] {
        let e = run(o).unwrap_err();
        assert_eq!(e.code(), "unwarp.option", "{name}: {e}");
        assert!(e.to_string().contains(name), "{e}");
    }
    let fine = run(UnwarpOptions {
        tolerance: 0.001,
        max_segment: 0.01,
        place: Some([9000.0, -9000.0]),
        ..d()
    })
    .unwrap();
    assert!(fine.report.segments_out > 0);
}
