//! Thin walls of the built-in slicer (issue 14): parts of a layer narrower than one line are
//! printed as one line along their middle, its cross-section the local thickness × the layer
//! height (`src/planar/thin.rs`), and parts thinner than `MIN_THIN_WIDTH` are counted, not
//! printed. The oracles are the meshes' geometry by hand (a plate, a wedge, a thin tube), the
//! G-code read by the tests' own reader (tests/common/written.rs) and the `;TYPE:` comments.

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

/// Layer height of every case, mm.
const H: f64 = 0.2;
/// Height of every part, mm: ten layers.
const HEIGHT: f64 = 2.0;
/// Filament diameter (the default), mm.
const FILAMENT: f64 = 1.75;

/// The defaults, the part centred on the origin, no skirt.
fn settings() -> Settings {
    Settings {
        center: [0.0, 0.0],
        skirts: 0,
        ..Settings::default()
    }
}

/// The object's extrusions of a planar file (layers [`H`] high, the default filament).
fn lines(gcode: &str) -> Vec<Line> {
    planar_lines::lines(gcode, H, FILAMENT)
}

/// A prism of height [`HEIGHT`] over the convex polygon `poly` (counter-clockwise), closed,
/// outward-facing: the sides as quads, top and bottom as fans.
fn convex_prism(poly: &[[f64; 2]]) -> Mesh {
    let n = poly.len() as u32;
    let mut vertices = Vec::new();
    for z in [0.0, HEIGHT] {
        vertices.extend(poly.iter().map(|p| DVec3::new(p[0], p[1], z)));
    }
    let mut triangles = Vec::new();
    for i in 0..n {
        let j = (i + 1) % n;
        triangles.push([i, j, n + j]);
        triangles.push([i, n + j, n + i]);
    }
    for i in 1..n - 1 {
        triangles.push([0, i + 1, i]);
        triangles.push([n, n + i, n + i + 1]);
    }
    Mesh {
        vertices,
        triangles,
    }
}

/// A tube of height [`HEIGHT`] between regular `n`-gons of circumradius `r_in` and `r_out`
/// centred on the z axis, closed, outward-facing.
fn tube(r_in: f64, r_out: f64, n: u32) -> Mesh {
    let ring = |r: f64, z: f64| {
        (0..n).map(move |k| {
            let a = std::f64::consts::TAU * f64::from(k) / f64::from(n);
            DVec3::new(r * a.cos(), r * a.sin(), z)
        })
    };
    // 0: outer bottom, n: outer top, 2n: inner bottom, 3n: inner top
    let mut vertices: Vec<DVec3> = ring(r_out, 0.0).collect();
    vertices.extend(ring(r_out, HEIGHT));
    vertices.extend(ring(r_in, 0.0));
    vertices.extend(ring(r_in, HEIGHT));
    let (ob, ot, ib, it) = (0, n, 2 * n, 3 * n);
    let mut triangles = Vec::new();
    for i in 0..n {
        let j = (i + 1) % n;
        triangles.push([ob + i, ob + j, ot + j]); // outer side, facing out
        triangles.push([ob + i, ot + j, ot + i]);
        triangles.push([ib + i, it + j, ib + j]); // inner side, facing the axis
        triangles.push([ib + i, it + i, it + j]);
        triangles.push([ot + i, ot + j, it + j]); // top, facing up
        triangles.push([ot + i, it + j, it + i]);
        triangles.push([ob + i, ib + j, ob + j]); // bottom, facing down
        triangles.push([ob + i, ib + i, ib + j]);
    }
    Mesh {
        vertices,
        triangles,
    }
}

#[test]
fn a_plate_thinner_than_a_line_is_printed_as_one_line_along_its_middle_holding_its_volume() {
    // 0.3 mm × 20 mm × 2 mm, centred: the middle is x = 0, y from −10 to 10
    let plate = cuboid(
        DVec3::new(-0.15, -10.0, 0.0),
        DVec3::new(0.15, 10.0, HEIGHT),
    );
    let out = slice(&plate, &settings(), "plate").unwrap();
    let ls = lines(&out.gcode);
    assert_eq!(out.report.layers, 10);
    for k in 0..10 {
        let layer: Vec<&Line> = ls.iter().filter(|l| l.layer == k).collect();
        assert!(!layer.is_empty(), "layer {k}: nothing printed");
        for l in &layer {
            assert_eq!(l.role, "External perimeter", "layer {k}");
            for p in [l.from, l.to] {
                assert!(
                    p[0].abs() <= 0.005,
                    "layer {k}: {p:?} is off the middle x = 0"
                );
            }
        }
        let length: f64 = layer.iter().map(|l| l.length()).sum();
        assert!(
            (length - 20.0).abs() <= 0.02,
            "layer {k}: the line is {length} mm long, the plate 20 mm"
        );
        // cross-section = thickness × layer height: the plate's own 0.3 × 20 × 0.2 mm³
        let volume: f64 = layer.iter().map(|l| l.volume).sum();
        assert!(
            (volume - 1.2).abs() <= 0.01 * 1.2,
            "layer {k}: {volume} mm³ extruded, the layer holds 1.2 mm³"
        );
    }
    assert_eq!(out.report.thin_walls, 10, "{:?}", out.report);
    assert!(
        (out.report.thin_wall_mm - 200.0).abs() <= 0.2,
        "{:?}",
        out.report
    );
    assert_eq!(out.report.thin_unprinted, 0);
}

