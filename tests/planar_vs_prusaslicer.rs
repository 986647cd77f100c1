//! The built-in planar slicer against the mesh and against PrusaSlicer (issue 14, acceptance
//! 2 and 3), on every `accept` corpus model and every generated part of the matrix, each
//! sliced flat (no warp) by both with the same line width (0.45 mm everywhere), layer height
//! (0.2 mm, the first too), two perimeters, 100 % rectilinear infill and no skirt:
//!
//! - **solid**: the object's extruded volume, E × the filament's cross-section π(d/2)², is
//!   within ±5 % of the mesh's volume for every closed mesh (volume by the divergence theorem,
//!   V = Σ v₀·(v₁ × v₂)/6 over the triangles, from the STL; closed: every edge shared by
//!   exactly two triangles in opposite directions), and within ±5 % of PrusaSlicer's;
//! - **walls reach the surface**: points sampled uniformly by area on the side faces (normal
//!   within 60° of horizontal, i.e. the face within 60° of vertical), above the first layer
//!   and below the top layer, lie within one line width (in XY) of an outer-wall extrusion of
//!   their own layer; the builtin's share of such points is at most 2 points below
//!   PrusaSlicer's on every model.
//!
//! Independent of the slicer's code: the G-code is read by the tests' own reader
//! (tests/common/written.rs), the volume and the samples come from the mesh, the placement is
//! the bed centre rule both slicers document (the XY bounding-box centre at (100, 100), the
//! lowest point on the bed). PrusaSlicer runs once per distinct geometry and both tests share
//! its files. A missing PrusaSlicer fails the tests (`WARPSLICE_ALLOW_SKIP=1`: skipped,
//! printed).
#![cfg(not(target_arch = "wasm32"))]

mod common;

use std::collections::HashMap;
use std::sync::OnceLock;

use glam::{DVec2, DVec3};
use warpslice::mesh::Mesh;
use warpslice::planar::Settings;

/// The line width of every extrusion of both slicers here, mm (PrusaSlicer's default for a
/// 0.4 mm nozzle); also the reach of the wall check (acceptance 3: "within one line width").
const LINE_WIDTH: f64 = 0.45;
/// Layer height of both slicers, the first layer's too, mm.
const LAYER_HEIGHT: f64 = 0.2;
/// Filament diameter of both slicers, mm.
const FILAMENT_DIAMETER: f64 = 1.75;
/// Where both slicers put the centre of the model's XY bounding box, mm.
const BED_CENTRE: [f64; 2] = [100.0, 100.0];
/// Largest relative difference of the builtin's extruded volume from the mesh's and from
/// PrusaSlicer's (acceptance 2: ±5 %).
const VOLUME_TOLERANCE: f64 = 0.05;
/// How far below PrusaSlicer's share of covered side points the builtin's may be
/// (acceptance 3: 2 percentage points).
const COVERAGE_SLACK: f64 = 0.02;
/// A face is a side face when it is within this angle of vertical, degrees (acceptance 3).
const SIDE_FACE_TILT_DEG: f64 = 60.0;
/// Two copies of a model (ASCII and binary) are the same geometry when their vertices agree
/// within this, mm (ASCII's decimal rounding).
const SAME_VERTEX: f64 = 1e-4;
/// Side-surface samples per model.
const SAMPLES: usize = 4000;
/// `;TYPE:` names of outer walls: PrusaSlicer labels an external perimeter over air
/// "Overhang perimeter" (counted, so PrusaSlicer's figure is not understated).
const OUTER_WALLS: [&str; 2] = ["External perimeter", "Overhang perimeter"];

/// A check the builtin is known to miss on a model (issue 14, left): the model's name
/// (substring), the check, and why. The tests print it and assert that it still misses, so
/// that a fix fails the test until its entry is removed.
struct KnownGap {
    model: &'static str,
    check: Check,
    why: &'static str,
}

/// The checks of this file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Check {
    VolumeVsMesh,
    VolumeVsPrusaSlicer,
    WallsReachTheSurface,
}

