//! The typed field warp through the CLI (issue 15 item 3b): `warpslice warp`, `unwarp`,
//! `run` and `overhangs` take `--warp field --expr EXPR`, the job stores the expression, and
//! a field typed as the tilted warp's roof gives the tilted warp's warped STL, G-code and
//! overhang area (the tilted warp's own code is the oracle).
#![cfg(not(target_arch = "wasm32"))]

#[path = "common/cli_part.rs"]
#[allow(dead_code)]
mod cli_part;
#[path = "common/synthetic.rs"]
#[allow(dead_code)]
mod synthetic;

use std::path::PathBuf;

use cli_part::{ok, run};
use warpslice::job::Job;
use warpslice::warp::WarpSpec;

/// The roof s·c·|x + a| with s = 0.3, inward, a = 2, as the tilted warp and as a field.
const TILTED: &[&str] = &[
    "--warp",
    "tilted",
    "--strength",
    "0.3",
    "--direction",
    "inward",
    "--offset",
    "2",
];
const ROOF: &str = "-0.3*abs(x + 2)";

/// Warped vertices of the two STLs may differ by this, mm: both evaluate 0.3·|x + 2| in f64.
const VERTEX_TOL: f64 = 1e-9;

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("warpslice-field-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn vertices(stl: &std::path::Path) -> Vec<[f32; 3]> {
    let mut f = std::fs::File::open(stl).unwrap();
    let m = stl_io::read_stl(&mut f).unwrap();
    m.vertices.iter().map(|v| [v[0], v[1], v[2]]).collect()
}

/// The moves of an unwarped G-code (its comments name the job and differ).
fn moves(g: &str) -> Vec<&str> {
    g.lines()
        .map(|l| l.split(';').next().unwrap().trim())
        .filter(|l| l.starts_with("G0") || l.starts_with("G1"))
        .collect()
}

#[test]
fn a_field_typed_as_the_tilted_roof_warps_and_unwarps_as_the_tilted_warp() {
    let d = dir("roof");
    let p = |f: &str| d.join(f).to_str().unwrap().to_string();
    ok(&["example", "overhang", "-o", &p("part.stl")]);
    let mut outs = Vec::new();
    for (name, flags) in [
        ("T", TILTED.to_vec()),
        ("F", vec!["--warp", "field", "--expr", ROOF]),
    ] {
        let mut args = vec!["warp".to_string(), p("part.stl")];
        args.extend(flags.iter().map(|s| s.to_string()));
        args.extend(["-o".to_string(), p(&format!("{name}.stl"))]);
        ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
        let job = Job::from_json(&std::fs::read_to_string(p(&format!("{name}.job.json"))).unwrap())
            .unwrap();
        std::fs::write(
            p(&format!("{name}.gcode")),
            synthetic::gcode(&job, true, 1.0),
        )
        .unwrap();
        ok(&[
            "unwarp",
            &p(&format!("{name}.gcode")),
            "--job",
            &p(&format!("{name}.job.json")),
            "-o",
            &p(&format!("{name}.out.gcode")),
        ]);
        outs.push((job, vertices(&d.join(format!("{name}.stl")))));
    }
    // the job stores the expression as typed
    match &outs[1].0.warp.spec {
        WarpSpec::Field { expr, .. } => assert_eq!(expr, ROOF),
        other => panic!("the field job holds {other:?}"),
    }
    let (t, f) = (&outs[0].1, &outs[1].1);
    assert_eq!(t.len(), f.len(), "the two warps subdivide alike");
    for (a, b) in t.iter().zip(f) {
        for k in 0..3 {
            assert!(
                (a[k] as f64 - b[k] as f64).abs() <= VERTEX_TOL,
                "vertex {a:?} vs {b:?}"
            );
        }
    }
    let gt = std::fs::read_to_string(p("T.out.gcode")).unwrap();
    let gf = std::fs::read_to_string(p("F.out.gcode")).unwrap();
    let (mt, mf) = (moves(&gt), moves(&gf));
    assert!(mt.len() > 100, "{} moves", mt.len());
    assert_eq!(mt, mf, "the unwarped moves differ");
}

