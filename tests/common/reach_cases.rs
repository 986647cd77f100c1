//! The reach cases of issue 10 §5 (tests/machine_reach.rs; the page's fixtures,
//! examples/finding_cases.rs): a part wider than the B head's bed, and a triple-Z pose outside
//! the tilted volume, each written without the machine's travel (the file `warpslice check`
//! then reads for the real machine). Needs `crate::synthetic` (tests/common/synthetic.rs) and
//! `crate::fk` (tests/common/fk.rs) in the including crate.
#![allow(dead_code)]

use glam::DVec3;
use warpslice::emit::Emitter;
use warpslice::job::Job;
use warpslice::machine::{preset, FeedMode, MachineEmitter, MachineSpec};
use warpslice::pipeline::{unwarp, warp_model, AnchorMode, UnwarpSettings, WarpOptions};
use warpslice::toolpath::{Feature, ToolPoint};
use warpslice::unwarp::UnwarpOptions;
use warpslice::warp::{WarpParams, WarpSpec};

use crate::fk::Limits;

/// A box job: the generated 20 mm cube scaled by `sx` in x, belt-warped by `belt` degrees
/// toward `toward` (0.5° toward +x: the B head tilts 0.5°).
pub fn box_job(sx: f64, belt: f64, toward: [f64; 2]) -> Job {
    let mut mesh = warpslice::shapes::example("cube").unwrap();
    for v in &mut mesh.vertices {
        v.x *= sx;
    }
    let stl = warpslice::mesh::write_stl(&mesh, "t");
    let opts = WarpOptions {
        anchor: AnchorMode::Off,
        ..WarpOptions::new(WarpParams {
            spec: WarpSpec::Belt {
                angle: belt,
                toward,
            },
            base: None,
        })
    };
    warp_model(&stl, &opts).unwrap().job
}

/// Unwarp settings for a machine, the other options at their defaults.
pub fn settings(spec: MachineSpec) -> UnwarpSettings {
    UnwarpSettings::with_machine(UnwarpOptions::default(), spec)
}

/// The spec without its `travel` (every linear axis unlimited).
pub fn unlimited(spec: &MachineSpec) -> MachineSpec {
    // (travel kept but 1 km wide: the header's M208 lines stay, so line numbers compare)
    let travel = spec.travel.as_ref().map(|t| {
        t.keys()
            .map(|k| (k.clone(), [-1e6, 1e6]))
            .collect::<std::collections::BTreeMap<_, _>>()
    });
    MachineSpec {
        travel,
        ..spec.clone()
    }
}

/// A box 240 mm wide (the B head's bed is 230 mm, seed 000 §4.2.3) sliced by the synthetic
/// slicer (centred on x = 100: its skirt and left wall at x < 0): the job, the slicer's G-code
/// and fullcontrol-prusa-b's machine G-code written without `travel`.
pub fn wide_part_case() -> (Job, String, String) {
    let spec = preset("fullcontrol-prusa-b").unwrap();
    let job = box_job(12.0, 0.5, [1.0, 0.0]);
    let input = crate::synthetic::gcode(&job, true, 4.0);
    let free = unwarp(input.as_bytes(), &job, &settings(unlimited(&spec))).unwrap();
    (job, input, String::from_utf8(free.gcode).unwrap())
}

/// A triple-Z pose (tip p, tool axis n tilted 30°) near the bed's right edge that the tests'
/// kinematics put outside the travel only (tilt and rails within limits).
pub fn three_z_pose(spec: &MachineSpec) -> (DVec3, DVec3) {
    let limits = Limits::from_spec(spec).unwrap();
    let free = Limits::from_spec(&unlimited(spec)).unwrap();
    for x in [296.0, 290.0, 280.0, 270.0] {
        for k in 0..24 {
            let az = (k as f64 * 15.0).to_radians();
            let t = 30f64.to_radians();
            let n = DVec3::new(t.sin() * az.cos(), t.sin() * az.sin(), t.cos());
            let p = DVec3::new(x, 146.0, 2.0);
            if free.out_of_reach(p, n).is_none() && limits.out_of_reach(p, n).is_some() {
                return (p, n);
            }
        }
    }
    panic!("no tilted pose beyond X/Y travel");
}

/// The machine emitter of `spec` writing a header, then the points (p.x, p.y, 20) vertical,
/// p vertical, p tilted to n (input lines 40, 41, 42): its result at the first refused point
/// (or the last) and the text written.
pub fn three_z_run(
    spec: &MachineSpec,
    p: DVec3,
    n: DVec3,
) -> (Result<(), warpslice::emit::EmitError>, String) {
    let mut em = MachineEmitter::new(spec, None, FeedMode::Xyz).unwrap();
    let mut out = Vec::new();
    em.lines_written(0);
    em.header(&mut out);
    let start = DVec3::new(p.x, p.y, 20.0);
    em.begin_region(&mut out, start, DVec3::Z).unwrap();
    let mut r = Ok(());
    for (i, (q, m)) in [(start, DVec3::Z), (p, DVec3::Z), (p, n)]
        .into_iter()
        .enumerate()
    {
        em.lines_written(out.iter().filter(|&&b| b == b'\n').count() as u64);
        let tp = ToolPoint {
            p: q,
            n: m,
            e: 0.0,
            f: 3000.0,
            layer: 1,
            feature: Feature::Unknown,
            travel: true,
            line: 40 + i as u64,
        };
        r = em.point(&mut out, &tp, true);
        if r.is_err() {
            break;
        }
    }
    (r, String::from_utf8(out).unwrap())
}

/// The triple-Z case's machine G-code for ratrig-vcore3-3z, written without `travel`.
pub fn three_z_case() -> String {
    let spec = preset("ratrig-vcore3-3z").unwrap();
    let (p, n) = three_z_pose(&spec);
    let (r, text) = three_z_run(&unlimited(&spec), p, n);
    r.unwrap();
    text
}
