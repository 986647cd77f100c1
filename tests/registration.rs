//! Registration to the bead with the real slicers: PrusaSlicer, Slic3r and CuraEngine centre
//! the model's bounding box on their bed centre, (100, 100) with the settings `warpslice run`
//! gives them (PrusaSlicer's and Slic3r's default print centre, CuraEngine's `center_object`
//! on a 200 mm bed), so the true STL → G-code translation is (100, 100) − the warped STL's box
//! centre. The fine registration (`register::refine`, the warped mesh given) must find it
//! within [`REGISTRATION_TOLERANCE`] on corpus models and on a generated part with fins thinner
//! than a line, which the slicers print partly or not at all (the printed box is then not the
//! mesh's: the bounding-box match alone is off by millimetres or refused).
#![cfg(not(target_arch = "wasm32"))] // native only: files, processes and the real slicers

mod common;
#[path = "common/synthetic.rs"]
mod synthetic;

use std::path::Path;

use warpslice::pipeline::files::{self, RunFiles};
use warpslice::pipeline::{UnwarpSettings, WarpOptions};
use warpslice::slicer::{SliceOptions, SlicerKind};
use warpslice::warp::{Direction, WarpParams, WarpSpec};

/// The registration's required accuracy, mm (issue 17).
const REGISTRATION_TOLERANCE: f64 = 0.02;
/// The slicers' bed centre, mm.
const BED_CENTRE: [f64; 2] = [100.0, 100.0];

fn conic() -> WarpOptions {
    conic_with(30.0, Direction::Outward, [0.0, 0.0])
}

/// `model` warped with `opts`, written where a run beside `d/part.gcode` puts it; the run's
/// file names and the warp's output.
fn warped_beside(
    d: &std::path::Path,
    model: &std::path::Path,
    opts: &WarpOptions,
) -> (RunFiles, warpslice::pipeline::WarpOutput) {
    let files = RunFiles::next_to(&d.join("part.gcode"));
    let w = files::warp_file(model, opts, &files.warped, &mut ()).unwrap();
    (files, w)
}

