//! Shared helpers of the integration tests: the corpus, the warps of the acceptance matrix,
//! and the checks a–e of the core issue.
#![allow(dead_code)]

pub mod acceptance;
pub mod admissible;
pub mod check;
pub mod closed;
pub mod collide;
pub mod firmware;
pub mod inside;
pub mod machine;
pub mod preset_warp;
pub mod skip;
pub mod written;

use std::path::PathBuf;

#[allow(unused_imports)] // not every test binary that includes tests/common uses it
pub use acceptance::acceptance_warps;
use glam::DVec3;
use warpslice::gcode::{Command, GcodeError, ReadOptions, Reader};
use warpslice::job::Job;
use warpslice::mesh::Mesh;
use warpslice::pipeline::WarpOptions;
use warpslice::toolpath::ToolPoint;
use warpslice::unwarp::UnwarpOutput;
use warpslice::warp::{WarpParams, WarpSpec};

/// `../shared/corpus/stl` next to the repository, if present.
pub fn corpus_dir() -> Option<PathBuf> {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/stl");
    d.join("INDEX.txt").exists().then_some(d)
}

/// The models INDEX.txt marks `accept`: (file name, bytes).
pub fn corpus_accept() -> Vec<(String, Vec<u8>)> {
    let Some(d) = corpus_dir() else {
        return Vec::new();
    };
    let index = std::fs::read_to_string(d.join("INDEX.txt")).unwrap_or_default();
    index
        .lines()
        .filter(|l| !l.starts_with('#') && l.trim_end().ends_with("accept"))
        .filter_map(|l| l.split('\t').next())
        .map(|name| {
            (
                name.to_string(),
                std::fs::read(d.join(name)).expect("corpus file"),
            )
        })
        .collect()
}

/// The generated meshes of the matrix: the crate's examples and [`finned_block`].
pub fn generated_models() -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = warpslice::shapes::EXAMPLES
        .iter()
        .map(|n| {
            (
                format!("gen-{n}"),
                warpslice::mesh::write_stl(&warpslice::shapes::example(n).unwrap(), n),
            )
        })
        .collect();
    v.push(("gen-fins".into(), finned_block()));
    v
}