/// What the builtin misses today (measured 2026-11-27; see docs/builtin-slicer.md "Not yet").
const KNOWN_GAPS: [KnownGap; 1] = [KnownGap {
    model: "np_moon",
    check: Check::VolumeVsPrusaSlicer,
    why: "PrusaSlicer (Arachne) ends the moon's thin lines well short of the part's ends (its lines 0.18–0.6 mm long in sections 0.6–1.0 mm long): it extrudes 44 % less than the mesh (also with min_bead_width 10 % and min_feature_size 5 %; its classic generator prints nothing on the first layer), the builtin's thin walls within 1 % of the mesh; both bounds cannot hold",
}];

/// Sort one check's misses into failures: a miss listed in [`KNOWN_GAPS`] is printed, an
/// unlisted miss fails, and a listed gap that no longer misses fails (remove its entry).
fn judge(check: Check, misses: Vec<(String, String)>, names: &[&str]) -> Vec<String> {
    let mut failures = Vec::new();
    for (model, what) in &misses {
        match KNOWN_GAPS
            .iter()
            .find(|g| g.check == check && model.contains(g.model))
        {
            Some(g) => println!("KNOWN GAP ({check:?}, issue 14 left): {what} — {}", g.why),
            None => failures.push(what.clone()),
        }
    }
    for g in KNOWN_GAPS.iter().filter(|g| g.check == check) {
        let measured = names.iter().any(|n| n.contains(g.model));
        let missed = misses.iter().any(|(m, _)| m.contains(g.model));
        if measured && !missed {
            failures.push(format!(
                "{}: {check:?} now passes; remove its KNOWN_GAPS entry ({})",
                g.model, g.why
            ));
        }
        if !measured {
            failures.push(format!(
                "{}: listed in KNOWN_GAPS but not measured",
                g.model
            ));
        }
    }
    failures
}

/// One model: its name, its mesh and its STL bytes.
struct Model {
    name: String,
    mesh: Mesh,
    stl: Vec<u8>,
}

/// What was measured on one model.
struct Measured {
    name: String,
    closed: bool,
    mesh_volume: f64,
    builtin_volume: f64,
    prusa_volume: f64,
    builtin_cover: Cover,
    prusa_cover: Cover,
}

/// Side-surface samples within a line width of an outer wall of their layer, of all samples.
#[derive(Clone, Copy, Debug, Default)]
struct Cover {
    hit: usize,
    of: usize,
}

impl Cover {
    fn share(self) -> f64 {
        if self.of == 0 {
            1.0
        } else {
            self.hit as f64 / self.of as f64
        }
    }
}

/// Every `accept` corpus model and every generated part, one per distinct geometry (the
/// corpus's ASCII and binary copies are sliced once).
fn models() -> Vec<Model> {
    let mut out: Vec<Model> = Vec::new();
    for (name, stl) in common::corpus_accept()
        .into_iter()
        .chain(common::generated_models())
    {
        let (mesh, _) = warpslice::mesh::read_stl(&stl).expect("model reads");
        let same = |a: &Mesh| {
            a.triangles == mesh.triangles
                && a.vertices.len() == mesh.vertices.len()
                && a.vertices
                    .iter()
                    .zip(&mesh.vertices)
                    .all(|(p, q)| (*p - *q).abs().max_element() <= SAME_VERTEX)
        };
        if out.iter().any(|m| same(&m.mesh)) {
            continue;
        }
        out.push(Model { name, mesh, stl });
    }
    out
}

/// Whether every edge is shared by exactly two triangles that run it in opposite directions.
fn is_closed(m: &Mesh) -> bool {
    // undirected edge → (uses, a→b minus b→a with a < b)
    let mut edges: HashMap<(u32, u32), (u32, i32)> = HashMap::new();
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let e = edges.entry((a.min(b), a.max(b))).or_default();
            e.0 += 1;
            e.1 += if a < b { 1 } else { -1 };
        }
    }
    !edges.is_empty() && edges.values().all(|&(n, s)| n == 2 && s == 0)
}

/// The enclosed volume by the divergence theorem, mm³: |Σ v₀·(v₁ × v₂)| / 6.
fn mesh_volume(m: &Mesh) -> f64 {
    let v = |i: u32| m.vertices[i as usize];
    m.triangles
        .iter()
        .map(|t| v(t[0]).dot(v(t[1]).cross(v(t[2]))))
        .sum::<f64>()
        .abs()
        / 6.0
}

