//! The law tests every machine must pass (shared by the native tests and the wasm tests, so not
//! `cfg(test)`).
//!
//! 1. **Round trip** ([`check_round_trip`]): on a grid of tip positions (corners, edges and
//!    centre of the machine's [`Workspace`]) × tool axes (vertical, 1e-6°, 0.25°, 0.5°, 1°, 10°,
//!    45°, 90°, 135°, 180° and exactly the workspace's largest tilt, at azimuths including
//!    ±180° ± 1e-4° and ±90°), `forward(inverse(p, n, None)) = (p, realised_axis(p, n))` within
//!    [`POSITION_TOLERANCE`] and [`ANGLE_TOLERANCE`] — `= (p, n)` itself, whatever the branch, for a
//!    machine that [`Machine::realises_requests`]; a tilt 3° beyond the workspace's largest
//!    (when below 180°) must be refused. A machine with a [`Machine::fixed_tool_axis`] must
//!    give exactly that axis, from `forward` and from `realised_axis`, at every point solved
//!    (here and in law 2).
//! 2. **Paths** ([`check_paths`]): sweeps of the azimuth over two full turns (crossing ±180°)
//!    and a meridian through the vertical, each point solved with the previous axes: the round
//!    trip still holds (orientation within `branch_freedom`), and every rotary axis moves by at
//!    most [`MAX_ROTARY_STEP_DEG`] per step (a single-revolution axis may instead wrap by
//!    exactly 360°), except where the realised axis itself jumps (a fixed-tilt nozzle passing
//!    over the vertical) and next to a hold zone (`branch_freedom > 0`: on leaving it a held
//!    axis may have to catch up; the interpolation splits such moves).
//! 3. **Fixed pose** ([`check_fixed_pose`]), for machines that are
//!    [`Machine::linear_at_fixed_pose`]: on straight tip segments with one tool axis whose ends
//!    solve to the same rotary axes (grid pairs, and segments along X, along Z and radial from
//!    the origin, where polar and mandrel machines keep their rotary axes), the linear
//!    interpolation of the axes lands on the exact pose at 100 points within
//!    [`POSITION_TOLERANCE`] and [`ANGLE_TOLERANCE`].
//! 4. **Nearest axis** ([`check_nearest`]): the realised tool axis is the machine's closest
//!    reachable one. At each grid position the reachable axes are sampled as
//!    `forward(inverse(p, m))` for m on a tilt × azimuth grid ([`NEAREST_GRID_DEG`]); for every
//!    sample axis n, angle(realised_axis(p, n), n) ≤ min over the samples of angle(s, n) +
//!    [`NEAREST_SLACK_DEG`]. Laws 1–3 compare `forward` with `realised_axis`, so a mistake both
//!    share (a mirrored azimuth in the one function that builds the axis) passes them; this law
//!    catches it because the samples cover every azimuth either way.
//! 5. **Head frame** ([`check_head_frame`]), for machines that give a
//!    [`Machine::head_frame`] (the collision check places the heater block with it): at every
//!    grid position and axis of law 1 the frame is orthonormal and right-handed within
//!    [`FRAME_TOLERANCE`], and its z column is the forward tool axis within
//!    [`ANGLE_TOLERANCE`]; along an azimuth sweep its x column turns by at most
//!    [`MAX_ROTARY_STEP_DEG`] per 0.5° step wherever the realised tool axis itself moves less
//!    than [`AXIS_JUMP_DEG`] (it jumps where a single-revolution axis reaches its limit): no
//!    flip of the block's side.
//! 6. **Closed-form bounds** ([`check_interpolation_bound`]): wherever a machine gives a
//!    [`Machine::interpolation_bound`] for a piece (from every grid position and sample axis,
//!    short moves turning the tool by 0.3°–8°), the firmware's path sampled densely
//!    ([`BOUND_SAMPLES`] points) stays within it, and `inverse` succeeds at every sample; for a
//!    machine that [`Machine::realises_bounded_requests`], `forward(inverse(p(s), n(s)))` is the request
//!    `(p(s), n(s))` itself there, within [`POSITION_TOLERANCE`] and [`ANGLE_TOLERANCE`].
//! 7. **Start drift** ([`check_start_drift`]): wherever a machine gives a
//!    [`Machine::start_drift_deg`] at a grid pose, requests turned and moved to the edge of
//!    its domain realise axes within it, and the tessellation's held-axis probe, wherever the
//!    bound lets the tessellation skip it, finds no jump and raises no error.