fn dir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("warpslice-reg-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Warp, slice and unwarp `model` with `slicer` (the warped mesh given); returns the found
/// translation's error from the known placement, mm, and the fit's report.
fn registration_error(model: &Path, slicer: SlicerKind, tag: &str) -> (f64, String) {
    let d = dir(tag);
    let out = d.join("part.gcode");
    let slice = SliceOptions {
        slicer,
        ..Default::default()
    };
    let report = files::run(
        model,
        &conic(),
        &slice,
        &UnwarpSettings::default(),
        &out,
        &mut (),
    )
    .unwrap_or_else(|e| panic!("{tag}: {e}"));
    let job = files::read_job(&files::job_path(&RunFiles::next_to(&out).warped)).unwrap();
    let c = job.warped_bbox.center();
    let want = [BED_CENTRE[0] - c.x, BED_CENTRE[1] - c.y];
    let t = report.translation;
    let err = (t[0] - want[0]).hypot(t[1] - want[1]);
    (err, format!("{:?} found {t:?} want {want:?}", report.fit))
}

#[test]
fn registration_is_within_two_hundredths_with_every_slicer() {
    let corpus = common::corpus_dir();
    let mut models: Vec<(String, std::path::PathBuf)> = Vec::new();
    let fins = dir("fins").join("fins.stl");
    std::fs::write(&fins, common::finned_block()).unwrap();
    models.push(("fins".into(), fins));
    match &corpus {
        Some(c) => {
            for m in ["ps_extruder_idler_fromobj.stl", "sm_gearwheel_bin.stl"] {
                models.push((m.into(), c.join(m)));
            }
        }
        None => common::skip::skip_or_fail("the corpus models", "no ../shared/corpus/stl"),
    }
    let mut failures = Vec::new();
    let mut ran = 0;
    for kind in [
        SlicerKind::PrusaSlicer,
        SlicerKind::Slic3r,
        SlicerKind::CuraEngine,
    ] {
        if let Err(e) = warpslice::slicer::available(kind) {
            common::skip::skip_or_fail(&format!("{kind:?}"), &e.to_string());
            continue;
        }
        for (name, path) in &models {
            let tag = format!("{kind:?}-{name}");
            let (err, what) = registration_error(path, kind, &tag);
            println!("{tag}: {err:.4} mm ({what})");
            if err > REGISTRATION_TOLERANCE {
                failures.push(format!("{tag}: off by {err:.4} mm: {what}"));
            }
            ran += 1;
        }
    }
    assert!(ran > 0 || common::skip::allowed());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Without the mesh, the finned block's G-code from CuraEngine (which drops the fins) is
/// refused by the bounding-box match, naming the mismatch; with it, it registers.
#[test]
fn without_the_mesh_a_part_missing_its_fins_is_refused_by_name() {
    if let Err(e) = warpslice::slicer::available(SlicerKind::CuraEngine) {
        common::skip::skip_or_fail("CuraEngine", &e.to_string());
        return;
    }
    let d = dir("nomesh");
    let stl = d.join("fins.stl");
    std::fs::write(&stl, common::finned_block()).unwrap();
    let (files, w) = warped_beside(&d, &stl, &conic());
    let slice = SliceOptions {
        slicer: SlicerKind::CuraEngine,
        ..Default::default()
    };
    warpslice::slicer::slice(&files.warped, &files.sliced, &slice).unwrap();
    let g = std::fs::read(&files.sliced).unwrap();
    let e = warpslice::pipeline::unwarp(&g, &w.job, &UnwarpSettings::default()).unwrap_err();
    assert_eq!(
        warpslice::error::Coded::code(&e),
        "register.mismatch",
        "{e}"
    );
    let stl_bytes = std::fs::read(&files.warped).unwrap();
    let mut u = warpslice::pipeline::unwarper_with_stl(
        &w.job,
        &UnwarpSettings::default(),
        Some(&stl_bytes),
    )
    .unwrap();
    u.scan(&g).unwrap();
    let reg = u.end_scan().unwrap();
    let fit = reg.fit.expect("a fit");
    assert!(fit.moved_mm > 1.0, "the fit moved the box match: {fit:?}");
}

/// The STL of another job is refused by name.
#[test]
fn the_stl_of_another_job_is_refused() {
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "t");
    let a = warpslice::pipeline::warp_model(&stl, &conic()).unwrap();
    let mut other = conic();
    other.layer_height = 0.3;
    let b = warpslice::pipeline::warp_model(&stl, &other).unwrap();
    let e = warpslice::pipeline::warped_mesh(&a.job, &b.stl).unwrap_err();
    assert_eq!(warpslice::error::Coded::code(&e), "job.stl-mismatch", "{e}");
    assert!(warpslice::pipeline::warped_mesh(&a.job, &a.stl).is_ok());
}

/// The slicers that are installed here (a missing one fails, or is skipped and said so with
/// `WARPSLICE_ALLOW_SKIP=1`).
fn slicers() -> Vec<SlicerKind> {
    [
        SlicerKind::PrusaSlicer,
        SlicerKind::Slic3r,
        SlicerKind::CuraEngine,
    ]
    .into_iter()
    .filter(|&k| match warpslice::slicer::available(k) {
        Ok(_) => true,
        Err(e) => {
            common::skip::skip_or_fail(&format!("{k:?}"), &e.to_string());
            false
        }
    })
    .collect()
}

fn conic_with(angle: f64, direction: Direction, center: [f64; 2]) -> WarpOptions {
    WarpOptions::new(WarpParams {
        spec: WarpSpec::Conic {
            angle,
            direction,
            center,
        },
        base: None,
    })
}

/// The model `stl` warped by each of the jobs a 30° outward cone's G-code must not be taken
/// with, their boxes within the box match's bound: 31°, 29.5°, the inward cone, the centre
/// moved 0.5 mm.
fn other_warps(stl: &[u8]) -> Vec<(&'static str, warpslice::pipeline::WarpOutput)> {
    [
        ("31°", conic_with(31.0, Direction::Outward, [0.0, 0.0])),
        ("29.5°", conic_with(29.5, Direction::Outward, [0.0, 0.0])),
        ("inward", conic_with(30.0, Direction::Inward, [0.0, 0.0])),
        (
            "centre +0.5 mm",
            conic_with(30.0, Direction::Outward, [0.5, 0.0]),
        ),
    ]
    .into_iter()
    .map(|(n, o)| (n, warpslice::pipeline::warp_model(stl, &o).unwrap()))
    .collect()
}

/// The project's independent checker (tests/common/check.rs) on `written`, the unwarp of the
/// slicer's `sliced` from the warped STL `warped` (its job beside it): the header's placement
/// within 0.02 mm of the slicers' known one (the warped box centred on the bed centre), every
/// vertex and chord on its layer surface, E, travels, bed.
fn independent_check(warped: &Path, sliced: &[u8], written: &[u8]) -> Result<(), String> {
    let job = files::read_job(&files::job_path(warped)).unwrap();
    let (mesh, _) = warpslice::mesh::read_stl(&std::fs::read(warped).unwrap()).unwrap();
    let c = job.warped_bbox.center();
    let d0 = warpslice::unwarp::UnwarpOptions::default();
    let expect = common::check::Expect {
        job: &job,
        warped: &mesh,
        placement: glam::DVec2::new(BED_CENTRE[0] - c.x, BED_CENTRE[1] - c.y),
        max_segment: d0.max_segment,
        tolerance: d0.tolerance,
        clearance: d0.travel_clearance,
    };
    common::check::check(&expect, sliced, written).map(|_| ())
}

/// Issue 12 item 3: a job of another warp was accepted when the bounding boxes agreed — an
/// inward-cone job on an outward-cone G-code (points 7.86 mm outside the part), a 31° or 29.5°
/// job on a 30° G-code, the cone's centre moved by 0.5 mm. With every slicer, the 20 mm cube's
/// G-code of the 30° outward cone is unwarped by its own job (and passes the independent
/// checker) and refused with each other job by name (`unwarp.shape-mismatch`: the line, the
/// face, the fix), by the library and the CLI, although every box agrees within the 1 mm the
/// box match allows.
#[test]
fn a_job_of_another_warp_is_refused_even_when_the_boxes_agree() {
    let d = dir("otherwarp");
    let model = d.join("cube.stl");
    std::fs::write(
        &model,
        warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "cube"),
    )
    .unwrap();
    let (files, right) = warped_beside(&d, &model, &conic());
    let stl = std::fs::read(&model).unwrap();
    let others: Vec<(&str, warpslice::job::Job)> = other_warps(&stl)
        .into_iter()
        .map(|(n, w)| (n, w.job))
        .collect();
    // the boxes agree: the box match alone would take each
    for (name, job) in &others {
        let (a, b) = (job.warped_bbox.size(), right.job.warped_bbox.size());
        assert!(
            (a - b).abs().max_element() < warpslice::tolerance::MAX_REGISTRATION_RESIDUAL,
            "{name}: {a} vs {b}"
        );
    }
    let mut ran = 0;
    for kind in slicers() {
        let slice = SliceOptions {
            slicer: kind,
            ..Default::default()
        };
        warpslice::slicer::slice(&files.warped, &files.sliced, &slice).unwrap();
        let g = std::fs::read(&files.sliced).unwrap();
        let own = warpslice::pipeline::unwarp(&g, &right.job, &UnwarpSettings::default())
            .unwrap_or_else(|e| panic!("{kind:?}, its own job: {e}"));
        independent_check(&files.warped, &g, &own.gcode)
            .unwrap_or_else(|e| panic!("{kind:?}, its own job: {e}"));
        for (name, job) in &others {
            let e = warpslice::pipeline::unwarp(&g, job, &UnwarpSettings::default())
                .err()
                .unwrap_or_else(|| panic!("{kind:?}: the {name} job is accepted"));
            assert_eq!(
                warpslice::error::Coded::code(&e),
                "unwarp.shape-mismatch",
                "{kind:?}, {name}: {e}"
            );
            let m = e.to_string();
            assert!(
                m.starts_with("G-code line ") && m.contains("another warp"),
                "{kind:?}, {name}: {m}"
            );
        }
        // the CLI, with the 31° job's file (no STL beside it)
        let job31 = d.join("other.job.json");
        std::fs::write(&job31, others[0].1.to_json_pretty()).unwrap();
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
            .args(["unwarp", files.sliced.to_str().unwrap(), "--job"])
            .arg(&job31)
            .arg("-o")
            .arg(d.join("out.gcode"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.contains("does not fit this job's part"),
            "{kind:?}: {err}"
        );
        assert!(!d.join("out.gcode").exists(), "no output file on a refusal");
        ran += 1;
    }
    assert!(ran > 0 || common::skip::allowed());
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 12 item 3, robust to what the slicer drops: a thin wing ([`common::thin_wing`]) whose
/// tips and top fin the slicers print partly or not at all (CuraEngine's printed box was
/// 27.97 × 5.60 × 48.00 mm for a 30.00 × 6.01 × 52.78 mm mesh, refused; PrusaSlicer's box centre
/// 0.18 mm off, taken). With every slicer and a cone and a belt warp, `warpslice unwarp --job`
/// registers against the warped STL beside the job and the written file passes the independent
/// checker (placement within 0.02 mm of the slicers' known one among its checks); the library
/// without the mesh either places it within 0.02 mm (along the belt's slope only: along x the
/// belt's layers do not change, a shift there moves the whole part) or refuses by name.
#[test]
fn a_thin_winged_part_is_placed_by_what_was_printed_with_every_slicer() {
    let belt = WarpOptions::new(WarpParams {
        spec: WarpSpec::Belt {
            angle: 45.0,
            toward: [0.0, 1.0],
        },
        base: None,
    });
    let mut ran = 0;
    let mut refused_without = 0;
    for kind in slicers() {
        for (wname, warp) in [
            ("conic", conic_with(30.0, Direction::Outward, [0.0, 0.0])),
            ("belt", belt.clone()),
        ] {
            let tag = format!("wing-{kind:?}-{wname}");
            let d = dir(&tag);
            let model = d.join("wing.stl");
            std::fs::write(&model, common::thin_wing()).unwrap();
            let (files, w) = warped_beside(&d, &model, &warp);
            let slice = SliceOptions {
                slicer: kind,
                ..Default::default()
            };
            warpslice::slicer::slice(&files.warped, &files.sliced, &slice).unwrap();
            let g = std::fs::read(&files.sliced).unwrap();
            let out = d.join("out.gcode");
            let o = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
                .args(["unwarp", files.sliced.to_str().unwrap(), "--job"])
                .arg(files::job_path(&files.warped))
                .arg("-o")
                .arg(&out)
                .output()
                .unwrap();
            let stdout = String::from_utf8_lossy(&o.stdout);
            assert!(
                o.status.success(),
                "{tag}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            assert!(
                stdout.contains("registering against the warped STL beside the job"),
                "{tag}: {stdout}"
            );
            independent_check(&files.warped, &g, &std::fs::read(&out).unwrap())
                .unwrap_or_else(|e| panic!("{tag}: {e}"));
            // without the mesh: right or refused
            let c = w.job.warped_bbox.center();
            let want = [BED_CENTRE[0] - c.x, BED_CENTRE[1] - c.y];
            match warpslice::pipeline::unwarp(&g, &w.job, &UnwarpSettings::default()) {
                Ok(u) => {
                    // off only along what the warp does not vary in: the belt's layers are
                    // the same along x (T_z depends on y), so a shift in x moves the whole
                    // part on the bed and changes nothing of it (Slic3r: 0.109 mm)
                    let t = u.report.translation;
                    let (ex, ey) = (t[0] - want[0], t[1] - want[1]);
                    let err = if wname == "belt" {
                        ey.abs()
                    } else {
                        ex.hypot(ey)
                    };
                    println!("{tag}: without the mesh placed ({ex:.3}, {ey:.3}) mm off");
                    assert!(
                        err <= REGISTRATION_TOLERANCE,
                        "{tag}: without the mesh placed ({ex:.3}, {ey:.3}) mm off"
                    );
                }
                Err(e) => {
                    let code = warpslice::error::Coded::code(&e);
                    assert!(
                        [
                            "register.features-dropped",
                            "register.mismatch",
                            "unwarp.shape-mismatch"
                        ]
                        .contains(&code),
                        "{tag}: {e}"
                    );
                    println!("{tag}: without the mesh: {code}");
                    refused_without += 1;
                }
            }
            ran += 1;
            let _ = std::fs::remove_dir_all(&d);
        }
    }
    assert!(ran > 0 || common::skip::allowed());
    // the tips were dropped: the box match cannot place every case
    assert!(ran == 0 || refused_without > 0);
}

// ── issue 12, misleading errors: what the slicer prints beside the part ──────────────────────

/// The synthetic slicer's file with Bambu Studio's / OrcaSlicer's labels (`; FEATURE: Outer
/// wall`, `Sparse infill`, `Skirt`) instead of PrusaSlicer's `;TYPE:`, a `; FEATURE: Brim` ring
/// touching the part on the first layer and a 10 mm `; FEATURE: Prime tower` 25 mm beside the
/// part on every layer. `labels`: false strips every label (an untyped file).
fn orca_like(g: &str, tower: bool, brim: bool, labels: bool) -> String {
    let mut out = String::new();
    let mut layer = 0;
    let mut brim_done = false;
    let label = |l: &str| {
        if labels {
            format!("; FEATURE: {l}\n")
        } else {
            String::new()
        }
    };
    for l in g.lines() {
        if let Some(t) = l.strip_prefix(";TYPE:") {
            let orca = match t {
                "External perimeter" => "Outer wall",
                "Internal infill" => "Sparse infill",
                "Skirt/Brim" => "Skirt",
                other => other,
            };
            out += &label(orca);
            if brim && layer == 1 && !brim_done && orca == "Outer wall" {
                // five loops from 0.45 to 2.25 mm outside the cube's 20 mm wall (x, y ∈ 100 ± 10
                // on a first layer that holds the whole cube)
                out += &label("Brim");
                for k in 1..=5 {
                    let r = 10.0 + 0.45 * f64::from(k);
                    let (a, b) = (100.0 - r, 100.0 + r);
                    out += &format!("G0 X{a:.3} Y{a:.3}\n");
                    for (x, y) in [(b, a), (b, b), (a, b), (a, a)] {
                        out += &format!("G1 X{x:.3} Y{y:.3} E0.5 F1800\n");
                    }
                }
                out += &label("Outer wall");
                brim_done = true;
            }
            continue;
        }
        if l == ";LAYER_CHANGE" {
            if tower && layer > 0 {
                let z = f64::from(layer) * 0.2;
                let (x0, x1, y0, y1) = (135.0, 145.0, 95.0, 105.0);
                out += &label("Prime tower");
                out += &format!("G1 E-0.8 F2400\nG0 X{x0} Y{y0} Z{z:.3} F6000\nG1 E0.8 F2400\n");
                for (x, y) in [(x1, y0), (x1, y1), (x0, y1), (x0, y0)] {
                    out += &format!("G1 X{x} Y{y} E0.4 F1800\n");
                }
            }
            layer += 1;
        }
        out += l;
        out.push('\n');
    }
    out
}

/// `warpslice unwarp G --job J -o OUT` (without `--offset`): Ok(stdout) or Err(stderr).
fn cli_unwarp(d: &Path, job: &warpslice::job::Job, g: &str) -> Result<String, String> {
    let (input, j, out) = (
        d.join("in.gcode"),
        d.join("part.job.json"),
        d.join("out.gcode"),
    );
    std::fs::write(&input, g).unwrap();
    std::fs::write(&j, job.to_json_pretty()).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
        .args(["unwarp", input.to_str().unwrap(), "--job"])
        .arg(&j)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    if o.status.success() {
        Ok(String::from_utf8_lossy(&o.stdout).into_owned())
    } else {
        Err(String::from_utf8_lossy(&o.stderr).into_owned())
    }
}

/// Issue 12, misleading errors: a file with Bambu/Orca `; FEATURE:` labels, a prime tower and a
/// brim got advice to use `--offset` (following it bent the tower and brim as if they were the
/// part). The labels are read as `;TYPE:` is: the tower and brim stay out of the placement and
/// are written flat, by the library and the CLI. Without labels, the same file is refused as
/// `register.more-than-the-model`, naming the missing labels, the tower or brim and the fix
/// (and saying `--offset` does not help); a brim alone is named as a brim.
#[test]
fn orca_feature_labels_keep_a_prime_tower_and_brim_out_of_the_part() {
    let w = synthetic::conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let d = dir("orca");
    let c = w.job.warped_bbox.center();
    let want = [BED_CENTRE[0] - c.x, BED_CENTRE[1] - c.y];
    let labelled = orca_like(&g, true, true, true);
    assert!(labelled.contains("; FEATURE: Prime tower") && !labelled.contains(";TYPE:"));
    let u = warpslice::pipeline::unwarp(labelled.as_bytes(), &w.job, &UnwarpSettings::default())
        .unwrap_or_else(|e| panic!("labelled: {e}"));
    let t = u.report.translation;
    let err = (t[0] - want[0]).hypot(t[1] - want[1]);
    assert!(err < 0.05, "placed {t:?}, want {want:?}");
    // the tower's corner is written as it was printed: flat, where the slicer put it
    let text = String::from_utf8_lossy(&u.gcode);
    assert!(
        text.contains("G1 X145 Y105") || text.contains("X145.000 Y105.000"),
        "the tower is not written flat"
    );
    let out = cli_unwarp(&d, &w.job, &labelled).unwrap_or_else(|e| panic!("CLI: {e}"));
    assert!(out.contains("registration: translation"), "{out}");

    // the cube's conic job has an anchor (the cone's tip touches the bed), whose whole first
    // layer is dropped with a brim in it: the brim case takes a nearly flat belt, no anchor
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "c");
    let mut flat = WarpOptions::new(WarpParams {
        spec: WarpSpec::Belt {
            angle: 0.5,
            toward: [0.0, 1.0],
        },
        base: None,
    });
    flat.anchor = warpslice::pipeline::AnchorMode::Off;
    let flat = warpslice::pipeline::warp_model(&stl, &flat).unwrap();
    let g_flat = synthetic::gcode(&flat.job, true, 2.0);
    for (what, job, g, tower, brim, words) in [
        (
            "tower",
            &w.job,
            &g,
            true,
            false,
            &["no feature labels", "prime tower", "--offset does not help"][..],
        ),
        (
            "brim",
            &flat.job,
            &g_flat,
            false,
            true,
            &["first layer only: a brim", "no feature labels"][..],
        ),
    ] {
        let bare = orca_like(g, tower, brim, false)
            .lines()
            .filter(|l| !l.starts_with(";TYPE:"))
            .collect::<Vec<_>>()
            .join("\n");
        let e = warpslice::pipeline::unwarp(bare.as_bytes(), job, &UnwarpSettings::default())
            .err()
            .unwrap_or_else(|| panic!("{what}: an unlabelled file accepted"));
        assert_eq!(
            warpslice::error::Coded::code(&e),
            "register.more-than-the-model",
            "{what}: {e}"
        );
        let cli = cli_unwarp(&d, job, &bare).unwrap_err();
        for n in words {
            assert!(e.to_string().contains(n), "{what}: {e}");
            assert!(cli.contains(n), "{what}: {cli}");
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 12, misleading errors: `--duplicate 2` (PrusaSlicer: two copies of the object) was
/// refused as a registration residual or, with the warped STL, misplaced onto one copy. It is
/// named as two objects with the fix (one object per file): a synthetic file with a second copy
/// 26 mm beside the first (library and CLI), and PrusaSlicer's own `--duplicate 2`.
#[test]
fn two_copies_of_the_object_are_named_as_two_objects() {
    let w = synthetic::conic_cube();
    let g = synthetic::gcode(&w.job, true, 2.0);
    let d = dir("duplicate");
    // every layer printed twice, the second time 26 mm to the right
    let mut two = String::new();
    let mut layer = String::new();
    let flush = |two: &mut String, layer: &mut String| {
        two.push_str(layer);
        two.push_str(&synthetic::shifted(layer, 26.0, 0.0));
        layer.clear();
    };
    for l in g.lines() {
        if l == ";LAYER_CHANGE" {
            flush(&mut two, &mut layer);
            two.push_str(";LAYER_CHANGE\n");
            continue;
        }
        layer.push_str(l);
        layer.push('\n');
    }
    flush(&mut two, &mut layer);
    let Err(e) = warpslice::pipeline::unwarp(two.as_bytes(), &w.job, &UnwarpSettings::default())
    else {
        panic!("two copies accepted")
    };
    assert_eq!(
        warpslice::error::Coded::code(&e),
        "register.more-than-the-model",
        "{e}"
    );
    let words = ["2 objects", "one object per file"];
    let cli = cli_unwarp(&d, &w.job, &two).unwrap_err();
    for n in words {
        assert!(e.to_string().contains(n), "{e}");
        assert!(cli.contains(n), "{cli}");
    }
    // one copy is accepted
    assert!(warpslice::pipeline::unwarp(g.as_bytes(), &w.job, &UnwarpSettings::default()).is_ok());

    if let Err(e) = warpslice::slicer::available(SlicerKind::PrusaSlicer) {
        common::skip::skip_or_fail("PrusaSlicer", &e.to_string());
        return;
    }
    let model = d.join("cube.stl");
    std::fs::write(
        &model,
        warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "cube"),
    )
    .unwrap();
    let (files, _) = warped_beside(&d, &model, &conic());
    let slice = SliceOptions {
        slicer: SlicerKind::PrusaSlicer,
        extra_args: vec!["--duplicate".into(), "2".into()],
        ..Default::default()
    };
    warpslice::slicer::slice(&files.warped, &files.sliced, &slice).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_warpslice"))
        .args(["unwarp", files.sliced.to_str().unwrap(), "--job"])
        .arg(files::job_path(&files.warped))
        .arg("-o")
        .arg(d.join("dup.gcode"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "PrusaSlicer --duplicate 2 accepted");
    for n in words {
        assert!(err.contains(n), "PrusaSlicer --duplicate 2: {err}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// The worst point's distance less its allowance in a `unwarp.shape-mismatch` message, mm
/// ("… lies D mm outside …(A mm allowed" or "… maps D mm …; A mm allowed").
fn refused_margin(m: &str) -> Option<f64> {
    let num = |s: &str| s.split(' ').next().and_then(|v| v.parse::<f64>().ok());
    let d = m
        .split_once(" lies ")
        .or_else(|| m.split_once(" maps "))
        .and_then(|(_, r)| num(r))?;
    let a = m.split_once(" mm allowed")?.0.rsplit([' ', '(']).next()?;
    Some(d - a.parse::<f64>().ok()?)
}

/// Issue 12 item 3, by cross-section: with the warped STL beside each job (as the CLI reads
/// it), the 30° outward cone's G-code of the corpus gear wheel (not a box: the box check's
/// weak case) is accepted with its own job and refused with each other job (31°, 29.5°,
/// inward, centre moved 0.5 mm), by every slicer; the own job's points lie inside the mesh's
/// cross-sections. Prints the accepted case's margin (distance outside less allowance, mm) by
/// box and by cross-section and the refused cases' smallest, for the record.
#[test]
fn with_the_mesh_another_warp_is_refused_and_the_section_margins_are_measured() {
    let Some(corpus) = common::corpus_dir() else {
        common::skip::skip_or_fail("the corpus models", "no ../shared/corpus/stl");
        return;
    };
    let d = dir("section");
    let stl = std::fs::read(corpus.join("sm_gearwheel_bin.stl")).unwrap();
    let model = d.join("gear.stl");
    std::fs::write(&model, &stl).unwrap();
    let (files, right) = warped_beside(&d, &model, &conic());
    let right_stl = std::fs::read(&files.warped).unwrap();
    let others = other_warps(&stl);
    let s = UnwarpSettings::default();
    let run = |g: &[u8], job: &warpslice::job::Job, stl: Option<&[u8]>| {
        let mut u = warpslice::pipeline::unwarper_with_stl(job, &s, stl)?;
        u.scan(g)?;
        u.end_scan()?;
        u.push(g)?;
        u.finish().map_err(warpslice::pipeline::Error::from)
    };
    let mut ran = 0;
    for kind in slicers() {
        let slice = SliceOptions {
            slicer: kind,
            ..Default::default()
        };
        warpslice::slicer::slice(&files.warped, &files.sliced, &slice).unwrap();
        let g = std::fs::read(&files.sliced).unwrap();
        let own = run(&g, &right.job, Some(&right_stl))
            .unwrap_or_else(|e| panic!("{kind:?}, its own job with its STL: {e}"));
        let own_box = run(&g, &right.job, None).unwrap();
        let section = own
            .shape_section_margin_mm
            .expect("checked by cross-section");
        assert!(
            section <= 0.0,
            "{kind:?}: own job, section margin {section}"
        );
        let (mut box_refused, mut section_refused) = (f64::INFINITY, f64::INFINITY);
        for (name, w) in &others {
            let e = run(&g, &w.job, Some(&w.stl))
                .err()
                .unwrap_or_else(|| panic!("{kind:?}: the {name} job with its STL is accepted"));
            let code = warpslice::error::Coded::code(&e);
            assert!(
                code == "unwarp.shape-mismatch" || code.starts_with("register."),
                "{kind:?}, {name}: {e}"
            );
            if let Some(m) = refused_margin(&e.to_string()) {
                section_refused = section_refused.min(m);
            }
            match run(&g, &w.job, None) {
                Err(e) => {
                    if let Some(m) = refused_margin(&e.to_string()) {
                        box_refused = box_refused.min(m);
                    }
                }
                Ok(r) => box_refused = box_refused.min(r.shape_margin_mm),
            }
        }
        println!(
            "{kind:?} gear wheel: box check accepted {:+.3} / refused from {:+.3} mm; with cross-sections accepted {:+.3} (section {:+.3}) / refused from {:+.3} mm",
            own_box.shape_margin_mm, box_refused, own.shape_margin_mm, section, section_refused
        );
        ran += 1;
    }
    assert!(ran > 0 || common::skip::allowed());
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 12 item 3, by cross-section, on its own: a printed point in the warped cylinder's box
/// but outside its round cross-section (near the box's corner) passes the box check and is
/// found by the cross-section check (face "outside the warped mesh's cross-section", its
/// layer; measured and reported, not yet refusing: see `src/unwarp/shape.rs`); the point on
/// the axis passes both.
#[test]
fn a_point_in_the_box_but_outside_the_cross_section_is_found_only_with_the_mesh() {
    use warpslice::unwarp::shape::{ShapeCheck, SECTION_FACE};
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("cylinder").unwrap(), "c");
    let w = warpslice::pipeline::warp_model(&stl, &conic()).unwrap();
    let (mesh, _) = warpslice::mesh::read_stl(&w.stl).unwrap();
    let warp = w.job.warp.clone().build(&w.job.model_bbox).unwrap();
    let b = w.job.warped_bbox;
    let c = b.center();
    // layer 80 of 0.2 mm: its top z = 16.0, mid-height 15.9: the whole disc (the warped
    // bottom reaches 10 · tan 30° ≈ 5.8 mm, the top starts at 20 mm); the corner point maps to
    // model z ≈ 15.9 − 13.7 · tan 30° ≈ 8 mm, inside the box
    let z = 16.0;
    let corner = glam::DVec3::new(b.max.x - 0.3, b.max.y - 0.3, z);
    let axis = glam::DVec3::new(c.x, c.y, z);
    let at = |shape: &mut ShapeCheck, g: glam::DVec3, line: u64| {
        // the layer below first, so the layer height is the slicer's 0.2 mm
        shape.point(
            warp.as_ref(),
            &w.job,
            (0.0, 0.0),
            79,
            line,
            axis - glam::DVec3::Z * 0.2,
            warpslice::toolpath::Feature::InnerWall,
        );
        shape.point(
            warp.as_ref(),
            &w.job,
            (0.0, 0.0),
            80,
            line + 1,
            g,
            warpslice::toolpath::Feature::OuterWall,
        )
    };
    let mut with = ShapeCheck::new(Some(&mesh));
    assert_eq!(at(&mut with, axis, 1), None);
    assert_eq!((with.section_beyond, with.section_worst), (0, None));
    assert!(with.section_margin.is_some_and(|m| m < 0.0));
    assert_eq!(at(&mut with, corner, 10), None, "the box check passes it");
    let f = with
        .section_worst
        .expect("the corner point is found by cross-section");
    assert_eq!(
        (f.face, f.layer, f.line, with.section_beyond),
        (SECTION_FACE, 80, 11, 1),
        "{f:?}"
    );
    assert!(
        f.overshoot > 0.5 && with.section_margin.is_some_and(|m| m > 0.4),
        "{f:?}"
    );
    let mut without = ShapeCheck::new(None);
    assert_eq!(at(&mut without, corner, 10), None);
    assert_eq!((without.section_beyond, without.section_margin), (0, None));
}