/// The object's extruded volume in a planar G-code, mm³: E of the moves that extrude with an
/// object `;TYPE:` (skirt, brim and custom lines aside) × π(d/2)².
fn extruded_volume(gcode: &[u8]) -> Result<f64, String> {
    let w = common::written::read(gcode)?;
    let e: f64 = w
        .extrusions()
        .filter(|m| m.typed == common::written::Typed::Object && !m.e_only)
        .map(|m| m.e)
        .sum();
    Ok(e * std::f64::consts::PI * (FILAMENT_DIAMETER / 2.0).powi(2))
}

/// The builtin's settings for this comparison.
fn builtin_settings() -> Settings {
    Settings {
        layer_height: LAYER_HEIGHT,
        first_layer_height: LAYER_HEIGHT,
        perimeters: 2,
        fill_density: 100.0,
        extrusion_width: LINE_WIDTH,
        filament_diameter: FILAMENT_DIAMETER,
        skirts: 0,
        brim_width: 0.0,
        center: BED_CENTRE,
        ..Settings::default()
    }
}

/// PrusaSlicer's command line for the same settings as [`builtin_settings`].
fn prusaslicer(stl: &std::path::Path, out: &std::path::Path) -> Result<(), String> {
    let width = format!("{LINE_WIDTH}");
    let h = format!("{LAYER_HEIGHT}");
    let mut args: Vec<String> = [
        "--loglevel",
        "1",
        "--export-gcode",
        "--gcode-flavor",
        "marlin2",
        "--nozzle-diameter",
        "0.4",
        "--filament-diameter",
        "1.75",
        "--perimeters",
        "2",
        "--fill-density",
        "100%",
        "--fill-pattern",
        "rectilinear",
        "--skirts",
        "0",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for k in ["--layer-height", "--first-layer-height"] {
        args.extend([k.to_string(), h.clone()]);
    }
    for k in [
        "--extrusion-width",
        "--first-layer-extrusion-width",
        "--perimeter-extrusion-width",
        "--external-perimeter-extrusion-width",
        "--infill-extrusion-width",
        "--solid-infill-extrusion-width",
        "--top-infill-extrusion-width",
    ] {
        args.extend([k.to_string(), width.clone()]);
    }
    args.extend(["--output".into(), out.display().to_string()]);
    args.push(stl.display().to_string());
    let r = std::process::Command::new("prusa-slicer")
        .args(&args)
        .output()
        .map_err(|e| format!("prusa-slicer does not start: {e}"))?;
    if !r.status.success() || !out.exists() {
        return Err(format!(
            "prusa-slicer failed ({}): {}",
            r.status,
            String::from_utf8_lossy(&r.stderr)
                .lines()
                .filter(|l| !l.contains("[trace]"))
                .collect::<Vec<_>>()
                .join(" | ")
        ));
    }
    Ok(())
}

/// The model's mesh where both slicers print it: XY box centre on [`BED_CENTRE`], lowest
/// point on the bed.
fn placed(m: &Mesh) -> Mesh {
    let b = m.bbox();
    let c = b.center();
    let mut p = m.clone();
    p.translate(DVec3::new(
        BED_CENTRE[0] - c.x,
        BED_CENTRE[1] - c.y,
        -b.min.z,
    ));
    p
}

/// A reproducible uniform generator on [0, 1) (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// [`SAMPLES`] points uniform by area on the side faces of the placed mesh `m` that lie above
/// the first layer and below the top layer.
fn side_samples(m: &Mesh) -> Vec<DVec3> {
    let top = m.bbox().max.z;
    let max_nz = SIDE_FACE_TILT_DEG.to_radians().sin();
    let tri = |t: &[u32; 3]| t.map(|i| m.vertices[i as usize]);
    let mut faces = Vec::new();
    let mut total = 0.0;
    for t in &m.triangles {
        let [a, b, c] = tri(t);
        let n = (b - a).cross(c - a);
        let area = n.length() / 2.0;
        if area > 0.0 && (n.z / n.length()).abs() <= max_nz {
            total += area;
            faces.push((total, [a, b, c]));
        }
    }
    let mut rng = Rng(0x5eed);
    let mut out = Vec::new();
    if faces.is_empty() {
        return out;
    }
    for _ in 0..SAMPLES {
        let pick = rng.next() * total;
        let i = faces.partition_point(|f| f.0 < pick).min(faces.len() - 1);
        let [a, b, c] = faces[i].1;
        let (mut u, mut v) = (rng.next(), rng.next());
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        let p = a + (b - a) * u + (c - a) * v;
        if p.z > LAYER_HEIGHT && p.z < top - LAYER_HEIGHT {
            out.push(p);
        }
    }
    out
}

/// Distance from `p` to the segment `a`–`b` in the plane.
fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t - p).length()
}

