//! The built-in planar slicer (issue 14), checked against oracles written from the meshes and
//! the settings' documented formulas, not from the slicer's code: a small G-code walker of
//! its own (`G1`, `M82`/`M83`, `G92`, `;Z:`, `;TYPE:`), the cube's and cylinder's geometry by
//! hand, the layer grid `z_k = first_layer_height + k·layer_height`.

#[cfg(not(target_arch = "wasm32"))]
#[path = "common/cli_part.rs"]
#[allow(dead_code)]
mod cli_part;
#[cfg(not(target_arch = "wasm32"))]
#[path = "common/synthetic.rs"]
#[allow(dead_code)]
mod synthetic;

use glam::DVec3;
use warpslice::mesh::Mesh;
use warpslice::planar::{slice, Settings, Sliced};

/// One extruding move of the walked file.
#[derive(Clone, Debug)]
struct Extrusion {
    layer_z: f64,
    role: String,
    from: [f64; 2],
    to: [f64; 2],
}

/// What the walker read: every extrusion, every `;Z:` and the net E.
#[derive(Default, Debug)]
struct Walk {
    zs: Vec<f64>,
    extrusions: Vec<Extrusion>,
    net_e: f64,
}

/// Walk planar G-code: absolute XY, E relative after M83 or absolute after M82, `G92 E`.
fn walk(gcode: &str) -> Walk {
    let mut w = Walk::default();
    let (mut x, mut y, mut e_abs) = (0.0, 0.0, 0.0);
    let mut relative = true;
    let mut role = String::new();
    for line in gcode.lines() {
        if let Some(z) = line.strip_prefix(";Z:") {
            w.zs.push(z.parse().unwrap());
            continue;
        }
        if let Some(t) = line.strip_prefix(";TYPE:") {
            role = t.to_string();
            continue;
        }
        let code = line.split(';').next().unwrap().trim();
        let mut words = code.split_whitespace();
        let Some(cmd) = words.next() else { continue };
        let word = |l: char| {
            code.split_whitespace()
                .skip(1)
                .find(|t| t.starts_with(l))
                .map(|t| t[1..].parse::<f64>().unwrap())
        };
        match cmd {
            "M83" => relative = true,
            "M82" => relative = false,
            "G92" => {
                if let Some(v) = word('E') {
                    e_abs = v;
                }
            }
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
                w.net_e += de;
                let moved = nx != x || ny != y;
                if de > 0.0 && moved {
                    w.extrusions.push(Extrusion {
                        layer_z: *w.zs.last().unwrap_or(&0.0),
                        role: role.clone(),
                        from: [x, y],
                        to: [nx, ny],
                    });
                }
                (x, y) = (nx, ny);
            }
            _ => {}
        }
    }
    w
}

/// The defaults with the part's footprint centred on the origin (where the oracles below
/// put it), then `sets`.
fn settings(sets: &[&str]) -> Settings {
    let mut s = Settings {
        center: [0.0, 0.0],
        ..Settings::default()
    };
    for a in sets {
        s.set(a).unwrap();
    }
    s
}

fn sliced(mesh: &Mesh, s: &Settings) -> Sliced {
    slice(mesh, s, "test").unwrap()
}

/// Filament cross-section of 1.75 mm filament, mm².
fn filament_area(d: f64) -> f64 {
    std::f64::consts::PI * d * d / 4.0
}

/// The file's net E × the filament's cross-section is the 20 mm cube's 8000 mm³ within ±5 %.
fn assert_holds_the_cube(w: &Walk) {
    let volume = w.net_e * filament_area(1.75);
    assert!(
        (volume - 8000.0).abs() <= 0.05 * 8000.0,
        "extruded {volume} mm³ for the 8000 mm³ cube"
    );
}

/// The distance from `p` to the segment `a–b`.
fn seg_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 == 0.0 {
        0.0
    } else {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    };
    ((p[0] - a[0] - t * dx).powi(2) + (p[1] - a[1] - t * dy).powi(2)).sqrt()
}

/// A 20 mm cube on z = 0 centred on the z axis, by hand: 8 corners, 12 triangles, outward.
fn cube20() -> Mesh {
    box_with_rows(20.0, &[])
}