/// A 20 × 20 × 8 mm block with three 0.2 mm fins, 8 mm long, on its +x side: thinner than a
/// line, so the slicers print them partly or not at all (issue 17).
pub fn finned_block() -> Vec<u8> {
    use glam::DVec3;
    use warpslice::mesh::{shapes::cuboid, Mesh};
    let mut parts = vec![cuboid(
        DVec3::new(-10.0, -10.0, 0.0),
        DVec3::new(10.0, 10.0, 8.0),
    )];
    for k in 0..3 {
        let y = -6.0 + 6.0 * k as f64;
        parts.push(cuboid(
            DVec3::new(9.9, y, 0.0),
            DVec3::new(18.0, y + 0.2, 8.0),
        ));
    }
    let mut m = Mesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    for p in parts {
        let base = m.vertices.len() as u32;
        m.vertices.extend(p.vertices);
        m.triangles
            .extend(p.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    warpslice::mesh::write_stl(&m, "finned block")
}

/// A thin wing: a rhombus 30 × 6 mm footprint (tips at x = −15 and x = 15, widest at x = −5),
/// 40 mm tall, with a fin 10 × 0.2 mm, 6 mm tall, on its top. Each tip is thinner than a line
/// over its last 0.75 mm (−x) and 1.5 mm (+x), unequally, and the fin is thinner than a line:
/// the slicers print the tips and the fin partly or not at all, so the printed box is narrower
/// and lower than the mesh's and its centre is not the mesh's (issue 12 item 3).
#[allow(dead_code)]
pub fn thin_wing() -> Vec<u8> {
    use glam::DVec3;
    use warpslice::mesh::Mesh;
    // a prism over the convex polygon `poly` (counter-clockwise seen from above), z0 … z1
    fn prism(m: &mut Mesh, poly: &[[f64; 2]], z0: f64, z1: f64) {
        let base = m.vertices.len() as u32;
        let n = poly.len() as u32;
        for z in [z0, z1] {
            m.vertices
                .extend(poly.iter().map(|p| DVec3::new(p[0], p[1], z)));
        }
        for i in 1..n - 1 {
            m.triangles.push([base, base + i + 1, base + i]);
            m.triangles.push([base + n, base + n + i, base + n + i + 1]);
        }
        for i in 0..n {
            let j = (i + 1) % n;
            m.triangles.push([base + i, base + j, base + n + j]);
            m.triangles.push([base + i, base + n + j, base + n + i]);
        }
    }
    let mut m = Mesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    prism(
        &mut m,
        &[[-15.0, 0.0], [-5.0, -3.0], [15.0, 0.0], [-5.0, 3.0]],
        0.0,
        40.0,
    );
    prism(
        &mut m,
        &[[-5.0, -0.1], [5.0, -0.1], [5.0, 0.1], [-5.0, 0.1]],
        40.0,
        46.0,
    );
    warpslice::mesh::write_stl(&m, "thin wing")
}

/// A line width as wide as any the three slicers use with a 0.4 mm nozzle at their defaults
/// (PrusaSlicer 0.45, CuraEngine 0.4, Slic3r ≈ 0.48), mm.
pub const LINE_WIDTH: f64 = 0.5;
/// Allowed distance of an object bead centre outside the original mesh: one line width
/// + 0.05 mm (the core issue, acceptance b).
pub const OUTSIDE_TOLERANCE: f64 = LINE_WIDTH + 0.05;

/// What a case measured.
#[derive(Debug, Default, Clone)]
pub struct CaseStats {
    pub points: usize,
    pub worst_outside: f64,
    pub e_in: f64,
    /// What the independent checker of the written file measured.
    pub checked: check::Checked,
    /// Wall time of the slicer, s (for the table; never asserted).
    pub slice_secs: f64,
    /// The unwarp's shape check: the worst point's distance outside the part less its
    /// allowance, mm (refused above 0), and the points beyond their allowance (refused above
    /// `warpslice::unwarp::shape::SHAPE_OUTLIERS`): printed by the matrix so a drift toward the
    /// threshold shows.
    pub shape_margin: f64,
    pub shape_outliers: u64,
    /// Of `shape_margin`, the part measured against the warped mesh's cross-sections.
    pub shape_section_margin: Option<f64>,
}

/// Read every move and non-move line of a G-code with the crate's reader.
pub struct Parsed {
    pub extrusion_e: f64,
    pub non_moves: Vec<String>,
}

pub fn parse(gcode: &[u8]) -> Result<Parsed, GcodeError> {
    let mut p = Parsed {
        extrusion_e: 0.0,
        non_moves: Vec::new(),
    };
    let mut r = Reader::new(ReadOptions::default());
    let mut sink =
        |l: warpslice::gcode::Line<'_>, _s: &warpslice::gcode::State| -> Result<(), GcodeError> {
            match l.command {
                Command::Move { .. } => {
                    for m in l.moves.iter().filter(|m| m.is_extrusion()) {
                        p.extrusion_e += m.e;
                    }
                }
                Command::Comment if l.raw.iter().all(|b| b.is_ascii_whitespace()) => {}
                _ => p
                    .non_moves
                    .push(String::from_utf8_lossy(l.raw).into_owned()),
            }
            Ok(())
        };
    r.push(gcode, &mut sink)?;
    r.finish(&mut sink)?;
    Ok(p)
}

/// The checks of one warp → slice → unwarp result: the independent checker of the written
/// file ([`check::check`]: placement, layer surfaces on vertices and chords, segment length,
/// E per class, travels, retractions, bed), and, on the in-memory toolpath, b (every object
/// bead inside the mesh grown by a line width) and e (non-move lines keep their order).
pub fn check_unwarp(
    model: &Mesh,
    job: &Job,
    expect: &check::Expect<'_>,
    input: &[u8],
    out: &UnwarpOutput,
) -> Result<CaseStats, String> {
    let checked = check::check(expect, input, &out.gcode)?;
    let m2o = DVec3::from_array(out.report.model_to_output);
    let pin = parse(input).map_err(|e| format!("input does not parse: {e}"))?;
    let pout = parse(&out.gcode).map_err(|e| format!("e. the output does not parse: {e}"))?;
    let mut st = CaseStats {
        e_in: pin.extrusion_e,
        checked,
        ..CaseStats::default()
    };

    // the original mesh in the model frame
    let mut m = model.clone();
    m.translate(DVec3::from_array(job.input_to_model));
    let inside = inside::Inside::new(&m, OUTSIDE_TOLERANCE);

    for tp in out
        .toolpath
        .iter()
        .filter(|t: &&ToolPoint| !t.travel && t.e > 0.0 && t.feature.is_object())
    {
        st.points += 1;
        let p = tp.p - m2o;
        // b. inside the mesh grown by one line width + 0.05 mm
        let out_d = inside.outside_distance(p);
        st.worst_outside = st.worst_outside.max(out_d);
        if out_d > OUTSIDE_TOLERANCE {
            return Err(format!(
                "b. point {p} (model frame) lies {out_d:.3} mm outside the model"
            ));
        }
    }
    if st.points == 0 {
        return Err("no object extrusion in the output".into());
    }
    // e. non-move lines keep their order (warpslice's own lines aside)
    let added = |l: &str| {
        l.starts_with("; warpslice")
            || l.starts_with("; generated by warpslice")
            || l.contains("; warpslice:")
    };
    let ours: Vec<&String> = pout.non_moves.iter().filter(|l| !added(l)).collect();
    if ours.len() != pin.non_moves.len() || ours.iter().zip(&pin.non_moves).any(|(a, b)| *a != b) {
        let k = ours
            .iter()
            .zip(&pin.non_moves)
            .position(|(a, b)| *a != b)
            .unwrap_or(ours.len().min(pin.non_moves.len()));
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

/// Extrusions of the object in a slicer's G-code (typed files: object `;TYPE:`s; untyped: all
/// but the first layer, which may be a skirt), counted independently of `register`.
pub fn object_extrusions(input: &[u8]) -> usize {
    let (mut typed, mut n_typed, mut n_upper) = (false, 0, 0);
    let mut r = Reader::new(ReadOptions::default());
    let mut sink =
        |l: warpslice::gcode::Line<'_>, _s: &warpslice::gcode::State| -> Result<(), GcodeError> {
            if let Command::FeatureType(_) = l.command {
                typed = true;
            }
            for m in l.moves.iter().filter(|m| m.is_extrusion()) {
                if typed && m.feature.is_object() {
                    n_typed += 1;
                }
                if m.layer > 0 {
                    n_upper += 1;
                }
            }
            Ok(())
        };
    let _ = r.push(input, &mut sink);
    let _ = r.finish(&mut sink);
    if typed {
        n_typed
    } else {
        n_upper
    }
}

/// Whether the acceptance requires this warp to be refused for this model (the base blend's
/// monotonicity: 1 + w′(z)·g > 0 needs −g < (z1 − z0)/1.5 over the model's bbox), computed
/// independently of the warp module.
pub fn must_refuse(params: &WarpParams, model: &Mesh) -> bool {
    let Some([z0, z1]) = params.base else {
        return false;
    };
    let mut b = model.bbox();
    let t = warpslice::pipeline::input_to_model(&b);
    b.min += t;
    b.max += t;
    let corners = [
        (b.min.x, b.min.y),
        (b.min.x, b.max.y),
        (b.max.x, b.min.y),
        (b.max.x, b.max.y),
    ];
    let worst_neg_g = match params.spec {
        WarpSpec::Belt { angle, toward } => {
            let l = (toward[0] * toward[0] + toward[1] * toward[1]).sqrt();
            corners
                .iter()
                .map(|&(x, y)| -(toward[0] * x + toward[1] * y) / l * angle.to_radians().tan())
                .fold(f64::MIN, f64::max)
        }
        _ => return false,
    };
    worst_neg_g * 1.5 / (z1 - z0) >= 1.0
}

/// Warp options for a matrix case.
pub fn warp_options(params: &WarpParams) -> WarpOptions {
    WarpOptions::new(params.clone())
}
