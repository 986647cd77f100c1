//! Travel of the built-in slicer round the part (issue 14: "no pointless travel across the
//! part where a path inside it exists"; `avoid_crossing_perimeters`, src/planar/travel.rs). On
//! a ring (a 20 mm square block with a 10 mm square hole through it), every travel of the
//! planar G-code is checked by the geometry by hand: one that passes over the hole (its segment
//! meets the open square |x|, |y| < 5 − w/2 inside the walls' lines) or outside the block
//! crosses a wall. With the setting on none does; with it off some do (so the count can fail).

#[path = "common/written.rs"]
#[allow(dead_code)]
mod written;

use glam::DVec3;
use warpslice::mesh::shapes::cuboid;
use warpslice::mesh::Mesh;
use warpslice::planar::{slice, Settings};

/// Half the block's side and half the hole's, mm.
const OUTER: f64 = 10.0;
const HOLE: f64 = 5.0;
/// Line width (the default), mm.
const W: f64 = 0.45;

/// The block minus the hole: four bars around it, 2 mm tall, merged by the slicer's union.
fn ring() -> Mesh {
    let bars = [
        cuboid(
            DVec3::new(-OUTER, -OUTER, 0.0),
            DVec3::new(OUTER, -HOLE, 2.0),
        ),
        cuboid(DVec3::new(-OUTER, HOLE, 0.0), DVec3::new(OUTER, OUTER, 2.0)),
        cuboid(DVec3::new(-OUTER, -HOLE, 0.0), DVec3::new(-HOLE, HOLE, 2.0)),
        cuboid(DVec3::new(HOLE, -HOLE, 0.0), DVec3::new(OUTER, HOLE, 2.0)),
    ];
    let mut m = Mesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    for b in bars {
        let base = m.vertices.len() as u32;
        m.vertices.extend(b.vertices);
        m.triangles
            .extend(b.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    m
}

/// Whether the segment a–b meets the open axis-aligned square |x|, |y| < r (Liang–Barsky
/// clipping: some t in [0, 1] puts the point inside on both axes).
fn meets_square(a: DVec3, b: DVec3, r: f64) -> bool {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for (p, d) in [(a.x, b.x - a.x), (a.y, b.y - a.y)] {
        if d == 0.0 {
            if p.abs() >= r {
                return false;
            }
            continue;
        }
        let (t0, t1) = ((-r - p) / d, (r - p) / d);
        lo = lo.max(t0.min(t1));
        hi = hi.min(t0.max(t1));
    }
    lo < hi
}

/// Travels (moves in X or Y without extruding) after the first layer's start, of the object
/// layers, that cross a wall: over the hole or outside the block.
fn crossing_travels(gcode: &str) -> (usize, usize) {
    let w = written::read(gcode.as_bytes()).unwrap();
    let mut travels = 0;
    let mut crossing = 0;
    // from the first extrusion on (the move to the start is not a travel across the part)
    let first = w.moves.iter().position(|m| m.extrudes()).unwrap();
    for m in &w.moves[first..] {
        if m.e > 0.0 || m.from.truncate() == m.to.truncate() || m.from.z != m.to.z {
            continue;
        }
        travels += 1;
        let inner = HOLE - W / 2.0 - 1e-6;
        let outside = |p: DVec3| p.x.abs() > OUTER || p.y.abs() > OUTER;
        if meets_square(m.from, m.to, inner) || outside(m.from) || outside(m.to) {
            crossing += 1;
        }
    }
    (travels, crossing)
}

fn settings(avoid: bool) -> Settings {
    Settings {
        center: [0.0, 0.0],
        skirts: 0,
        avoid_crossing_perimeters: avoid,
        ..Settings::default()
    }
}

#[test]
fn with_avoid_crossing_perimeters_no_travel_crosses_the_hole_of_a_ring() {
    let out = slice(&ring(), &settings(true), "ring").unwrap();
    let (travels, crossing) = crossing_travels(&out.gcode);
    assert!(travels > 100, "only {travels} travels");
    assert_eq!(crossing, 0, "{crossing} of {travels} travels cross a wall");
}

#[test]
fn without_it_travels_cross_the_hole_of_the_same_ring() {
    let out = slice(&ring(), &settings(false), "ring").unwrap();
    let (travels, crossing) = crossing_travels(&out.gcode);
    assert!(crossing > 0, "none of {travels} travels crosses a wall");
}

#[test]
fn routing_round_the_hole_keeps_every_extrusion() {
    // the same lines are printed, only the travels between them change
    let on = slice(&ring(), &settings(true), "ring").unwrap().report;
    let off = slice(&ring(), &settings(false), "ring").unwrap().report;
    assert!(
        (on.filament_mm - off.filament_mm).abs() < 1e-6,
        "{} mm of filament with the setting, {} without",
        on.filament_mm,
        off.filament_mm
    );
}