/// A square prism of side `a` from z = 0 to z = a whose side walls have a vertex row at every
/// height in `rows` (0 < row < a), closed and outward-facing.
fn box_with_rows(a: f64, rows: &[f64]) -> Mesh {
    let h = a / 2.0;
    let corners = [[-h, -h], [h, -h], [h, h], [-h, h]]; // counter-clockwise from above
    let mut zs = vec![0.0];
    zs.extend_from_slice(rows);
    zs.push(a);
    let mut vertices = Vec::new();
    for &z in &zs {
        for c in corners {
            vertices.push(DVec3::new(c[0], c[1], z));
        }
    }
    let v = |row: usize, c: usize| (row * 4 + c % 4) as u32;
    let mut triangles = Vec::new();
    for r in 0..zs.len() - 1 {
        for c in 0..4 {
            // outward: counter-clockwise seen from outside
            triangles.push([v(r, c), v(r, c + 1), v(r + 1, c + 1)]);
            triangles.push([v(r, c), v(r + 1, c + 1), v(r + 1, c)]);
        }
    }
    let top = zs.len() - 1;
    triangles.push([v(0, 0), v(0, 2), v(0, 1)]);
    triangles.push([v(0, 0), v(0, 3), v(0, 2)]);
    triangles.push([v(top, 0), v(top, 1), v(top, 2)]);
    triangles.push([v(top, 0), v(top, 2), v(top, 3)]);
    Mesh {
        vertices,
        triangles,
    }
}

#[test]
fn cube_has_one_layer_per_grid_step_and_every_z_on_the_grid() {
    let s = settings(&[]);
    let out = sliced(&cube20(), &s);
    let w = walk(&out.gcode);
    // layers whose mid-height cut is inside the 20 mm cube: z_k = 0.2 + 0.2·k ≤ 20
    assert_eq!(w.zs.len(), 100, "layer count");
    assert_eq!(out.report.layers, 100);
    for (k, z) in w.zs.iter().enumerate() {
        let grid = 0.2 * (k + 1) as f64;
        assert!(
            (z - grid).abs() < 1e-9,
            "layer {k}: ;Z:{z} is not on the grid ({grid})"
        );
    }
}

#[test]
fn cube_external_perimeter_lies_within_a_line_width_of_the_side_and_covers_it() {
    let s = settings(&[]);
    let width = s.extrusion_width;
    let w = walk(&sliced(&cube20(), &s).gcode);
    let outer: Vec<&Extrusion> = w
        .extrusions
        .iter()
        .filter(|x| x.role == "External perimeter")
        .collect();
    assert!(!outer.is_empty());
    // every external-perimeter point is inside the 20 mm square, at most a line width from its side
    for x in &outer {
        for p in [x.from, x.to] {
            let inset = 10.0 - p[0].abs().max(p[1].abs());
            assert!(
                (0.0..=width).contains(&inset),
                "external perimeter point {p:?} at z {} is {inset} mm inside the side",
                x.layer_z
            );
        }
    }
    // every sample of the side surface (each layer, every 0.5 mm round the square) has an
    // external-perimeter line within one line width on its layer
    for &z in &w.zs {
        let layer: Vec<&&Extrusion> = outer.iter().filter(|x| x.layer_z == z).collect();
        for i in 0..160 {
            let t = -10.0 + 0.5 * (i % 40) as f64;
            let p = match i / 40 {
                0 => [t, -10.0],
                1 => [10.0, t],
                2 => [-t, 10.0],
                _ => [-10.0, -t],
            };
            let d = layer
                .iter()
                .map(|x| seg_dist(p, x.from, x.to))
                .fold(f64::INFINITY, f64::min);
            assert!(
                d <= width,
                "side point {p:?} at z {z}: nearest outer wall {d} mm"
            );
        }
    }
}