#[test]
fn a_wedges_line_width_follows_its_local_thickness() {
    // thickness t(x) = 0.12 + 0.28·(x + 10)/20 from x = −10 to 10, symmetric about y = 0
    let t = |x: f64| 0.12 + 0.28 * (x + 10.0) / 20.0;
    let wedge = convex_prism(&[[-10.0, -0.06], [10.0, -0.2], [10.0, 0.2], [-10.0, 0.06]]);
    let out = slice(&wedge, &settings(), "wedge").unwrap();
    let ls = lines(&out.gcode);
    let mut checked = 0;
    for l in &ls {
        let mx = (l.from[0] + l.to[0]) / 2.0;
        assert!(
            l.from[1].abs() <= 0.005 && l.to[1].abs() <= 0.005,
            "{:?}–{:?} is off the middle y = 0",
            l.from,
            l.to
        );
        if mx.abs() > 9.5 {
            continue; // the ends' segments take their neighbour's thickness
        }
        let seen = l.volume / (l.length() * H);
        assert!(
            (seen - t(mx)).abs() <= 0.01,
            "at x = {mx:.2}: the line deposits a {seen:.4} mm wide band, the wedge is {:.4} mm thick",
            t(mx)
        );
        checked += 1;
    }
    assert!(checked >= 10 * 20, "only {checked} segments checked");
    let volume: f64 = ls.iter().map(|l| l.volume).sum();
    let mesh = 20.0 * (0.12 + 0.4) / 2.0 * HEIGHT;
    assert!(
        (volume / mesh - 1.0).abs() <= 0.01,
        "{volume} mm³ extruded, the wedge holds {mesh} mm³"
    );
}

#[test]
fn a_part_thinner_than_the_floor_is_counted_and_not_printed() {
    // 0.06 mm: below MIN_THIN_WIDTH (0.1 mm)
    let foil = cuboid(
        DVec3::new(-0.03, -10.0, 0.0),
        DVec3::new(0.03, 10.0, HEIGHT),
    );
    let out = slice(&foil, &settings(), "foil").unwrap();
    assert!(lines(&out.gcode).is_empty(), "the foil was printed");
    assert_eq!(out.report.thin_walls, 0);
    assert_eq!(out.report.thin_unprinted, 10, "{:?}", out.report);
    const { assert!(warpslice::planar::thin::MIN_THIN_WIDTH > 0.06) };
}

#[test]
fn a_thin_tube_is_printed_as_one_closed_line_on_its_middle_circle() {
    let (r_in, r_out, n) = (4.85, 5.15, 96);
    let out = slice(&tube(r_in, r_out, n), &settings(), "tube").unwrap();
    let ls = lines(&out.gcode);
    // the n-gons' area between them, × h per layer
    let ngon = |r: f64| f64::from(n) / 2.0 * r * r * (std::f64::consts::TAU / f64::from(n)).sin();
    let per_layer = (ngon(r_out) - ngon(r_in)) * H;
    for k in 0..10 {
        let layer: Vec<&Line> = ls.iter().filter(|l| l.layer == k).collect();
        assert!(layer.len() > 50, "layer {k}: {} moves", layer.len());
        for w in layer.windows(2) {
            assert_eq!(w[0].to, w[1].from, "layer {k}: the line is broken");
        }
        let (first, last) = (layer[0].from, layer[layer.len() - 1].to);
        assert!(
            (first[0] - last[0]).hypot(first[1] - last[1]) < 1e-3,
            "layer {k}: the line does not close ({first:?} … {last:?})"
        );
        for l in &layer {
            let r = l.to[0].hypot(l.to[1]);
            // within a tenth of the wall's 0.3 mm: the sections are simplified to within
            // RESOLUTION (0.0125 mm) of the n-gons, and the chords between the simplified
            // contours' vertices are slanted (measured: 0.025 mm at most)
            assert!((r - 5.0).abs() <= 0.03, "layer {k}: a point at radius {r}");
        }
        let volume: f64 = layer.iter().map(|l| l.volume).sum();
        assert!(
            (volume / per_layer - 1.0).abs() <= 0.01,
            "layer {k}: {volume} mm³ extruded, the layer holds {per_layer} mm³"
        );
    }
    assert_eq!(out.report.thin_walls, 10, "{:?}", out.report);
}
