//! Shared helpers of the integration tests: the corpus, the warps of the acceptance matrix,
//! and the checks a–e of the core issue.
#![allow(dead_code)]

pub mod inside;

use std::path::PathBuf;

use glam::DVec3;
use warpslice::gcode::{Command, GcodeError, ReadOptions, Reader};
use warpslice::job::Job;
use warpslice::mesh::Mesh;
use warpslice::pipeline::WarpOptions;
use warpslice::toolpath::{Feature, ToolPoint};
use warpslice::unwarp::UnwarpOutput;
use warpslice::warp::{Direction, WarpParams, WarpSpec};

/// `../shared/corpus/stl` next to the repository, if present.
pub fn corpus_dir() -> Option<PathBuf> {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/stl");
    d.join("INDEX.txt").exists().then_some(d)
}

/// The models INDEX.txt marks `accept`: (file name, bytes).
pub fn corpus_accept() -> Vec<(String, Vec<u8>)> {
    let Some(d) = corpus_dir() else { return Vec::new() };
    let index = std::fs::read_to_string(d.join("INDEX.txt")).unwrap_or_default();
    index
        .lines()
        .filter(|l| !l.starts_with('#') && l.trim_end().ends_with("accept"))
        .filter_map(|l| l.split('\t').next())
        .map(|name| (name.to_string(), std::fs::read(d.join(name)).expect("corpus file")))
        .collect()
}

/// The warps of the acceptance matrix: curved outward s = 0.3, tilted outward s = 0.2, conic
/// 30° outward, conic 30° inward, belt 15° with --base 0.6,10.
pub fn acceptance_warps() -> Vec<(&'static str, WarpParams)> {
    vec![
        ("curved-out-0.3", WarpParams { spec: WarpSpec::Curved { strength: 0.3, direction: Direction::Outward, offset: 0.0, width: 0.0 }, base: None }),
        ("tilted-out-0.2", WarpParams { spec: WarpSpec::Tilted { strength: 0.2, direction: Direction::Outward, offset: 0.0 }, base: None }),
        ("conic-out-30", WarpParams { spec: WarpSpec::Conic { angle: 30.0, direction: Direction::Outward, center: [0.0, 0.0] }, base: None }),
        ("conic-in-30", WarpParams { spec: WarpSpec::Conic { angle: 30.0, direction: Direction::Inward, center: [0.0, 0.0] }, base: None }),
        ("belt-15-base", WarpParams { spec: WarpSpec::Belt { angle: 15.0, toward: [0.0, 1.0] }, base: Some([0.6, 10.0]) }),
    ]
}

/// The generated meshes of the matrix.
pub fn generated_models() -> Vec<(String, Vec<u8>)> {
    warpslice::shapes::EXAMPLES
        .iter()
        .map(|n| (format!("gen-{n}"), warpslice::mesh::write_stl(&warpslice::shapes::example(n).unwrap(), n)))
        .collect()
}

/// A line width as wide as any the three slicers use with a 0.4 mm nozzle at their defaults
/// (PrusaSlicer 0.45, CuraEngine 0.4, Slic3r ≈ 0.48), mm.
pub const LINE_WIDTH: f64 = 0.5;
/// Allowed distance of an object bead centre outside the original mesh: one line width
/// + 0.05 mm (the core issue, acceptance b).
pub const OUTSIDE_TOLERANCE: f64 = LINE_WIDTH + 0.05;
/// Acceptance a: distance of T_z(p) from a slicer layer plane, mm.
pub const LAYER_SURFACE_TOLERANCE: f64 = 0.01;
/// Acceptance c: relative E difference.
pub const E_TOLERANCE: f64 = 0.02;
/// Acceptance d: lowest z, mm.
pub const BED_TOLERANCE: f64 = -0.001;

/// What a case measured.
#[derive(Debug, Default, Clone)]
pub struct CaseStats {
    pub points: usize,
    pub worst_layer_distance: f64,
    pub worst_outside: f64,
    pub e_in: f64,
    pub e_out: f64,
    pub e_anchor: f64,
    pub min_z: f64,
    pub clamped: u64,
}

/// Read every move and non-move line of a G-code with the crate's reader.
pub struct Parsed {
    pub extrusion_e: f64,
    pub min_z: f64,
    pub layer_zs: Vec<f64>,
    pub non_moves: Vec<String>,
}

