//! The streaming unwarp's state (`Unwarper`): the output does not depend on how the bytes are
//! cut into chunks, drained output concatenates to the one-shot result, calls out of order
//! are named errors with a stable code, and an emitter's refusal before the first line names
//! no line. Synthetic slicer G-code; runs natively and under wasm.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

#[path = "common/synthetic.rs"]
mod synthetic;

use warpslice::emit::{Cartesian, EmitError, Emitter};
use warpslice::error::Coded;
use warpslice::job::Job;
use warpslice::pipeline::{unwarp, warp_model, UnwarpSettings, WarpOptions};
use warpslice::toolpath::ToolPoint;
use warpslice::unwarp::{UnwarpError, UnwarpOptions, Unwarper};
use warpslice::warp::{Direction, WarpParams, WarpSpec};

fn job_and_gcode() -> (Job, Vec<u8>) {
    let stl = warpslice::mesh::write_stl(&warpslice::shapes::example("cube").unwrap(), "t");
    let p = WarpParams {
        spec: WarpSpec::Curved {
            strength: 0.3,
            direction: Direction::Outward,
            offset: 0.0,
            width: 0.0,
        },
        base: None,
    };
    let w = warp_model(&stl, &WarpOptions::new(p)).unwrap();
    let g = synthetic::gcode(&w.job, true, 2.0).into_bytes();
    (w.job, g)
}

/// Unwarp `g` fed in chunks of `chunk` bytes, draining the output after every push.
fn chunked(job: &Job, g: &[u8], chunk: usize) -> (Vec<u8>, warpslice::unwarp::UnwarpReport) {
    let mut u = Unwarper::new(job, &UnwarpOptions::default(), Box::new(Cartesian::new())).unwrap();
    for c in g.chunks(chunk) {
        u.scan(c).unwrap();
    }
    u.end_scan().unwrap();
    let mut out = Vec::new();
    for c in g.chunks(chunk) {
        u.push(c).unwrap();
        out.extend(u.take_output());
    }
    let report = u.finish().unwrap();
    out.extend(u.take_output());
    (out, report)
}

#[test]
fn chunk_size_does_not_change_the_output() {
    let (job, g) = job_and_gcode();
    let whole = unwarp(&g, &job, &UnwarpSettings::default()).unwrap();
    assert!(whole.report.segments_out > 100);
    for chunk in [1, 7, 4096, g.len()] {
        let (out, report) = chunked(&job, &g, chunk);
        assert!(
            out == whole.gcode,
            "chunks of {chunk} bytes change the output"
        );
        assert_eq!(report, whole.report, "chunks of {chunk}");
    }
}

#[test]
fn calls_out_of_order_are_named_errors() {
    let (job, g) = job_and_gcode();
    let new = || Unwarper::new(&job, &UnwarpOptions::default(), Box::new(Cartesian::new()));
    let order = |e: UnwarpError| {
        assert!(matches!(e, UnwarpError::Order { .. }), "{e:?}");
        assert_eq!(e.code(), "unwarp.order");
        e.to_string()
    };
    // pass 2 before pass 1 ended
    let mut u = new().unwrap();
    u.scan(&g).unwrap();
    let msg = order(u.push(&g).unwrap_err());
    assert!(msg.contains("end_scan"), "{msg}");
    order(u.finish().unwrap_err());
    // pass 1 after it ended; end_scan twice
    let mut u = new().unwrap();
    u.scan(&g).unwrap();
    u.end_scan().unwrap();
    order(u.scan(&g).unwrap_err());
    order(u.end_scan().unwrap_err());
    // finish twice
    u.push(&g).unwrap();
    u.finish().unwrap();
    order(u.finish().unwrap_err());
    // nothing is drained before pass 2
    let mut u = new().unwrap();
    assert!(u.take_output().is_empty() && u.take_toolpath().is_empty());
}

#[test]
fn bad_options_are_refused_before_any_byte() {
    let (job, _) = job_and_gcode();
    for (opts, name) in [
        (
            UnwarpOptions {
                tolerance: 0.0,
                ..Default::default()
            },
            "tolerance",
        ),
        (
            UnwarpOptions {
                max_segment: f64::NAN,
                ..Default::default()
            },
            "max-segment",
        ),
        (
            UnwarpOptions {
                z_offset: f64::INFINITY,
                ..Default::default()
            },
            "z-offset",
        ),
    ] {
        let e = Unwarper::new(&job, &opts, Box::new(Cartesian::new()))
            .err()
            .unwrap();
        assert_eq!(e.code(), "unwarp.option");
        assert!(e.to_string().contains(name), "{e}");
    }
}