#[test]
fn overhangs_and_run_take_a_field_and_refuse_bad_ones_by_code() {
    let d = dir("run");
    let p = |f: &str| d.join(f).to_str().unwrap().to_string();
    ok(&["example", "overhang", "-o", &p("part.stl")]);
    let part = p("part.stl");
    let area = |flags: &[&str]| -> f64 {
        let mut args = vec!["overhangs", part.as_str()];
        args.extend(flags);
        args.push("--json");
        let v: serde_json::Value = serde_json::from_str(&ok(&args)).unwrap();
        v["warped"]["area_mm2"].as_f64().unwrap()
    };
    let (t, f) = (area(TILTED), area(&["--warp", "field", "--expr", ROOF]));
    assert!((t - f).abs() < 1e-9, "tilted {t} mm², field {f} mm²");
    ok(&[
        "run",
        &p("part.stl"),
        "--warp",
        "field",
        "--expr",
        "2*sin(x/5)*cos(y/7)",
        "--base",
        "0,4",
        "-o",
        &p("part.gcode"),
    ]);
    assert!(std::fs::metadata(p("part.gcode")).unwrap().len() > 1000);
    for (expr, says) in [
        ("2*sin(x/5", "is not an expression of x and y"),
        ("x*z", "uses z"),
        ("20*x", "too steep"),
    ] {
        let o = run(&[
            "overhangs",
            &p("part.stl"),
            "--warp",
            "field",
            "--expr",
            expr,
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says), "{expr}: {err}");
    }
}

/// `suggest` lists a fitted field whose `flags` `warpslice warp` takes (split at spaces, as a
/// shell would), and `warp --suggested N` of that entry writes the same warped part; the field
/// is a correction over the best family warp (`--over`), which both jobs store.
#[test]
fn a_suggested_field_is_applied_by_its_flags_and_by_suggested_n() {
    let d = dir("suggested");
    let p = |f: &str| d.join(f).to_str().unwrap().to_string();
    ok(&["example", "overhang", "-o", &p("part.stl")]);
    let json = ok(&[
        "suggest",
        &p("part.stl"),
        "--machine",
        "pax-5axis",
        "--top",
        "20",
        "--json",
    ]);
    let list: Vec<serde_json::Value> = serde_json::from_str(&json).unwrap();
    let (n, field) = list
        .iter()
        .enumerate()
        .find(|(_, s)| {
            s["flags"]
                .as_str()
                .unwrap()
                .starts_with("--warp field --grid ")
        })
        .expect("a fitted field among the suggestions");
    let flags = field["flags"].as_str().unwrap();
    // the fit starts at the best family warp and keeps it as the field's family part
    let over = flags
        .split_whitespace()
        .skip_while(|w| *w != "--over")
        .nth(1)
        .unwrap_or_else(|| panic!("no --over in {flags}"));
    let mut args = vec!["warp", "--machine", "pax-5axis", "-o"];
    let by_flags = p("F.stl");
    args.push(&by_flags);
    let part = p("part.stl");
    args.push(&part);
    args.extend(flags.split_whitespace());
    ok(&args);
    let nth = (n + 1).to_string();
    ok(&[
        "warp",
        &part,
        "--suggested",
        &nth,
        "--machine",
        "pax-5axis",
        "-o",
        &p("N.stl"),
    ]);
    assert_eq!(
        std::fs::read(p("F.stl")).unwrap(),
        std::fs::read(p("N.stl")).unwrap(),
        "{flags}"
    );
    // both jobs store the family part
    for job in ["F.job.json", "N.job.json"] {
        let j: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(p(job)).unwrap()).unwrap();
        assert_eq!(j["warp"]["spec"]["over"], over, "{job}: {j}");
    }
}