// `!(x <= tol)` on purpose: a NaN error must fail the law.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use glam::DVec3;

use super::{Machine, Workspace};
use crate::num;

/// |p − forward(inverse(p)).p| bound, mm.
pub const POSITION_TOLERANCE: f64 = 1e-9;
/// Angle between the realised and the forward tool axis, radians.
pub const ANGLE_TOLERANCE: f64 = 1e-9;
/// Largest change of a rotary axis between two path points 0.5° (azimuth) or 0.05° (tilt)
/// apart, degrees. An azimuth-like axis turns by step / (distance to its pole) radians; with the
/// pole held within 0.5° that is at most 0.05°/0.5° = 0.1 rad = 5.73° on the meridian.
pub const MAX_ROTARY_STEP_DEG: f64 = 6.0;

/// A tilt this far beyond the workspace's largest must be refused, degrees.
pub const BEYOND_MARGIN_DEG: f64 = 3.0;

/// Step of the tilt × azimuth grid whose `forward(inverse(·))` axes sample what a machine can
/// reach (law 4), degrees. A sample is then at most ~√2·1.5° from the nearest reachable axis,
/// which only loosens the law.
pub const NEAREST_GRID_DEG: f64 = 3.0;
/// How much farther than the best sample the realised axis may be from the wanted one (law 4),
/// degrees: the A/B table holds its pole within 0.5° (`abtable`), plus rounding.
pub const NEAREST_SLACK_DEG: f64 = 0.6;

/// |RᵀR − I| and |det R − 1| bound for a head frame (law 5), unit-free.
pub const FRAME_TOLERANCE: f64 = 1e-9;

/// A step of law 5's sweep whose realised tool axis turns by more than this is a jump of the
/// pose itself (a single-revolution axis at its limit), where the frame may jump too, degrees.
pub const AXIS_JUMP_DEG: f64 = 1.0;

/// What a law check measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LawReport {
    /// Points checked.
    pub points: usize,
    /// Worst position error, mm.
    pub worst_position_mm: f64,
    /// Worst orientation error (beyond the allowed branch freedom), radians.
    pub worst_angle_rad: f64,
    /// Largest rotary step on the paths, degrees.
    pub worst_rotary_step_deg: f64,
}

/// The unit vector of tilt `t` and azimuth `a` (degrees).
pub fn axis(tilt_deg: f64, azimuth_deg: f64) -> DVec3 {
    let (t, a) = (num::rad(tilt_deg), num::rad(azimuth_deg));
    DVec3::new(
        num::sin(t) * num::cos(a),
        num::sin(t) * num::sin(a),
        num::cos(t),
    )
}

/// The sample positions of a workspace: 3 × 3 × 3 (min, middle, max per axis).
pub fn positions(ws: &Workspace) -> Vec<DVec3> {
    let mut v = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                let f = |lo: f64, hi: f64, s: usize| lo + (hi - lo) * s as f64 / 2.0;
                v.push(DVec3::new(
                    f(ws.min.x, ws.max.x, i),
                    f(ws.min.y, ws.max.y, j),
                    f(ws.min.z, ws.max.z, k),
                ));
            }
        }
    }
    v
}

/// The sample tool axes of a workspace (singular ones included).
pub fn axes(ws: &Workspace) -> Vec<DVec3> {
    let mut tilts: Vec<f64> = vec![0.0, 1e-6, 0.25, 0.5, 1.0, 10.0, 45.0, 90.0, 135.0, 180.0]
        .into_iter()
        .filter(|t| *t <= ws.max_tilt_deg)
        .collect();
    tilts.push(ws.max_tilt_deg);
    let azimuths = [
        0.0,
        30.0,
        45.0,
        90.0,
        135.0,
        180.0 - 1e-4,
        180.0,
        -180.0 + 1e-4,
        -90.0,
        -45.0,
        -120.0,
    ];
    let mut v = Vec::new();
    for &t in &tilts {
        if t == 0.0 || t == 180.0 {
            v.push(axis(t, 0.0));
            continue;
        }
        for &a in &azimuths {
            v.push(axis(t, a));
        }
    }
    v
}