#[test]
fn cube_prints_every_perimeter_on_every_layer() {
    // 2 perimeters: each layer's perimeter lines are two closed squares of sides
    // 20 − w and 20 − w − 2s (s = w − h(1 − π/4)), so their lengths add up to 4·(40 − 2w − 2s)
    let s = settings(&[]);
    let (w_, h) = (s.extrusion_width, s.layer_height);
    let sp = w_ - h * (1.0 - std::f64::consts::FRAC_PI_4);
    let expected = 4.0 * (20.0 - w_) + 4.0 * (20.0 - w_ - 2.0 * sp);
    let w = walk(&sliced(&cube20(), &s).gcode);
    for &z in &w.zs {
        let len: f64 = w
            .extrusions
            .iter()
            .filter(|x| x.layer_z == z && x.role.ends_with("erimeter"))
            .map(|x| ((x.to[0] - x.from[0]).powi(2) + (x.to[1] - x.from[1]).powi(2)).sqrt())
            .sum();
        assert!(
            (len - expected).abs() < 0.01,
            "z {z}: perimeters {len} mm long, expected {expected}"
        );
    }
}

#[test]
fn solid_cube_extrudes_its_volume_within_5_percent() {
    let s = settings(&["fill_density=100", "skirts=0"]);
    let out = sliced(&cube20(), &s);
    let w = walk(&out.gcode);
    let volume = w.net_e * filament_area(1.75);
    eprintln!("solid cube: {volume:.1} mm³ extruded for 8000 mm³");
    assert!(
        (volume - 8000.0).abs() <= 0.05 * 8000.0,
        "extruded {volume} mm³ for the 8000 mm³ cube"
    );
    // the report's own figure agrees with the file
    assert!((out.report.volume_mm3 - volume).abs() < 0.01 * volume);
}

#[test]
fn absolute_e_gives_the_same_filament_as_relative_e() {
    let rel = walk(&sliced(&cube20(), &settings(&["skirts=0"])).gcode);
    let abs = walk(
        &sliced(
            &cube20(),
            &settings(&["skirts=0", "use_relative_e_distances=false"]),
        )
        .gcode,
    );
    // each relative E word is rounded to 5 decimals (±5e-6 mm); the absolute file rounds once
    let bound = 5e-6 * rel.extrusions.len() as f64;
    assert!(
        (rel.net_e - abs.net_e).abs() <= bound,
        "{} vs {}",
        rel.net_e,
        abs.net_e
    );
}

#[test]
fn solid_cylinder_extrudes_its_volume_within_5_percent_and_walls_follow_its_side() {
    let (r, height, n) = (10.0, 10.0, 96u32);
    let mesh = warpslice::shapes::cylinder(r, height, n);
    let s = settings(&["fill_density=100", "skirts=0"]);
    let out = sliced(&mesh, &s);
    let w = walk(&out.gcode);
    // the n-gon's area × height
    let area = 0.5 * n as f64 * r * r * (2.0 * std::f64::consts::PI / n as f64).sin();
    let volume = w.net_e * filament_area(1.75);
    eprintln!(
        "solid cylinder: {volume:.1} mm³ extruded for {:.1} mm³",
        area * height
    );
    assert!(
        (volume - area * height).abs() <= 0.05 * area * height,
        "extruded {volume} mm³, the cylinder holds {}",
        area * height
    );
    assert_eq!(w.zs.len(), 50);
    // external perimeter within a line width inside the faceted side: the n-gon's inscribed
    // radius r·cos(π/n) and its corner radius r bound the side
    let inscribed = r * (std::f64::consts::PI / n as f64).cos();
    for x in w
        .extrusions
        .iter()
        .filter(|x| x.role == "External perimeter")
    {
        let rho = (x.to[0].powi(2) + x.to[1].powi(2)).sqrt();
        assert!(
            rho <= r && rho >= inscribed - s.extrusion_width,
            "external perimeter at radius {rho}"
        );
    }
}

#[test]
fn a_mesh_with_a_missing_triangle_is_repaired_and_reported() {
    // the cube subdivided as the pipeline does (edges ≤ 1 mm), one side triangle at mid-height
    // removed: the cuts through it leave open chains with a gap of at most 1 mm
    let opts = warpslice::mesh::SubdivideOptions {
        max_edge: 1.0,
        ..Default::default()
    };
    let (mut mesh, _) = warpslice::mesh::subdivide(&cube20(), &opts, &|p| p);
    let side = mesh
        .triangles
        .iter()
        .position(|t| {
            let p: Vec<DVec3> = t.iter().map(|&i| mesh.vertices[i as usize]).collect();
            let zs = p.iter().map(|p| p.z);
            p.iter().all(|p| p.x == 10.0)
                && zs.clone().fold(f64::INFINITY, f64::min) < 10.1
                && zs.fold(f64::NEG_INFINITY, f64::max) > 10.1
        })
        .unwrap();
    mesh.triangles.remove(side);
    let s = settings(&["fill_density=100", "skirts=0"]);
    let out = sliced(&mesh, &s);
    assert!(out.report.repaired_loops >= 1, "{:?}", out.report);
    assert_eq!(out.report.dropped_chains, 0, "{:?}", out.report);
    let w = walk(&out.gcode);
    assert_eq!(w.zs.len(), 100);
    assert_holds_the_cube(&w);
}