/// An emitter that refuses every job, as a machine refuses a job it would print wrong.
#[derive(Debug)]
struct Refuses;

#[derive(Debug)]
struct NotThisJob;

impl std::fmt::Display for NotThisJob {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("this emitter refuses the job")
    }
}
impl std::error::Error for NotThisJob {}
impl Coded for NotThisJob {
    fn code(&self) -> &'static str {
        "test.refused"
    }
}

impl Emitter for Refuses {
    fn check_job(&mut self, _: &Job, _: glam::DVec3) -> Result<(), EmitError> {
        Err(EmitError::new(NotThisJob))
    }
    fn point(&mut self, _: &mut Vec<u8>, _: &ToolPoint, _: bool) -> Result<(), EmitError> {
        Ok(())
    }
    fn reset_e(&mut self, _: f64) {}
    fn current_e(&self) -> f64 {
        0.0
    }
}

#[test]
fn an_emitter_refusing_the_job_stops_before_the_first_line() {
    let (job, g) = job_and_gcode();
    let mut u = Unwarper::new(&job, &UnwarpOptions::default(), Box::new(Refuses)).unwrap();
    u.scan(&g).unwrap();
    let e = u.end_scan().unwrap_err();
    assert!(
        matches!(&e, UnwarpError::Emit { line: None, error } if error.downcast_ref::<NotThisJob>().is_some()),
        "{e:?}"
    );
    assert_eq!(e.code(), "test.refused");
    assert_eq!(e.to_string(), "this emitter refuses the job");
    assert!(u.take_output().is_empty(), "nothing written");
}

/// `toolpath_every` (the page's preview decimation, done in the core): the points drained
/// chunk by chunk are those of the whole toolpath with point i kept when i is a multiple of
/// `every` or starts a layer (its layer is not the previous point's), the output bytes are the
/// same, and every layer of the whole toolpath still appears, starting at its first point.
#[test]
fn a_thinned_toolpath_keeps_every_nth_point_and_each_layers_first() {
    let (job, g) = job_and_gcode();
    let all = unwarp(
        &g,
        &job,
        &UnwarpOptions {
            collect_toolpath: true,
            ..UnwarpOptions::default()
        }
        .into(),
    )
    .unwrap();
    let full = all.toolpath;
    assert!(full.len() > 500, "{} points", full.len());
    for (every, chunk) in [(1, 4096), (3, 1000), (16, 7777), (1000, 4096)] {
        let opts = UnwarpOptions {
            collect_toolpath: true,
            toolpath_every: every,
            ..UnwarpOptions::default()
        };
        let mut u = Unwarper::new(&job, &opts, Box::new(Cartesian::new())).unwrap();
        for c in g.chunks(chunk) {
            u.scan(c).unwrap();
        }
        u.end_scan().unwrap();
        let (mut out, mut kept) = (Vec::new(), Vec::new());
        for c in g.chunks(chunk) {
            u.push(c).unwrap();
            out.extend(u.take_output());
            kept.extend(u.take_toolpath());
        }
        u.finish().unwrap();
        out.extend(u.take_output());
        kept.extend(u.take_toolpath());
        assert!(out == all.gcode, "every {every}: the output changed");
        let want: Vec<&ToolPoint> = full
            .iter()
            .enumerate()
            .filter(|&(i, p)| i % every as usize == 0 || (i > 0 && p.layer != full[i - 1].layer))
            .map(|(_, p)| p)
            .collect();
        assert_eq!(kept.len(), want.len(), "every {every}: points kept");
        for (k, (a, b)) in kept.iter().zip(&want).enumerate() {
            assert_eq!(a, *b, "every {every}: the {k}th point kept");
        }
        let layers = |v: &mut dyn Iterator<Item = u32>| {
            let mut l: Vec<u32> = v.collect();
            l.dedup();
            l
        };
        assert_eq!(
            layers(&mut kept.iter().map(|p| p.layer)),
            layers(&mut full.iter().map(|p| p.layer)),
            "every {every}: the layer sequence"
        );
    }
}