fn check_one(
    m: &dyn Machine,
    p: DVec3,
    n: DVec3,
    previous: Option<&[f64]>,
    rep: &mut LawReport,
) -> Result<Vec<f64>, String> {
    let a = m
        .inverse(p, n, previous)
        .map_err(|e| format!("{}: inverse({p}, {n}) failed: {e}", m.name()))?;
    if a.len() != m.limits().len() {
        return Err(format!(
            "{}: inverse gave {} axes, limits has {}",
            m.name(),
            a.len(),
            m.limits().len()
        ));
    }
    let (q, nq) = m
        .forward(&a)
        .map_err(|e| format!("{}: forward({a:?}) failed: {e}", m.name()))?;
    if let Some(fixed) = m.fixed_tool_axis() {
        let realised = m.realised_axis(p, n);
        if nq != fixed || realised != fixed {
            return Err(format!(
                "{}: fixed_tool_axis {fixed} but forward(inverse({p}, {n}, {previous:?})) has axis {nq} and realised_axis {realised}",
                m.name()
            ));
        }
    }
    let dp = (q - p).length();
    // a machine that realises every request exactly is held to the request itself
    let exact = m.realises_requests();
    let want = if exact { n } else { m.realised_axis(p, n) };
    let freedom = if previous.is_some() && !exact {
        m.branch_freedom(p, n)
    } else {
        0.0
    };
    let da = (num::angle_between(nq, want) - freedom).max(0.0);
    rep.points += 1;
    rep.worst_position_mm = rep.worst_position_mm.max(dp);
    rep.worst_angle_rad = rep.worst_angle_rad.max(da);
    if !(dp <= POSITION_TOLERANCE)
        || !(da <= ANGLE_TOLERANCE)
        || !((nq.length() - 1.0).abs() <= super::UNIT_EPSILON)
    {
        return Err(format!(
            "{}: forward(inverse({p}, {n}, {previous:?})) = ({q}, {nq}) via axes {a:?}: position error {dp:e} mm, axis error {da:e} rad against realised {want}",
            m.name()
        ));
    }
    Ok(a)
}

/// Law 1: round trip on the grid, and refusal beyond the largest tilt.
pub fn check_round_trip(m: &dyn Machine) -> Result<LawReport, String> {
    let ws = m.workspace();
    let mut rep = LawReport::default();
    for p in positions(&ws) {
        for n in axes(&ws) {
            check_one(m, p, n, None, &mut rep)?;
        }
        if ws.max_tilt_deg < 180.0 - BEYOND_MARGIN_DEG {
            let n = axis(ws.max_tilt_deg + BEYOND_MARGIN_DEG, 60.0);
            if let Ok(a) = m.inverse(p, n, None) {
                return Err(format!(
                    "{}: tilt {}° beyond the workspace was accepted: {a:?}",
                    m.name(),
                    ws.max_tilt_deg + BEYOND_MARGIN_DEG
                ));
            }
        }
    }
    Ok(rep)
}

fn walk(
    m: &dyn Machine,
    p: DVec3,
    path: &[DVec3],
    step_deg: f64,
    rep: &mut LawReport,
) -> Result<(), String> {
    let limits = m.limits();
    let mut prev: Option<(DVec3, Vec<f64>)> = None;
    for &n in path {
        let a = check_one(m, p, n, prev.as_ref().map(|(_, a)| a.as_slice()), rep)?;
        if let Some((pn, pa)) = &prev {
            let jump = num::angle_between(m.realised_axis(p, *pn), m.realised_axis(p, n));
            let held = m.branch_freedom(p, *pn) > 0.0 || m.branch_freedom(p, n) > 0.0;
            if jump <= num::rad(10.0 * step_deg) && !held {
                for (k, l) in limits.iter().enumerate() {
                    if !l.rotary {
                        continue;
                    }
                    let mut d = (a[k] - pa[k]).abs();
                    if (l.max - l.min) <= 360.0 + super::ONE_TURN_SLACK_DEG && d > 180.0 {
                        d = (d - 360.0).abs();
                    }
                    rep.worst_rotary_step_deg = rep.worst_rotary_step_deg.max(d);
                    if !(d <= MAX_ROTARY_STEP_DEG) {
                        return Err(format!(
                            "{}: axis {} jumps by {d}° between {pn} ({pa:?}) and {n} ({a:?})",
                            m.name(),
                            l.name
                        ));
                    }
                }
            }
        }
        prev = Some((n, a));
    }
    Ok(())
}