#[test]
fn a_vertex_row_exactly_on_every_cut_plane_slices_whole() {
    // cut planes at mid-layer: z_k − h/2 = 0.1 + 0.2·k; give the side walls a vertex row on
    // each of them (computed as the documented grid, first 0.2 mm, then 0.2 mm)
    let rows: Vec<f64> = (0..100).map(|k| 0.2 + 0.2 * k as f64 - 0.1).collect();
    let mesh = box_with_rows(20.0, &rows);
    let s = settings(&["fill_density=100", "skirts=0"]);
    let out = sliced(&mesh, &s);
    assert_eq!(out.report.dropped_chains, 0);
    assert_eq!(out.report.repaired_loops, 0);
    let w = walk(&out.gcode);
    assert_eq!(w.zs.len(), 100);
    for &z in &w.zs {
        assert!(
            w.extrusions
                .iter()
                .any(|x| x.layer_z == z && x.role == "External perimeter"),
            "no wall at z {z}"
        );
    }
    assert_holds_the_cube(&w);
}

#[test]
fn infill_alternates_between_plus_and_minus_45_degrees() {
    let w = walk(&sliced(&cube20(), &settings(&[])).gcode);
    for (k, &z) in w.zs.iter().enumerate() {
        for x in w
            .extrusions
            .iter()
            .filter(|x| x.layer_z == z && x.role.contains("infill"))
        {
            let (dx, dy) = (x.to[0] - x.from[0], x.to[1] - x.from[1]);
            // 45° lines have dx = dy, −45° lines dx = −dy (3-decimal rounding: 2e-3)
            let off = if k % 2 == 0 { dx - dy } else { dx + dy };
            assert!(off.abs() < 2e-3, "layer {k}: infill line ({dx}, {dy})");
        }
    }
}

#[test]
fn top_and_bottom_layers_are_solid_and_the_middle_sparse() {
    let s = settings(&[]); // 5 top, 4 bottom solid layers, 20 % infill
    let w = walk(&sliced(&cube20(), &s).gcode);
    for (k, &z) in w.zs.iter().enumerate() {
        let roles: std::collections::BTreeSet<&str> = w
            .extrusions
            .iter()
            .filter(|x| x.layer_z == z && x.role.contains("infill"))
            .map(|x| x.role.as_str())
            .collect();
        let expect: &[&str] = match k {
            0..=3 => &["Solid infill"],
            99 => &["Top solid infill"],
            95..=98 => &["Solid infill"],
            _ => &["Internal infill"],
        };
        assert_eq!(roles.into_iter().collect::<Vec<_>>(), expect, "layer {k}");
    }
}

