//! Bridges of the built-in slicer (issue 14, the solid check against PrusaSlicer): the infill
//! of a layer over air is "Bridge infill" at bridge flow — PrusaSlicer 2.5's thick bridges, a
//! round thread of the nozzle's diameter d (cross-section π·d²/4), threads d + 0.05 mm apart —
//! grown 3 mm into the part it rests on (PrusaSlicer 2.5's `EXTERNAL_INFILL_MARGIN`), on that
//! layer only. The part is a table: two 5 × 20 × 2 mm legs and a 30 × 20 × 1 mm top over them;
//! the oracle is the table's geometry by hand, the G-code read by the tests' own reader
//! (tests/common/written.rs) and the `;TYPE:` comments.

#[path = "common/planar_lines.rs"]
mod planar_lines;
#[path = "common/written.rs"]
#[allow(dead_code)]
mod written;

use planar_lines::Line;

use glam::DVec3;
use warpslice::mesh::shapes::cuboid;
use warpslice::mesh::Mesh;
use warpslice::planar::{slice, Settings};

/// Layer height, mm.
const H: f64 = 0.2;
/// The legs are x ∈ ±[INNER, OUTER], y ∈ ±HALF_DEPTH, z ∈ [0, LEG]; the top spans
/// x ∈ ±OUTER, z ∈ [LEG, LEG + TOP], mm.
const INNER: f64 = 10.0;
const OUTER: f64 = 15.0;
const HALF_DEPTH: f64 = 10.0;
const LEG: f64 = 2.0;
const TOP: f64 = 1.0;
/// The nozzle and filament diameters (the defaults), mm.
const NOZZLE: f64 = 0.4;
const FILAMENT: f64 = 1.75;
/// How far a bridge reaches into the part it rests on, mm (PrusaSlicer 2.5's
/// `EXTERNAL_INFILL_MARGIN`).
const ANCHOR: f64 = 3.0;
/// Slack on positions read back from 3-decimal G-code, mm.
const READ_SLACK: f64 = 0.002;

/// The object's extrusions of a planar file (layers [`H`] high, the default filament).
fn lines(gcode: &str) -> Vec<Line> {
    planar_lines::lines(gcode, H, FILAMENT)
}

/// The table: the legs and the top as three boxes (touching shells, unioned by the slicer).
fn table() -> Mesh {
    let mut mesh = Mesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    for (min, max) in [
        (
            DVec3::new(-OUTER, -HALF_DEPTH, 0.0),
            DVec3::new(-INNER, HALF_DEPTH, LEG),
        ),
        (
            DVec3::new(INNER, -HALF_DEPTH, 0.0),
            DVec3::new(OUTER, HALF_DEPTH, LEG),
        ),
        (
            DVec3::new(-OUTER, -HALF_DEPTH, LEG),
            DVec3::new(OUTER, HALF_DEPTH, LEG + TOP),
        ),
    ] {
        let b = cuboid(min, max);
        let base = mesh.vertices.len() as u32;
        mesh.vertices.extend(b.vertices);
        mesh.triangles
            .extend(b.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    mesh
}

fn sliced() -> Vec<Line> {
    let s = Settings {
        center: [0.0, 0.0],
        skirts: 0,
        fill_density: 100.0,
        ..Settings::for_layers(H)
    };
    lines(&slice(&table(), &s, "table").unwrap().gcode)
}

/// The first layer of the top, over the air between the legs, is bridged: its bridge lines
/// cover every point over the air inside the perimeters (within half a thread pitch), reach
/// [`ANCHOR`] mm onto the legs and no farther, and no other layer has a bridge.
#[test]
fn the_layer_over_air_is_bridged_and_anchored_on_the_legs() {
    let all = sliced();
    let first_top = (LEG / H).round() as usize;
    let bridges: Vec<&Line> = all.iter().filter(|l| l.role == "Bridge infill").collect();
    assert!(!bridges.is_empty(), "no bridge infill at all");
    let layers: std::collections::BTreeSet<usize> = bridges.iter().map(|l| l.layer).collect();
    assert_eq!(
        layers.into_iter().collect::<Vec<_>>(),
        vec![first_top],
        "bridges only on the top's first layer"
    );
    // anchored: |x| reaches INNER + ANCHOR and not beyond (the legs' infill region is wider)
    let reach = bridges
        .iter()
        .flat_map(|l| [l.from[0].abs(), l.to[0].abs()])
        .fold(0.0, f64::max);
    assert!(
        (reach - (INNER + ANCHOR)).abs() <= 0.05,
        "bridges reach |x| = {reach:.3}, not the air's edge + {ANCHOR} = {}",
        INNER + ANCHOR
    );
    // covered: over the air, inside the two perimeters (0.45 + 0.42 mm) and a pitch more
    let pitch = NOZZLE + 0.05;
    let inset = 0.45 + 0.42 + pitch;
    let mut worst: f64 = 0.0;
    let n = 60;
    for i in 0..=n {
        for j in 0..=n {
            let p = [
                -INNER + 2.0 * INNER * i as f64 / n as f64,
                -(HALF_DEPTH - inset) + 2.0 * (HALF_DEPTH - inset) * j as f64 / n as f64,
            ];
            let d = bridges
                .iter()
                .map(|l| l.distance(p))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    assert!(
        worst <= pitch / 2.0 + READ_SLACK,
        "a point over the air {worst:.3} mm from the nearest bridge line (half the pitch: {})",
        pitch / 2.0
    );
}

/// Every bridge line deposits the round thread's cross-section, π·d²/4 with d the nozzle's
/// diameter, per mm of its length (the filament read back, 5-decimal E), and the threads lie
/// d + 0.05 mm apart.
#[test]
fn bridge_lines_are_round_threads_of_the_nozzles_diameter_a_thread_and_a_gap_apart() {
    let all = sliced();
    let bridges: Vec<&Line> = all
        .iter()
        .filter(|l| l.role == "Bridge infill" && l.length() > 1.0)
        .collect();
    let thread = std::f64::consts::PI * NOZZLE * NOZZLE / 4.0;
    for l in &bridges {
        let per_mm = l.volume / l.length();
        assert!(
            (per_mm - thread).abs() <= 0.002 * thread + 2.5e-5 / l.length(),
            "a bridge line deposits {per_mm:.5} mm²/mm, the thread {thread:.5}"
        );
    }
    // the pitch: offsets of the lines across their direction
    let d = [
        bridges[0].to[0] - bridges[0].from[0],
        bridges[0].to[1] - bridges[0].from[1],
    ];
    let len = d[0].hypot(d[1]);
    let normal = [-d[1] / len, d[0] / len];
    let mut offsets: Vec<f64> = bridges
        .iter()
        .map(|l| l.from[0] * normal[0] + l.from[1] * normal[1])
        .collect();
    offsets.sort_by(f64::total_cmp);
    offsets.dedup_by(|a, b| (*a - *b).abs() < 0.01);
    let steps: Vec<f64> = offsets.windows(2).map(|w| w[1] - w[0]).collect();
    let pitch = NOZZLE + 0.05;
    assert!(
        steps.iter().all(|s| (s - pitch).abs() <= 0.01),
        "thread pitch {:?} … not {pitch}",
        &steps[..steps.len().min(5)]
    );
}