/// Law 2: continuity along azimuth sweeps and a meridian through the vertical.
pub fn check_paths(m: &dyn Machine) -> Result<LawReport, String> {
    let ws = m.workspace();
    // Off-centre, so polar machines are away from their centre singularity.
    let p = ws.min + (ws.max - ws.min) * 0.7;
    let mut rep = LawReport::default();
    for t in [0.3, 20.0, ws.max_tilt_deg.min(60.0)] {
        if t > ws.max_tilt_deg {
            continue;
        }
        let path: Vec<DVec3> = (0..=1440)
            .map(|i| axis(t, -170.0 + 0.5 * i as f64))
            .collect();
        walk(m, p, &path, 0.5, &mut rep)?;
    }
    let top = ws.max_tilt_deg.min(20.0);
    let steps = (2.0 * top / 0.05).round() as i64;
    let path: Vec<DVec3> = (0..=steps)
        .map(|i| {
            let s = -top + 0.05 * i as f64;
            if s >= 0.0 {
                axis(s, 30.0)
            } else {
                axis(-s, 210.0)
            }
        })
        .collect();
    walk(m, p, &path, 0.05, &mut rep)?;
    Ok(rep)
}

/// Law 3 (see the module documentation). Returns the points checked (0 for a machine that
/// does not claim [`Machine::linear_at_fixed_pose`]).
pub fn check_fixed_pose(m: &dyn Machine) -> Result<LawReport, String> {
    let mut rep = LawReport::default();
    if !m.linear_at_fixed_pose() {
        return Ok(rep);
    }
    let ws = m.workspace();
    let grid = positions(&ws);
    let span = ws.max - ws.min;
    let rotary: Vec<bool> = m.limits().iter().map(|l| l.rotary).collect();
    let mut pairs: Vec<(DVec3, DVec3)> = Vec::new();
    for (i, &a) in grid.iter().enumerate() {
        for &b in &grid[i + 1..] {
            pairs.push((a, b));
        }
        pairs.push((a, a + DVec3::new(span.x * 0.3, 0.0, 0.0)));
        pairs.push((a, a + DVec3::new(0.0, 0.0, span.z * 0.3)));
        pairs.push((a, a * 0.6));
    }
    for n in axes(&ws) {
        for &(p0, p1) in &pairs {
            let Ok(a0) = m.inverse(p0, n, None) else {
                continue;
            };
            let Ok(a1) = m.inverse(p1, n, Some(&a0)) else {
                continue;
            };
            if rotary
                .iter()
                .zip(a0.iter().zip(&a1))
                .any(|(r, (x, y))| *r && x != y)
            {
                continue;
            }
            for k in 1..100 {
                let s = k as f64 / 100.0;
                let lerped: Vec<f64> = a0.iter().zip(&a1).map(|(x, y)| x + (y - x) * s).collect();
                let fw = m.forward(&lerped).map_err(|e| e.to_string())?;
                let exact_axes = m
                    .inverse(p0.lerp(p1, s), n, Some(&a0))
                    .map_err(|e| e.to_string())?;
                let exact = m.forward(&exact_axes).map_err(|e| e.to_string())?;
                let dp = (fw.0 - exact.0).length();
                let da = num::angle_between(fw.1, exact.1);
                rep.points += 1;
                rep.worst_position_mm = rep.worst_position_mm.max(dp);
                rep.worst_angle_rad = rep.worst_angle_rad.max(da);
                if !(dp <= POSITION_TOLERANCE && da <= ANGLE_TOLERANCE) {
                    return Err(format!(
                        "{}: linear_at_fixed_pose is false here: from {p0} to {p1} with n = {n}, the interpolated axes at s = {s} are {dp:.3e} mm / {da:.3e} rad off the exact pose",
                        m.name()
                    ));
                }
            }
        }
    }
    Ok(rep)
}