#[test]
fn unknown_and_out_of_range_settings_are_named_errors() {
    use warpslice::error::Coded;
    let e = Settings::from_json(r#"{"fill_densty": 50}"#).unwrap_err();
    assert_eq!(e.code(), "planar.settings-json");
    assert!(e.to_string().contains("fill_densty"), "{e}");
    let e = Settings::default().set("fill_densty=50").unwrap_err();
    assert_eq!(e.code(), "planar.settings-json");
    let e = Settings::default().set("fill_density=150").unwrap_err();
    assert_eq!(e.code(), "planar.setting");
    assert!(e.to_string().contains("fill_density = 150"), "{e}");
    for (bad, allowed) in [
        ("layer_height=0", "a positive number"),
        ("skirt_distance=-1", "a number ≥ 0"),
    ] {
        let e = Settings::default().set(bad).unwrap_err();
        assert_eq!(e.code(), "planar.setting");
        assert!(e.to_string().contains(allowed), "{bad}: {e}");
    }
    Settings::default().set("skirt_distance=0").unwrap();
    let s = Settings::from_json(r#"{"fill_density": 100, "perimeters": 3}"#).unwrap();
    assert_eq!((s.fill_density, s.perimeters), (100.0, 3));
}

#[test]
fn the_default_places_the_footprint_centre_on_the_bed_centre() {
    // the cube spans x, y ∈ [−10, 10]; placed at (100, 100) its walls lie in [90, 110]
    let out = sliced(&cube20(), &Settings::default());
    assert_eq!(out.report.shift, [100.0, 100.0]);
    let w = walk(&out.gcode);
    for x in w.extrusions.iter().filter(|x| x.role != "Skirt") {
        for p in [x.from, x.to] {
            assert!(
                (90.0..=110.0).contains(&p[0]) && (90.0..=110.0).contains(&p[1]),
                "{} point {p:?} off the centred cube",
                x.role
            );
        }
    }
}

#[test]
fn simplified_contours_stay_within_the_resolution_of_every_section_point() {
    use warpslice::planar::region::{simplify_closed, RESOLUTION};
    // a circle of radius 10 sampled every 0.01 rad, with a notch, and a square with collinear
    // points every 0.1 mm
    let mut circle: Vec<[f64; 2]> = (0..628)
        .map(|i| {
            let a = i as f64 * 0.01;
            let r = if (100..110).contains(&i) { 9.0 } else { 10.0 };
            [r * a.cos(), r * a.sin()]
        })
        .collect();
    let square: Vec<[f64; 2]> = (0..800)
        .map(|i| {
            let t = (i % 200) as f64 * 0.1 - 10.0;
            match i / 200 {
                0 => [t, -10.0],
                1 => [10.0, t],
                2 => [-t, 10.0],
                _ => [-10.0, -t],
            }
        })
        .collect();
    assert_eq!(simplify_closed(&square, RESOLUTION).len(), 4);
    let simple = simplify_closed(&circle, RESOLUTION);
    assert!(
        simple.len() < circle.len() / 3,
        "{} points kept",
        simple.len()
    );
    for p in circle.drain(..) {
        let d = (0..simple.len())
            .map(|i| seg_dist(p, simple[i], simple[(i + 1) % simple.len()]))
            .fold(f64::INFINITY, f64::min);
        assert!(d <= RESOLUTION + 1e-12, "point {p:?} is {d} mm off");
    }
}

#[test]
fn describe_lists_every_setting_with_its_default_and_each_is_settable() {
    let d = warpslice::describe::describe().unwrap();
    let json = serde_json::to_value(&d).unwrap();
    let listed = json["slicer_settings"]
        .as_object()
        .expect("slicer_settings");
    assert_eq!(
        serde_json::to_value(Settings::default()).unwrap(),
        json["slicer_settings"]
    );
    for (key, value) in listed {
        let mut s = Settings::default();
        s.set(&format!("{key}={value}"))
            .unwrap_or_else(|e| panic!("--set {key}={value}: {e}"));
        assert_eq!(s, Settings::default(), "{key}");
    }
    assert!(listed.contains_key("fill_density") && listed.contains_key("perimeters"));
}

#[test]
fn the_settings_page_documents_every_key() {
    let page = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/builtin-slicer.md"),
    )
    .unwrap();
    let keys = serde_json::to_value(Settings::default()).unwrap();
    for key in keys.as_object().unwrap().keys() {
        assert!(
            page.contains(&format!("| `{key}` |")),
            "docs/builtin-slicer.md has no row for {key}"
        );
    }
}

/// The CLI's `run` with the built-in slicer, on files (native only).
#[cfg(not(target_arch = "wasm32"))]
mod cli {
    use std::path::{Path, PathBuf};

    fn dir(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("warpslice-planar-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn warpslice(args: &[&str]) -> (bool, String, String) {
        let out = super::cli_part::run(args);
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    }

    fn cube(d: &Path) -> String {
        let stl = d.join("cube.stl").display().to_string();
        let (ok, _, err) = warpslice(&["example", "cube", "-o", &stl]);
        assert!(ok, "{err}");
        stl
    }

    /// Extruding G1 lines of a file (an `E` word after a coordinate word).
    fn extrusions(path: &Path) -> usize {
        std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .filter(|l| l.starts_with("G1 ") && l.contains(" E") && l.contains(" X"))
            .count()
    }

    const CONIC: [&str; 6] = ["--warp", "conic", "--angle", "30", "--direction", "outward"];

    #[test]
    fn run_without_a_slicer_uses_the_builtin_and_unwarps_a_conic_cube_to_3_axis() {
        let d = dir("three-axis");
        let stl = cube(&d);
        let out = d.join("cube.gcode");
        let kept = d.join("kept.gcode");
        let mut args = vec!["run", stl.as_str()];
        args.extend(CONIC);
        let (o, k) = (out.display().to_string(), kept.display().to_string());
        args.extend(["-o", o.as_str(), "--keep-sliced", k.as_str()]);
        let (ok, stdout, err) = warpslice(&args);
        assert!(ok, "{stdout}\n{err}");
        assert!(stdout.contains("built-in slicer"), "{stdout}");
        assert!(extrusions(&out) > 1000, "the unwarped file prints");
        // the kept planar file is the one the unwarp read, its job beside it
        let sliced = d.join("cube.sliced.gcode");
        assert_eq!(
            std::fs::read(&kept).unwrap(),
            std::fs::read(&sliced).unwrap()
        );
        let job = std::fs::read_to_string(d.join("kept.gcode.job.json")).unwrap();
        let warped_job = std::fs::read_to_string(d.join("cube.warped.job.json")).unwrap();
        assert_eq!(job, warped_job);
        // the planar file's layers are the warp's: ;Z: on the 0.2 mm grid
        for z in std::fs::read_to_string(&kept)
            .unwrap()
            .lines()
            .filter_map(|l| l.strip_prefix(";Z:"))
        {
            let z: f64 = z.parse().unwrap();
            let k = (z / 0.2).round();
            assert!(
                k >= 1.0 && (z - 0.2 * k).abs() < 1e-9,
                ";Z:{z} off the grid"
            );
        }
    }

    #[test]
    fn run_builtin_writes_machine_gcode_for_a_5_axis_preset() {
        let d = dir("machine");
        let stl = cube(&d);
        let out = d.join("cube-pax.gcode");
        let o = out.display().to_string();
        let mut args = vec!["run", stl.as_str(), "--slicer", "builtin"];
        args.extend(CONIC);
        // the path to machine G-code is tested here; the default E3D head meets the 30° cone on
        // the PAX head (the collision check, on by default, is tested in collision_check.rs)
        args.extend([
            "--machine",
            "pax-5axis",
            "--allow-collisions",
            "-o",
            o.as_str(),
        ]);
        let (ok, stdout, err) = warpslice(&args);
        assert!(ok, "{stdout}\n{err}");
        let text = std::fs::read_to_string(&out).unwrap();
        // a 5-axis head's file names its rotary axes on the tilted layers
        assert!(
            text.lines()
                .any(|l| l.starts_with("G1 ") && l.contains(" A")),
            "no A axis move in the machine file"
        );
        assert!(extrusions(&out) > 1000);
    }

    #[test]
    fn run_builtin_refuses_unknown_settings_and_other_layer_heights_by_name() {
        let d = dir("refuse");
        let stl = cube(&d);
        let o = d.join("x.gcode").display().to_string();
        let run = |extra: &[&str]| {
            let mut args = vec!["run", stl.as_str()];
            args.extend(CONIC);
            args.extend(extra);
            args.extend(["-o", o.as_str()]);
            warpslice(&args)
        };
        let (ok, _, err) = run(&["--set", "fill_densty=50"]);
        assert!(!ok && err.contains("fill_densty"), "{err}");
        let (ok, _, err) = run(&["--set", "layer_height=0.3"]);
        assert!(!ok && err.contains("--layer-height"), "{err}");
        let file = d.join("s.json");
        std::fs::write(&file, r#"{"perimeters": 3, "brim": 5}"#).unwrap();
        let f = file.display().to_string();
        let (ok, _, err) = run(&["--slicer-settings", &f]);
        assert!(
            !ok && err.contains("s.json") && err.contains("brim"),
            "{err}"
        );
        let (ok, _, err) = run(&["--slicer", "prusaslicer", "--set", "perimeters=3"]);
        assert!(!ok && err.contains("built-in"), "{err}");
    }
}
