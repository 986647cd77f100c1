//! Extruded volume per `;TYPE:` of the built-in slicer beside another slicer's G-code of the
//! same model (a measurement, not a test):
//! `cargo run --release --example type_volumes -- MODEL.stl OTHER.gcode`.
//!
//! The builtin slices MODEL.stl flat with the settings of `tests/planar_vs_prusaslicer.rs`
//! (0.45 mm lines, 0.2 mm layers, two perimeters, 100 % rectilinear infill, no skirt); slice
//! OTHER.gcode with the same (that test's PrusaSlicer command line). Per `;TYPE:` label: the
//! volume E × π(1.75/2)² of the moves that extrude while moving in X or Y (retractions and
//! their push-backs left out), mm³, and the length of those moves, mm.

use std::collections::BTreeMap;

/// Per label: (volume mm³, length mm).
fn per_type(gcode: &str) -> BTreeMap<String, (f64, f64)> {
    let area = std::f64::consts::PI * 1.75 * 1.75 / 4.0;
    let mut out: BTreeMap<String, (f64, f64)> = BTreeMap::new();
    let (mut x, mut y, mut e_abs, mut relative) = (0.0f64, 0.0f64, 0.0f64, false);
    let mut label = String::from("(none)");
    for line in gcode.lines() {
        if let Some(t) = line.trim().strip_prefix(";TYPE:") {
            label = t.trim().to_string();
            continue;
        }
        let code = line.split(';').next().unwrap_or("").trim();
        let mut words = code.split_whitespace();
        let Some(cmd) = words.next() else { continue };
        let word = |l: char| {
            code.split_whitespace()
                .skip(1)
                .find(|w| w.starts_with(l))
                .and_then(|w| w[1..].parse::<f64>().ok())
        };
        match cmd {
            "M83" => relative = true,
            "M82" => relative = false,
            "G92" => e_abs = word('E').unwrap_or(e_abs),
            "G1" | "G0" => {
                let (nx, ny) = (word('X').unwrap_or(x), word('Y').unwrap_or(y));
                let de = match word('E') {
                    Some(v) if relative => v,
                    Some(v) => {
                        let d = v - e_abs;
                        e_abs = v;
                        d
                    }
                    None => 0.0,
                };
                let len = (nx - x).hypot(ny - y);
                if de > 0.0 && len > 0.0 {
                    let t = out.entry(label.clone()).or_default();
                    t.0 += de * area;
                    t.1 += len;
                }
                (x, y) = (nx, ny);
            }
            _ => {}
        }
    }
    out
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [stl, other] = args.as_slice() else {
        eprintln!("usage: type_volumes MODEL.stl OTHER.gcode");
        std::process::exit(2);
    };
    let read = |p: &str| std::fs::read(p).unwrap_or_else(|e| panic!("{p}: {e}"));
    let (mesh, _) = warpslice::mesh::read_stl(&read(stl)).expect("the STL reads");
    let settings = warpslice::planar::Settings {
        layer_height: 0.2,
        first_layer_height: 0.2,
        perimeters: 2,
        fill_density: 100.0,
        extrusion_width: 0.45,
        skirts: 0,
        brim_width: 0.0,
        ..warpslice::planar::Settings::default()
    };
    let builtin = warpslice::planar::slice(&mesh, &settings, stl).expect("the builtin slices");
    let other_text = String::from_utf8_lossy(&read(other)).into_owned();
    let (b, o) = (per_type(&builtin.gcode), per_type(&other_text));
    let mut labels: Vec<&String> = b.keys().chain(o.keys()).collect();
    labels.sort();
    labels.dedup();
    println!("| ;TYPE: | builtin mm³ | builtin mm | other mm³ | other mm |");
    println!("|---|---:|---:|---:|---:|");
    let (mut tb, mut to) = (0.0, 0.0);
    for l in labels {
        let (bv, bl) = b.get(l).copied().unwrap_or_default();
        let (ov, ol) = o.get(l).copied().unwrap_or_default();
        tb += bv;
        to += ov;
        println!("| {l} | {bv:.1} | {bl:.0} | {ov:.1} | {ol:.0} |");
    }
    println!("| all | {tb:.1} | | {to:.1} | |");
}