/// Law 4 (see the module documentation).
pub fn check_nearest(m: &dyn Machine) -> Result<LawReport, String> {
    let ws = m.workspace();
    let mut rep = LawReport::default();
    let steps_t = (ws.max_tilt_deg.min(180.0) / NEAREST_GRID_DEG).ceil() as usize;
    let steps_a = (360.0 / NEAREST_GRID_DEG).round() as usize;
    for p in positions(&ws) {
        let mut reach: Vec<DVec3> = Vec::new();
        for i in 0..=steps_t {
            let t = (i as f64 * NEAREST_GRID_DEG).min(ws.max_tilt_deg);
            for j in 0..steps_a {
                let a = -180.0 + j as f64 * NEAREST_GRID_DEG;
                if let Ok(x) = m.inverse(p, axis(t, a), None) {
                    if let Ok((_, s)) = m.forward(&x) {
                        reach.push(s);
                    }
                }
            }
        }
        if reach.is_empty() {
            continue;
        }
        for n in axes(&ws) {
            let r = m.realised_axis(p, n);
            let got = num::deg(num::angle_between(r, n));
            let (best, at) = reach
                .iter()
                .map(|s| (num::deg(num::angle_between(*s, n)), *s))
                .fold(
                    (f64::INFINITY, DVec3::ZERO),
                    |b, c| if c.0 < b.0 { c } else { b },
                );
            rep.points += 1;
            let excess = got - best;
            rep.worst_angle_rad = rep.worst_angle_rad.max(num::rad(excess.max(0.0)));
            if !(excess <= NEAREST_SLACK_DEG) {
                return Err(format!(
                    "{}: at {p} the realised axis {r} is {got:.3}° from the wanted {n}, but the machine reaches {at}, {best:.3}° from it",
                    m.name()
                ));
            }
        }
    }
    Ok(rep)
}

/// Law 5 (see the module documentation). Returns the frames checked (0 for a machine without
/// a head frame).
pub fn check_head_frame(m: &dyn Machine) -> Result<LawReport, String> {
    let ws = m.workspace();
    let mut rep = LawReport::default();
    let check = |a: &[f64], rep: &mut LawReport| -> Result<Option<glam::DMat3>, String> {
        // `pose` is `forward` and `head_frame` at once, to the bit
        let (p, n) = m.forward(a).map_err(|e| e.to_string())?;
        let frame = m.head_frame(a);
        let pose = m.pose(a).map_err(|e| e.to_string())?;
        if pose != (p, n, frame) {
            return Err(format!(
                "{}: pose {pose:?} at axes {a:?} differs from forward and head_frame ({p}, {n}, {frame:?})",
                m.name()
            ));
        }
        let Some(f) = frame else {
            return Ok(None);
        };
        let gram = f.transpose() * f;
        let off = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| (gram.col(i)[j] - f64::from(u8::from(i == j))).abs())
            .fold(0.0, f64::max)
            .max((f.determinant() - 1.0).abs());
        let da = num::angle_between(f.z_axis, n);
        rep.points += 1;
        rep.worst_position_mm = rep.worst_position_mm.max(off);
        rep.worst_angle_rad = rep.worst_angle_rad.max(da);
        if !(off <= FRAME_TOLERANCE) || !(da <= ANGLE_TOLERANCE) {
            return Err(format!(
                "{}: head frame {f:?} at axes {a:?} is not a right-handed orthonormal frame about the tool axis {n} (orthonormality error {off:e}, z column {da:e} rad off)",
                m.name()
            ));
        }
        Ok(Some(f))
    };
    for p in positions(&ws) {
        for n in axes(&ws) {
            if let Ok(a) = m.inverse(p, n, None) {
                check(&a, &mut rep)?;
            }
        }
    }
    // The azimuth sweep at a 30° tilt (or the largest): the block's side turns smoothly.
    let c = (ws.min + ws.max) / 2.0;
    let tilt = ws.max_tilt_deg.min(30.0);
    let mut previous: Option<(Vec<f64>, glam::DMat3)> = None;
    for k in 0..=1440 {
        let az = -360.0 + k as f64 * 0.5;
        let Ok(a) = m.inverse(
            c,
            axis(tilt, az),
            previous.as_ref().map(|(a, _)| a.as_slice()),
        ) else {
            previous = None;
            continue;
        };
        let Some(f) = check(&a, &mut rep)? else {
            return Ok(rep);
        };
        if let Some((_, f0)) = &previous {
            let turn = num::deg(num::angle_between(f0.x_axis, f.x_axis));
            let axis_jump = num::deg(num::angle_between(f0.z_axis, f.z_axis));
            if axis_jump > AXIS_JUMP_DEG {
                previous = Some((a, f));
                continue;
            }
            rep.worst_rotary_step_deg = rep.worst_rotary_step_deg.max(turn);
            if tilt > 1.0 && !(turn <= MAX_ROTARY_STEP_DEG) {
                return Err(format!(
                    "{}: the head frame's x axis turns {turn:.3}° between azimuths {:.1}° and {az:.1}° at tilt {tilt}° (axes {a:?})",
                    m.name(),
                    az - 0.5
                ));
            }
        }
        previous = Some((a, f));
    }
    Ok(rep)
}
/// Samples per piece of law 6 (not a power of two: none coincides with the interpolation
/// check's s = k/16 but s = ¼, ½, ¾).
pub const BOUND_SAMPLES: usize = 100;