/// Of the side samples, those within [`LINE_WIDTH`] (XY) of an outer-wall extrusion of their
/// layer: layer k spans (k·h, (k + 1)·h] and its extrusions run at z = (k + 1)·h.
fn coverage(samples: &[DVec3], gcode: &[u8]) -> Result<Cover, String> {
    let text = std::str::from_utf8(gcode).map_err(|e| e.to_string())?;
    // the `;TYPE:` in force on each line (1-based)
    let mut types = vec![String::new()];
    let mut now = String::new();
    for l in text.lines() {
        if let Some(t) = l.trim().strip_prefix(";TYPE:") {
            now = t.trim().to_string();
        }
        types.push(now.clone());
    }
    let w = common::written::read(gcode)?;
    let mut walls: HashMap<i64, Vec<(DVec2, DVec2)>> = HashMap::new();
    for m in w.extrusions() {
        if OUTER_WALLS.contains(&types[m.line].as_str()) && m.from.z == m.to.z {
            let layer = (m.to.z / LAYER_HEIGHT).round() as i64 - 1;
            walls
                .entry(layer)
                .or_default()
                .push((m.from.truncate(), m.to.truncate()));
        }
    }
    let mut c = Cover {
        hit: 0,
        of: samples.len(),
    };
    for p in samples {
        let layer = (p.z / LAYER_HEIGHT).ceil() as i64 - 1;
        let q = p.truncate();
        if walls.get(&layer).is_some_and(|segs| {
            segs.iter()
                .any(|&(a, b)| segment_distance(q, a, b) <= LINE_WIDTH)
        }) {
            c.hit += 1;
        }
    }
    Ok(c)
}

/// Slice one model with both slicers and measure it.
fn measure(m: &Model, dir: &std::path::Path, k: usize) -> Result<Measured, String> {
    let stl = dir.join(format!("{k}.stl"));
    let gcode = dir.join(format!("{k}.gcode"));
    std::fs::write(&stl, &m.stl).map_err(|e| e.to_string())?;
    prusaslicer(&stl, &gcode)?;
    let prusa = std::fs::read(&gcode).map_err(|e| e.to_string())?;
    let builtin = warpslice::planar::slice(&m.mesh, &builtin_settings(), &m.name)
        .map_err(|e| format!("builtin: {e}"))?
        .gcode
        .into_bytes();
    let placed = placed(&m.mesh);
    let samples = side_samples(&placed);
    Ok(Measured {
        name: m.name.clone(),
        closed: is_closed(&m.mesh),
        mesh_volume: mesh_volume(&m.mesh),
        builtin_volume: extruded_volume(&builtin)?,
        prusa_volume: extruded_volume(&prusa)?,
        builtin_cover: coverage(&samples, &builtin)?,
        prusa_cover: coverage(&samples, &prusa)?,
    })
}