pub fn parse(gcode: &[u8]) -> Result<Parsed, GcodeError> {
    let mut p = Parsed { extrusion_e: 0.0, min_z: f64::INFINITY, layer_zs: Vec::new(), non_moves: Vec::new() };
    let mut r = Reader::new(ReadOptions::default());
    let mut sink = |l: warpslice::gcode::Line<'_>, _s: &warpslice::gcode::State| -> Result<(), GcodeError> {
        match l.command {
            Command::Move { .. } => {
                for m in l.moves {
                    if m.from != m.to {
                        p.min_z = p.min_z.min(m.to.z);
                    }
                    if m.is_extrusion() {
                        p.extrusion_e += m.e;
                        p.layer_zs.push(m.to.z);
                    }
                }
            }
            Command::Comment if l.raw.iter().all(|b| b.is_ascii_whitespace()) => {}
            _ => p.non_moves.push(String::from_utf8_lossy(l.raw).into_owned()),
        }
        Ok(())
    };
    r.push(gcode, &mut sink)?;
    r.finish(&mut sink)?;
    p.layer_zs.sort_by(f64::total_cmp);
    p.layer_zs.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    Ok(p)
}

fn nearest(sorted: &[f64], v: f64) -> f64 {
    let i = sorted.partition_point(|&x| x < v);
    let mut best = f64::INFINITY;
    for k in [i.wrapping_sub(1), i] {
        if let Some(&x) = sorted.get(k) {
            best = best.min((x - v).abs());
        }
    }
    best
}

/// Checks a–e of the core issue on one warp → slice → unwarp result.
pub fn check_unwarp(model: &Mesh, job: &Job, input: &[u8], out: &UnwarpOutput) -> Result<CaseStats, String> {
    let mut params = job.warp.clone();
    let warp = params.build(&job.model_bbox).map_err(|e| e.to_string())?;
    let m2o = DVec3::from_array(out.report.model_to_output);
    let pin = parse(input).map_err(|e| format!("input does not parse: {e}"))?;
    let pout = parse(&out.gcode).map_err(|e| format!("e. the output does not parse: {e}"))?;
    let mut st = CaseStats { e_in: pin.extrusion_e, e_out: pout.extrusion_e, e_anchor: out.report.e_anchor, min_z: pout.min_z, clamped: out.report.clamped_points, ..CaseStats::default() };

    // the original mesh in the model frame
    let mut m = model.clone();
    m.translate(DVec3::from_array(job.input_to_model));
    let inside = inside::Inside::new(&m, OUTSIDE_TOLERANCE);

    let flat = |f: Feature| !f.is_object();
    for tp in out.toolpath.iter().filter(|t: &&ToolPoint| !t.travel && t.e > 0.0 && !flat(t.feature)) {
        st.points += 1;
        let p = tp.p - m2o;
        // a. on a layer surface (points clamped to the bed excepted: they are counted)
        if p.z > 0.0 {
            let t = warp.forward(p).z + job.stl_z_offset;
            let d = nearest(&pin.layer_zs, t);
            st.worst_layer_distance = st.worst_layer_distance.max(d);
            if d > LAYER_SURFACE_TOLERANCE {
                return Err(format!("a. point {p} (model frame) lies {d:.4} mm off every layer surface (T_z + offset = {t:.4})"));
            }
        }
        // b. inside the mesh grown by one line width + 0.05 mm
        let out_d = inside.outside_distance(p);
        st.worst_outside = st.worst_outside.max(out_d);
        if out_d > OUTSIDE_TOLERANCE {
            return Err(format!("b. point {p} (model frame) lies {out_d:.3} mm outside the model"));
        }
    }
    if st.points == 0 {
        return Err("no object extrusion in the output".into());
    }
    // c. total E within 2 % (the anchor layer is not printed)
    let expect = st.e_in - st.e_anchor;
    if ((st.e_out - expect) / expect).abs() > E_TOLERANCE {
        return Err(format!("c. E out {:.3} mm vs slicer E {:.3} mm − anchor {:.3} mm", st.e_out, st.e_in, st.e_anchor));
    }
    // d. nothing below the bed
    if st.min_z < BED_TOLERANCE {
        return Err(format!("d. a point at z = {} below the bed", st.min_z));
    }
    // e. non-move lines keep their order (warpslice's own lines aside)
    let added = |l: &str| l.starts_with("; warpslice") || l.starts_with("; generated by warpslice") || l.contains("; warpslice:");
    let ours: Vec<&String> = pout.non_moves.iter().filter(|l| !added(l)).collect();
    if ours.len() != pin.non_moves.len() || ours.iter().zip(&pin.non_moves).any(|(a, b)| *a != b) {
        let k = ours.iter().zip(&pin.non_moves).position(|(a, b)| *a != b).unwrap_or(ours.len().min(pin.non_moves.len()));
        return Err(format!(
            "e. non-move lines differ at #{k}: out {:?} vs in {:?} ({} vs {} lines)",
            ours.get(k),
            pin.non_moves.get(k),
            ours.len(),
            pin.non_moves.len()
        ));
    }
    Ok(st)
}

/// Warp options for a matrix case.
pub fn warp_options(params: &WarpParams) -> WarpOptions {
    WarpOptions::new(params.clone())
}