/// Tip steps (mm) and tool-axis turns (degrees) of the pieces of law 6.
const BOUND_STEPS: [(f64, f64, f64, f64); 4] = [
    (0.4, -0.3, 0.05, 0.3),
    (1.5, 0.8, -0.2, 1.5),
    (-0.7, 2.0, 0.4, 4.0),
    (3.0, -1.0, 1.0, 8.0),
];

/// Law 6 (see the module documentation). `points` counts the pieces bounded; the worst
/// position and angle are the largest sampled error as a fraction of the bound (≤ 1).
pub fn check_interpolation_bound(m: &dyn Machine) -> Result<LawReport, String> {
    let ws = m.workspace();
    let limits = m.limits();
    let mut rep = LawReport::default();
    for p0 in positions(&ws) {
        for (j, n0) in axes(&ws).into_iter().enumerate() {
            let Ok(a0) = m.inverse(p0, n0, None) else {
                continue;
            };
            for (k, &(dx, dy, dz, turn)) in BOUND_STEPS.iter().enumerate() {
                // turn n0 about an axis perpendicular to it, in a direction that varies
                let side = [DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.3)][(j + k) % 3];
                let about = n0.cross(side);
                let about = if about.length() > 1e-6 {
                    about.normalize()
                } else {
                    n0.any_orthonormal_vector()
                };
                let n1 = super::angles::rotate(n0, about, num::rad(turn));
                let p1 = p0 + DVec3::new(dx, dy, dz);
                let Ok(a1) = m.inverse(p1, n1, Some(&a0)) else {
                    continue;
                };
                // a single-revolution axis crossing its seam is turned around, not interpolated
                let wraps = limits.iter().zip(a0.iter().zip(&a1)).any(|(l, (x, y))| {
                    l.rotary
                        && l.max - l.min <= 360.0 + super::ONE_TURN_SLACK_DEG
                        && (y - x).abs() > 180.0
                });
                if wraps {
                    continue;
                }
                let Some((bp, ba)) = m.interpolation_bound((&a0, p0, n0), (&a1, p1, n1)) else {
                    continue;
                };
                let (wp, wa) = sampled_error(m, (&a0, p0, n0), (&a1, p1, n1))?;
                rep.points += 1;
                rep.worst_position_mm = rep.worst_position_mm.max(wp / bp.max(f64::MIN_POSITIVE));
                rep.worst_angle_rad = rep.worst_angle_rad.max(if ba > 0.0 {
                    wa / ba
                } else if wa > 0.0 {
                    f64::INFINITY
                } else {
                    0.0
                });
                if !(wp <= bp) || !(wa <= ba) {
                    return Err(format!(
                        "{}: the closed-form bound {bp:e} mm / {ba:e}° of the piece from {p0} (n {n0}, axes {a0:?}) to {p1} (n {n1}, axes {a1:?}) is below the sampled error {wp:e} mm / {wa:e}°",
                        m.name()
                    ));
                }
            }
        }
    }
    Ok(rep)
}