/// Every model measured once (both tests read it); `None` when skipped.
fn measured() -> Option<&'static [Result<Measured, String>]> {
    static ALL: OnceLock<Option<Vec<Result<Measured, String>>>> = OnceLock::new();
    ALL.get_or_init(|| {
        let models = models();
        if common::corpus_dir().is_none() {
            common::skip::skip_or_fail(
                "the builtin vs PrusaSlicer",
                "../shared/corpus/stl/INDEX.txt not found next to the repository",
            );
            return None;
        }
        if let Err(e) = warpslice::slicer::available(warpslice::slicer::SlicerKind::PrusaSlicer) {
            common::skip::skip_or_fail("the builtin vs PrusaSlicer", &e.to_string());
            return None;
        }
        let dir = std::env::temp_dir().join(format!("warpslice-vsprusa-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let all = models
            .iter()
            .enumerate()
            .map(|(k, m)| measure(m, &dir, k).map_err(|e| format!("{}: {e}", m.name)))
            .collect();
        let _ = std::fs::remove_dir_all(&dir);
        Some(all)
    })
    .as_deref()
}

/// The models measured, and the failures of those that could not be.
fn split(all: &[Result<Measured, String>]) -> (Vec<&Measured>, Vec<String>) {
    let (mut ok, mut failures) = (Vec::new(), Vec::new());
    for r in all {
        match r {
            Ok(m) => ok.push(m),
            Err(e) => failures.push(e.clone()),
        }
    }
    (ok, failures)
}

#[test]
fn solid_fill_extrudes_the_mesh_volume_and_prusaslicers_within_5_percent() {
    let Some(all) = measured() else { return };
    let (ok, mut failures) = split(all);
    let (mut vs_mesh_misses, mut vs_prusa_misses) = (Vec::new(), Vec::new());
    for m in &ok {
        let vs_mesh = m.builtin_volume / m.mesh_volume - 1.0;
        let vs_prusa = m.builtin_volume / m.prusa_volume - 1.0;
        println!(
            "{:40} closed {:5} mesh {:10.1} mm³ builtin {:10.1} ({:+.2} %) PrusaSlicer {:10.1} (builtin {:+.2} %)",
            m.name,
            m.closed,
            m.mesh_volume,
            m.builtin_volume,
            100.0 * vs_mesh,
            m.prusa_volume,
            100.0 * vs_prusa
        );
        if m.closed && vs_mesh.abs() > VOLUME_TOLERANCE {
            vs_mesh_misses.push((
                m.name.clone(),
                format!(
                    "{}: builtin volume {:.1} mm³ is {:+.2} % of the mesh's {:.1} mm³",
                    m.name,
                    m.builtin_volume,
                    100.0 * vs_mesh,
                    m.mesh_volume
                ),
            ));
        }
        if vs_prusa.abs() > VOLUME_TOLERANCE {
            vs_prusa_misses.push((
                m.name.clone(),
                format!(
                    "{}: builtin volume {:.1} mm³ is {:+.2} % of PrusaSlicer's {:.1} mm³",
                    m.name,
                    m.builtin_volume,
                    100.0 * vs_prusa,
                    m.prusa_volume
                ),
            ));
        }
    }
    let names: Vec<&str> = ok.iter().map(|m| m.name.as_str()).collect();
    failures.extend(judge(Check::VolumeVsMesh, vs_mesh_misses, &names));
    failures.extend(judge(Check::VolumeVsPrusaSlicer, vs_prusa_misses, &names));
    assert!(
        all.iter().flatten().any(|m| m.closed),
        "no closed mesh among the models"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn outer_walls_reach_the_side_surface_as_often_as_prusaslicers() {
    let Some(all) = measured() else { return };
    let (ok, mut failures) = split(all);
    let mut misses = Vec::new();
    for m in &ok {
        let (b, p) = (m.builtin_cover.share(), m.prusa_cover.share());
        println!(
            "{:40} side samples {:5}: within a line width of an outer wall: builtin {:6.2} %, PrusaSlicer {:6.2} %",
            m.name,
            m.builtin_cover.of,
            100.0 * b,
            100.0 * p
        );
        if b < p - COVERAGE_SLACK {
            misses.push((m.name.clone(), format!(
                "{}: {:.2} % of the side samples are within a line width of the builtin's outer wall, PrusaSlicer's {:.2} %",
                m.name,
                100.0 * b,
                100.0 * p
            )));
        }
    }
    let names: Vec<&str> = ok.iter().map(|m| m.name.as_str()).collect();
    failures.extend(judge(Check::WallsReachTheSurface, misses, &names));
    assert!(
        all.iter().flatten().any(|m| m.prusa_cover.of > 0),
        "no side samples on any model"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
