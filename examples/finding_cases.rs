//! The hand-built finding cases of issue 10 §5 as G-code files, for the page's test
//! (www/tests/run.mjs, "every hand-built finding case through the page"):
//!
//! `cargo run --release --example finding_cases -- DIR`
//!
//! writes `DIR/NAME.gcode` per case and `DIR/cases.json`, a list of `{ name, machine, file,
//! lines }` (`lines`: the file lines the case is built to be found on, empty for the clean
//! file, `null` where the Rust test finds the line by reading the file). The G-code comes from
//! the builders the Rust tests use (tests/common/check_files.rs, tests/common/reach_cases.rs):
//! the plunge, the B head beside the 20 mm wall, the RTN rotate-around, the B head's block
//! reaching the bed near the plate's edge (tests/collision_check.rs); the part wider than the B
//! head's bed and the triple-Z pose outside the tilted volume, written without the machine's
//! travel (tests/machine_reach.rs); the rotary axis past its range and the axis over its feed
//! (tests/check_gcode.rs); the clean files.

#[path = "../tests/common/check_files.rs"]
mod check_files;
// (the tests' kinematics: only the triple-Z case's pose search uses it here)
#[allow(dead_code)]
#[path = "../tests/common/fk.rs"]
mod fk;
#[path = "../tests/common/reach_cases.rs"]
mod reach_cases;
#[path = "../tests/common/synthetic.rs"]
mod synthetic;

use std::path::PathBuf;

/// The B head's tilt and tip x of the bed case (tests/collision_check.rs: the block reaches
/// the plate at 25° with the tip 14 mm from its edge).
const BED_CASE: (f64, f64) = (236.0, 25.0);

fn main() {
    let Some(dir) = std::env::args().nth(1).map(PathBuf::from) else {
        eprintln!("usage: finding_cases DIR");
        std::process::exit(2);
    };
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("{}: {e}", dir.display());
        std::process::exit(2);
    }
    let (plunge, plunge_line, retreat) = check_files::plunge_case();
    let wall = check_files::bhead_wall_case();
    let (rtn, _, turn, _) = check_files::rtn_rotate_around_case();
    let (bed, down) = check_files::bhead_bed_case(BED_CASE.0, BED_CASE.1);
    let (reach, bad) = check_files::rtn_reach_file();
    let (speed, fast) = check_files::bhead_speed_file();
    let cases: Vec<(&str, &str, String, Option<Vec<u64>>)> = vec![
        (
            "plunge",
            "cartesian",
            plunge,
            Some(vec![plunge_line, retreat]),
        ),
        (
            "b-head-wall",
            "fullcontrol-prusa-b",
            wall.text,
            Some(vec![wall.approach, wall.retreat]),
        ),
        ("rtn-rotate-around", "rtn-slicer4rtn", rtn, Some(vec![turn])),
        (
            "b-head-bed-edge",
            "fullcontrol-prusa-b",
            bed,
            Some(vec![down]),
        ),
        (
            "wide-part",
            "fullcontrol-prusa-b",
            reach_cases::wide_part_case().2,
            None,
        ),
        (
            "three-z-pose",
            "ratrig-vcore3-3z",
            reach_cases::three_z_case(),
            None,
        ),
        ("rtn-reach", "rtn-slicer4rtn", reach, Some(vec![bad])),
        (
            "b-head-speed",
            "fullcontrol-prusa-b",
            speed,
            Some(vec![fast]),
        ),
        (
            "clean-pad",
            "cartesian",
            check_files::clean_pad_case(),
            Some(vec![]),
        ),
        (
            "clean",
            "cartesian",
            check_files::clean_file(),
            Some(vec![]),
        ),
    ];
    let mut list = Vec::new();
    for (name, machine, text, lines) in cases {
        let file = dir.join(format!("{name}.gcode"));
        if let Err(e) = std::fs::write(&file, text) {
            eprintln!("{}: {e}", file.display());
            std::process::exit(2);
        }
        list.push(serde_json::json!({
            "name": name,
            "machine": machine,
            "file": file.to_string_lossy(),
            "lines": lines,
        }));
    }
    let manifest = dir.join("cases.json");
    let text = serde_json::to_string_pretty(&list).expect("plain JSON values");
    if let Err(e) = std::fs::write(&manifest, text) {
        eprintln!("{}: {e}", manifest.display());
        std::process::exit(2);
    }
    println!("{} cases in {}", list.len(), manifest.display());
}