/// The interpolation error of a piece sampled at [`BOUND_SAMPLES`] points: the firmware's
/// pose `forward(lerp(a₀, a₁, s))` against the intended `forward(inverse(lerp(p₀, p₁, s),
/// n(s), a₀))`, n(s) the great-circle interpolation of n₀ and n₁ (written here from its
/// definition, not with the tessellation's code). Tip mm, axis degrees.
pub fn sampled_error(
    m: &dyn Machine,
    (a0, p0, n0): (&[f64], DVec3, DVec3),
    (a1, p1, n1): (&[f64], DVec3, DVec3),
) -> Result<(f64, f64), String> {
    let w = num::angle_between(n0, n1);
    let (mut wp, mut wa) = (0.0f64, 0.0f64);
    for i in 1..BOUND_SAMPLES {
        let s = i as f64 / BOUND_SAMPLES as f64;
        let n = if w < 1e-9 {
            n0
        } else {
            (n0 * num::sin((1.0 - s) * w) + n1 * num::sin(s * w)) / num::sin(w)
        };
        let p = p0 + (p1 - p0) * s;
        let exact_axes = m.inverse(p, n, Some(a0)).map_err(|e| {
            format!(
                "{}: a closed-form bound was given, but inverse fails inside the piece: {e}",
                m.name()
            )
        })?;
        let exact = m.forward(&exact_axes).map_err(|e| e.to_string())?;
        // a machine that realises requests where bounded is held to the request itself here
        if m.realises_bounded_requests()
            && !((exact.0 - p).length() <= POSITION_TOLERANCE
                && num::angle_between(exact.1, n) <= ANGLE_TOLERANCE)
        {
            return Err(format!(
                "{}: realises requests, but forward(inverse({p}, {n})) = ({}, {}) inside a bounded piece",
                m.name(),
                exact.0,
                exact.1
            ));
        }
        let lerped: Vec<f64> = a0.iter().zip(a1).map(|(x, y)| x + (y - x) * s).collect();
        let fw = m.forward(&lerped).map_err(|e| e.to_string())?;
        wp = wp.max((fw.0 - exact.0).length());
        wa = wa.max(num::deg(num::angle_between(fw.1, exact.1)));
    }
    Ok((wp, wa))
}

/// Turns (radians) and tip steps (mm) at which law 7 checks a start-drift bound at the edge
/// of its domain: the held-axis probe's own turn with the tip steps of moves of 0, 1 and
/// 1000 mm, and wider ones.
const DRIFT_STEPS: [(f64, f64); 5] = [
    (super::tessellate::PROBE_TURN_RAD, 0.0),
    (super::tessellate::PROBE_TURN_RAD, 1e-7),
    (super::tessellate::PROBE_TURN_RAD, 1e-4),
    (1e-4, 1e-3),
    (1e-2, 0.5),
];

/// Directions of law 7's tip steps (unit).
fn drift_directions() -> [DVec3; 8] {
    let d = DVec3::new(1.0, -1.0, 1.0).normalize();
    [
        DVec3::X,
        -DVec3::X,
        DVec3::Y,
        -DVec3::Y,
        DVec3::Z,
        -DVec3::Z,
        d,
        -d,
    ]
}

