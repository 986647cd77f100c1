//! The built-in slicer run one step at a time (what the web worker does, for progress per
//! layer and cancel between layers): the counts are the layer grid's, worked out by hand for a
//! 20 mm cube, and the file does not depend on where the stepping paused. The settings a page
//! sends start from the job's layer height and refuse unknown keys, as the CLI's do.

use warpslice::pipeline::{builtin_settings, start_builtin, warp_model, WarpOptions};
use warpslice::planar::{slice, Settings, Slicing};

/// A 20 mm cube at 0.2 mm layers: 20 / 0.2 = 100 layers (cut at 0.1, 0.3, …, 19.9 mm).
const CUBE_LAYERS: usize = 100;

fn cube() -> warpslice::mesh::Mesh {
    warpslice::shapes::cube(20.0)
}

#[test]
fn stepping_a_20mm_cube_takes_one_cut_and_one_written_step_per_layer() {
    let mut s = Slicing::new(&cube(), &Settings::default(), "test").unwrap();
    let p0 = s.progress();
    assert_eq!(
        (p0.done, p0.total, p0.layers),
        (0, 2 * CUBE_LAYERS, CUBE_LAYERS)
    );
    let mut done = 0;
    loop {
        let p = s.step().unwrap();
        assert_eq!(p.done, done + 1, "every step does one unit of work");
        assert_eq!(p.total, 2 * CUBE_LAYERS);
        done = p.done;
        if p.is_done() {
            break;
        }
    }
    assert_eq!(done, 2 * CUBE_LAYERS);
    // a step after the end does nothing
    assert_eq!(s.step().unwrap().done, 2 * CUBE_LAYERS);
    let out = s.finish().unwrap();
    assert_eq!(out.report.layers, CUBE_LAYERS);
    let changes = out.gcode.lines().filter(|l| *l == ";LAYER_CHANGE").count();
    assert_eq!(
        changes, CUBE_LAYERS,
        "one ;LAYER_CHANGE per layer in the file"
    );
}

#[test]
fn a_slice_paused_anywhere_and_finished_writes_the_one_shot_file() {
    let whole = slice(&cube(), &Settings::default(), "test").unwrap();
    // paused in the cuts, at the turn from cutting to writing, and in the writing
    for pause in [1, 37, CUBE_LAYERS, CUBE_LAYERS + 1, 2 * CUBE_LAYERS - 1] {
        let mut s = Slicing::new(&cube(), &Settings::default(), "test").unwrap();
        for _ in 0..pause {
            s.step().unwrap();
        }
        assert_eq!(s.progress().done, pause);
        let out = s.finish().unwrap();
        assert!(
            out.gcode == whole.gcode,
            "paused after {pause} steps: the file differs"
        );
        assert_eq!(out.report, whole.report, "paused after {pause} steps");
    }
}

#[test]
fn a_mesh_thinner_than_one_layer_is_refused_at_once() {
    // the cube's two bottom triangles: a flat square at z = 0, below the first cut at 0.1 mm
    let mut flat = cube();
    flat.triangles
        .retain(|t| t.iter().all(|&i| flat.vertices[i as usize].z == 0.0));
    assert_eq!(flat.triangles.len(), 2);
    let e = Slicing::new(&flat, &Settings::default(), "test")
        .err()
        .unwrap();
    assert_eq!(warpslice::error::Coded::code(&e), "planar.empty");
}

#[test]
fn a_surface_without_volume_is_refused_after_its_last_cut() {
    // one vertical triangle 5 mm high: 25 layers whose cuts are open chains, nothing closed
    let wall = warpslice::mesh::Mesh {
        vertices: vec![
            glam::DVec3::new(0.0, 0.0, 0.0),
            glam::DVec3::new(10.0, 0.0, 0.0),
            glam::DVec3::new(5.0, 0.0, 5.0),
        ],
        triangles: vec![[0, 1, 2]],
    };
    let mut s = Slicing::new(&wall, &Settings::default(), "test").unwrap();
    assert_eq!(s.progress().layers, 25);
    for k in 1..25 {
        assert_eq!(s.step().unwrap().done, k, "cut {k} of 25 is not the last");
    }
    let e = s.step().unwrap_err();
    assert_eq!(warpslice::error::Coded::code(&e), "planar.empty");
}

fn job_at(layer_height: f64) -> warpslice::pipeline::WarpOutput {
    let stl = warpslice::mesh::write_stl(&cube(), "cube");
    let mut o =
        WarpOptions::from_json(r#"{"warp": {"spec": {"kind": "conic", "angle": 15}}}"#).unwrap();
    o.layer_height = layer_height;
    warp_model(&stl, &o).unwrap()
}

#[test]
fn page_settings_start_from_the_jobs_layer_height_and_name_unknown_keys() {
    let w = job_at(0.3);
    let s = builtin_settings(&w.job, "").unwrap();
    assert_eq!((s.layer_height, s.first_layer_height), (0.3, 0.3));
    assert_eq!(s.fill_density, Settings::default().fill_density);
    let s = builtin_settings(&w.job, r#"{"fill_density": 35, "perimeters": 3}"#).unwrap();
    assert_eq!(
        (s.fill_density, s.perimeters, s.layer_height),
        (35.0, 3, 0.3)
    );
    let e = builtin_settings(&w.job, r#"{"fill_densty": 35}"#).unwrap_err();
    assert_eq!(warpslice::error::Coded::code(&e), "planar.settings-json");
    assert!(e.to_string().contains("fill_densty"), "{e}");
    // a layer height other than the warp's is refused when the slice starts
    let s = builtin_settings(&w.job, r#"{"layer_height": 0.2}"#).unwrap();
    let e = start_builtin(&w.stl, &w.job, &s).err().unwrap();
    assert_eq!(warpslice::error::Coded::code(&e), "planar.layer-height");
}