/// Law 7 (start drift; see [`Machine::start_drift_deg`]): at every grid position and axis of
/// law 1, solved alone and after the solution of another grid axis (a held axis, another
/// branch), wherever the machine gives a bound:
/// - (a) for each of [`DRIFT_STEPS`] the request turned by exactly that turn in 8 directions
///   about it, with the tip moved by that step, is solved from the start's axes and its
///   realised axis is within the bound of the start's (`forward`, written here);
/// - (b) wherever the tessellation would skip its held-axis probe ([`Plan::probe_skipped`],
///   under the default bounds and under a 1e-4° angle bound) for a move to another grid
///   position or a point 1 m away with the same, the opposite or another grid axis, the
///   probe itself ([`tessellate::held_axis_probe`]) raises no error and finds no jump.
///
/// `points` counts the checks of (a) and (b); the worst angle is the largest realised drift
/// of (a) as a fraction of its bound.
///
/// [`Plan::probe_skipped`]: super::tessellate::Plan::probe_skipped
/// [`tessellate::held_axis_probe`]: super::tessellate::held_axis_probe
pub fn check_start_drift(m: &dyn Machine) -> Result<LawReport, String> {
    use super::tessellate::{held_axis_probe, Bounds, Plan, DEFAULT_BOUNDS};
    let ws = m.workspace();
    let grid = positions(&ws);
    let grid_axes = axes(&ws);
    let dirs = drift_directions();
    let tight = Bounds {
        max_angle_deg: 1e-4,
        ..DEFAULT_BOUNDS
    };
    let plans = [Plan::new(m, &DEFAULT_BOUNDS), Plan::new(m, &tight)];
    let mut rep = LawReport::default();
    for (i, &p) in grid.iter().enumerate() {
        for (j, &n) in grid_axes.iter().enumerate() {
            let other = grid_axes[(j + 7) % grid_axes.len()];
            for prev in [None, m.inverse(p, other, None).ok()] {
                let Ok(a0) = m.inverse(p, n, prev.as_deref()) else {
                    continue;
                };
                let r0 = m.forward(&a0).map_err(|e| e.to_string())?.1;
                // (a) the bound at the edge of its domain
                for &(turn, tip) in &DRIFT_STEPS {
                    let Some(bound) = m.start_drift_deg(p, n, &a0, turn, tip) else {
                        continue;
                    };
                    let side = n.any_orthonormal_vector();
                    for (k, dir) in dirs.iter().enumerate() {
                        let about = super::angles::rotate(side, n, num::rad(45.0 * k as f64));
                        let n2 = super::angles::rotate(n, about, turn);
                        let p2 = p + *dir * tip;
                        let a2 = m.inverse(p2, n2, Some(&a0)).map_err(|e| {
                            format!(
                                "{}: start_drift_deg gave {bound}° at {p}, {n} (axes {a0:?}), but inverse({p2}, {n2}) fails: {e}",
                                m.name()
                            )
                        })?;
                        let r2 = m.forward(&a2).map_err(|e| e.to_string())?.1;
                        let got = num::deg(num::angle_between(r0, r2));
                        rep.points += 1;
                        rep.worst_angle_rad = rep.worst_angle_rad.max(got / bound);
                        if !(got <= bound) {
                            return Err(format!(
                                "{}: start_drift_deg gave {bound:e}° at {p}, {n} (axes {a0:?}) for a turn of {turn:e} rad and a tip step of {tip:e} mm, but {p2}, {n2} realises {r2} (axes {a2:?}), {got:e}° from {r0}",
                                m.name()
                            ));
                        }
                    }
                }
                // (b) the probe itself where the tessellation skips it
                for plan in &plans {
                    plan.note_solved(&a0, p, n);
                    let ends = [
                        grid[(i + j) % grid.len()],
                        grid[(i + 13) % grid.len()],
                        p + DVec3::new(1000.0, 0.0, 0.0),
                    ];
                    let to_axes = [n, -n, other, grid_axes[(3 * j + i) % grid_axes.len()]];
                    for &p1 in &ends {
                        for &n1 in &to_axes {
                            if !plan.probe_skipped(m, (&a0, p, n), (p1, n1)) {
                                continue;
                            }
                            rep.points += 1;
                            match held_axis_probe(m, plan, (&a0, p, n), (p1, n1)) {
                                Ok((_, _, false)) => {}
                                Ok((r0, re, true)) => {
                                    return Err(format!(
                                        "{}: the held-axis probe is skipped from {p}, {n} (axes {a0:?}) to {p1}, {n1} under a {}° bound, but it finds the realised axis jumping from {r0} to {re}",
                                        m.name(),
                                        plan.bounds().max_angle_deg
                                    ));
                                }
                                Err(e) => {
                                    return Err(format!(
                                        "{}: the held-axis probe is skipped from {p}, {n} (axes {a0:?}) to {p1}, {n1}, but it fails: {e}",
                                        m.name()
                                    ));
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    Ok(rep)
}
