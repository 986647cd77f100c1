//! The machine checks shared by the end-to-end tests (tests/machine_emit.rs, with one real
//! slicer file per machine, and tests/real_slicers.rs, the core matrix on every preset): parse a
//! machine G-code with the machine's axis letters (the crate's reader tracks X Y Z E only) and
//! walk it against the core toolpath with the tests' own forward kinematics of the machine file
//! ([`fk`]: closed forms from the seeds and docs/machines.md, sharing no code with
//! `warpslice::machine`, so a kinematic formula wrong the same way in the crate's inverse and
//! forward is caught):
//! - every toolpath point is reached: walking the output in order, the forward kinematics of a
//!   line lands on each toolpath tip within 0.01 mm and (where the machine realises the axis
//!   without a branch choice) on its realised tool axis within 0.1°; every line in between lies
//!   on the toolpath segment;
//! - interpolation (`samples` > 1): points sampled on every output move stay within
//!   0.02 mm / 0.1° of the intended path (linear tip, slerp tool axis, realised by the machine).

use glam::DVec3;
use warpslice::machine::MachineSpec;
use warpslice::toolpath::ToolPoint;

#[path = "fk.rs"]
pub mod fk;

use fk::Fk;

/// Tip tolerance of the forward check, mm (issue: 0.01).
pub const TIP_TOL: f64 = 0.01;
/// Tool-axis tolerance, degrees (issue: 0.1).
pub const AXIS_TOL_DEG: f64 = 0.1;
/// Interpolation bound, mm / degrees, plus the 3-decimal rounding of the written axes.
pub const INTERP_MM: f64 = 0.02 + 0.002;
pub const INTERP_DEG: f64 = 0.1 + 0.005;
/// How much closer (in [`TIP_TOL`] units of the landing score) a following line must come to a
/// toolpath point to be its landing instead of the line already within tolerance: 0.0025 mm,
/// above what the 3-decimal writing of the axes moves the tip (≤ 0.0017 mm for three linear
/// axes at 0.0005 mm each, plus the rotary axes' 0.0005° at the tip's lever arm).
pub const ROUNDING_SCORE: f64 = 0.25;
/// Two toolpath points at most this far apart (mm) can be written with the same 3-decimal axis
/// words (0.0005 mm per linear axis, 0.0005° per rotary one at the tip's lever arm), and then
/// the second has no line of its own (the emitter writes no move the firmware reads as none).
pub const NO_OP_POINT_MM: f64 = 0.0025;
/// Samples per output move in the interpolation check (issue: 100).
pub const SAMPLES: usize = 100;

/// One parsed output line with machine axes.
#[derive(Clone, Debug)]
pub struct AxisLine {
    pub number: usize,
    pub axes: Vec<f64>,
    pub rotate_around: bool,
    /// The axes after a `G92` rename that follows this line (the start of the next move).
    pub after: Option<Vec<f64>>,
    pub reorient: bool,
    pub discontinuity: bool,
}

/// Parse the machine G-code: `G1` lines with every axis letter (the region), `G92` on the
/// axes (rotary resets: the next move starts from the renamed position).
pub fn parse(text: &str, names: &[String]) -> Result<Vec<AxisLine>, String> {
    let mut cur: Vec<Option<f64>> = vec![None; names.len()];
    let mut out: Vec<AxisLine> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let (code, comment) = match raw.find(';') {
            Some(k) => (&raw[..k], &raw[k..]),
            None => (raw, ""),
        };
        let mut words = code.split_whitespace();
        let Some(cmd) = words.next() else { continue };
        if cmd != "G1" && cmd != "G0" && cmd != "G92" {
            continue;
        }
        let mut seen = vec![false; names.len()];
        for w in words {
            let (letter, value) = w.split_at(1);
            if let Some(k) = names.iter().position(|n| n.eq_ignore_ascii_case(letter)) {
                let v: f64 = value
                    .parse()
                    .map_err(|_| format!("line {}: bad number in '{w}'", i + 1))?;
                cur[k] = Some(v);
                seen[k] = true;
            } else if !matches!(letter, "E" | "F" | "X" | "Y" | "Z") {
                return Err(format!("line {}: unknown word '{w}'", i + 1));
            }
        }
        if cmd == "G92" {
            if let Some(last) = out.last_mut() {
                // a rotary reset renames the current position: the next move starts there
                let mut after = last.after.clone().unwrap_or_else(|| last.axes.clone());
                for (k, &sn) in seen.iter().enumerate() {
                    if sn {
                        after[k] = cur[k].unwrap_or(0.0);
                    }
                }
                last.after = Some(after);
            }
            continue;
        }
        if seen.iter().all(|&s| s) && names.iter().any(|n| !["X", "Y", "Z"].contains(&n.as_str())) {
            let axes: Vec<f64> = cur.iter().map(|v| v.unwrap_or(0.0)).collect();
            out.push(AxisLine {
                number: i + 1,
                axes,
                // a swing lift (lift, turn in the air, set down) is off the path by design
                // like a rotate-around
                rotate_around: comment.contains("rotate-around") || comment.contains("swing-lift"),
                after: None,
                reorient: comment.contains("; reorient"),
                discontinuity: comment.contains("; discontinuity"),
            });
        }
    }
    Ok(out)
}

/// Distance from `q` to the segment a–b and the parameter of the closest point.
pub fn to_segment(q: DVec3, a: DVec3, b: DVec3) -> (f64, f64) {
    let d = b - a;
    let l2 = d.length_squared();
    let s = if l2 > 0.0 {
        ((q - a).dot(d) / l2).clamp(0.0, 1.0)
    } else {
        1.0
    };
    ((a + d * s - q).length(), s)
}

pub fn deg(a: DVec3, b: DVec3) -> f64 {
    a.angle_between(b).to_degrees()
}

/// The unit vector a fraction `s` of the way from unit `a` to unit `b` along their great circle
/// (the intended tool axis between two toolpath points, docs/machines.md "slerp").
pub fn slerp(a: DVec3, b: DVec3, s: f64) -> DVec3 {
    let w = a.angle_between(b);
    let v = if !(1e-9..=std::f64::consts::PI - 1e-9).contains(&w) {
        a.lerp(b, s)
    } else {
        (a * ((1.0 - s) * w).sin() + b * (s * w).sin()) / w.sin()
    };
    if v.length() > 1e-12 {
        v.normalize()
    } else {
        a
    }
}

#[derive(Default, Debug)]
pub struct Measured {
    pub points: usize,
    pub lines: usize,
    pub worst_tip: f64,
    pub worst_axis: f64,
    pub worst_interp_mm: f64,
    pub worst_interp_deg: f64,
    pub discontinuities: usize,
    pub worst_line: usize,
    pub fallbacks: usize,
    pub worst_detail: String,
}

/// The checks of the module documentation, for the machine `spec` (its parameters only: the
/// kinematics are [`fk`]'s).
pub fn check(
    spec: &MachineSpec,
    toolpath: &[ToolPoint],
    lines: &[AxisLine],
    samples: usize,
) -> Result<Measured, String> {
    let m = Fk::from_spec(spec)?;
    let mut r = Measured {
        lines: lines.len(),
        ..Measured::default()
    };
    let pts: Vec<&ToolPoint> = toolpath
        .iter()
        .filter(|t| !(t.travel && t.e != 0.0))
        .collect();
    // which segment (index of its end point) and parameter each line belongs to
    let mut owner: Vec<Option<(usize, f64)>> = vec![None; lines.len()];
    let mut li = 0usize;
    for (k, tp) in pts.iter().enumerate() {
        let start = if k == 0 { tp.p } else { pts[k - 1].p };
        // a point this close to the previous one can be written with the same rounded words,
        // and the emitter writes no line for a move the firmware reads as none: the previous
        // line lands on it too (CuraEngine-sliced rear case × curved-out-0.3 on the polar
        // machine: two points 0.001 mm apart)
        if k > 0 && li > 0 && (tp.p - start).length() <= NO_OP_POINT_MM {
            let (p, n) = m.forward(&lines[li - 1].axes)?;
            let dtip = (p - tp.p).length();
            let axis_err = deg(n, m.realised(tp.p, tp.n, None));
            if dtip <= TIP_TOL && (m.free(tp.p, tp.n) || axis_err <= AXIS_TOL_DEG) {
                r.points += 1;
                r.worst_tip = r.worst_tip.max(dtip);
                continue;
            }
        }
        loop {
            let Some(line) = lines.get(li) else {
                return Err(format!(
                    "toolpath point {k} at {:?} is never reached by the output",
                    tp.p
                ));
            };
            let (p, n) = m.forward(&line.axes)?;
            li += 1;
            // how far a line's pose is from a toolpath point, in tolerances (tip, realisable
            // axis): (tip distance, axis error, score)
            let miss_to = |q: &ToolPoint, p: DVec3, n: DVec3| -> (f64, f64, f64) {
                let free = m.free(q.p, q.n);
                let dtip = (p - q.p).length();
                let axis_err = deg(n, m.realised(q.p, q.n, None));
                let score = dtip / TIP_TOL + if free { 0.0 } else { axis_err / AXIS_TOL_DEG };
                (dtip, axis_err, score)
            };
            let free = m.free(tp.p, tp.n);
            let within = |(d, a, _): (f64, f64, f64)| d <= TIP_TOL && (free || a <= AXIS_TOL_DEG);
            let (dtip, axis_err, score) = miss_to(tp, p, n);
            // the emitter's last piece of a move lands on the point: tip and (realisable) axis;
            // a line that comes within tolerance of the point while a following line lands
            // closer is on the way (a rotate-around that lands 0.006 mm before the point, the
            // seam piece and the last piece after it: PrusaSlicer sphere × conic-in-30 on RTN).
            // The following lines within tolerance are looked at (the lifted rotate-around
            // lines between them passed over); one closer still to the next point is that
            // point's; closer by less than the writing's rounding does not count (two points
            // 0.0014 mm apart, each line within 0.0008 mm of both: CuraEngine 20 mm box ×
            // tilted-out-0.2 on the triple-Z bed).
            let after = pts.get(k + 1).copied();
            let closer_next = || -> Result<bool, String> {
                for next in lines.iter().skip(li) {
                    let (pn, nn) = m.forward(&next.axes)?;
                    let here = miss_to(tp, pn, nn);
                    if within(here) && here.2 < score - ROUNDING_SCORE {
                        let theirs = after.map_or(f64::INFINITY, |q| miss_to(q, pn, nn).2);
                        return Ok(here.2 < theirs);
                    }
                    if !within(here) && !next.rotate_around {
                        break;
                    }
                }
                Ok(false)
            };
            let is_end = within((dtip, axis_err, score)) && !closer_next()?;
            if line.rotate_around && !is_end {
                // a lifted turn-around (single-revolution axis): off the path by design; its
                // descent lands on the point
                continue;
            }
            let (dseg, s) = to_segment(p, start, tp.p);
            // (the first point is reached from the region's start, not a toolpath point)
            if k > 0 && dseg > INTERP_MM {
                if std::env::var("WARPSLICE_DEBUG_WALK").is_ok() {
                    let from = li.saturating_sub(6);
                    for l in lines.iter().skip(from).take(li + 2 - from) {
                        let (pj, nj) = m.forward(&l.axes)?;
                        eprintln!(
                            "line {} tip {pj:?} n {nj:?} ra {}",
                            l.number, l.rotate_around
                        );
                    }
                    let from = k.saturating_sub(3);
                    for (j, q) in pts.iter().enumerate().skip(from).take(k + 2 - from) {
                        eprintln!("pt {j} {:?} n {:?} free {}", q.p, q.n, m.free(q.p, q.n));
                    }
                }
                return Err(format!("output line {} (tip {p:?}) is off the toolpath segment to point {k} {:?} by {dseg:.4} mm", line.number, tp.p));
            }
            owner[li - 1] = Some((
                k,
                if (tp.p - start).length() > 1e-9 {
                    s
                } else {
                    1.0
                },
            ));
            if is_end {
                r.worst_tip = r.worst_tip.max(dtip);
                if !free {
                    r.worst_axis = r.worst_axis.max(axis_err);
                }
                r.points += 1;
                break;
            }
        }
    }
    // interpolation of every output move between two lines of the same segment (or from the
    // end of one segment to a line of the next)
    let moves = if samples > 1 { lines.len() } else { 0 };
    for w in 1..moves {
        let b = &lines[w];
        let mut a = lines[w - 1].clone();
        if let Some(after) = a.after.take() {
            a.axes = after;
        }
        let a = &a;
        if a.rotate_around || b.rotate_around {
            continue;
        }
        if b.discontinuity {
            r.discontinuities += 1;
            continue;
        }
        if b.reorient {
            // in place: tip fixed, axis slerp between the realised axes of the two lines
            let (pa, na) = m.forward(&a.axes)?;
            let (_, nb) = m.forward(&b.axes)?;
            for i in 1..samples {
                let u = i as f64 / samples as f64;
                let axes: Vec<f64> = a
                    .axes
                    .iter()
                    .zip(&b.axes)
                    .map(|(x, y)| x + (y - x) * u)
                    .collect();
                let (fp, fn_) = m.forward(&axes)?;
                let exact = m.realised(pa, slerp(na, nb, u), Some(&a.axes));
                r.worst_interp_mm = r.worst_interp_mm.max((fp - pa).length());
                r.worst_interp_deg = r.worst_interp_deg.max(deg(fn_, exact));
            }
            continue;
        }
        // the intended path: the toolpath segment the two lines belong to (tip linear, axis
        // slerp) when the matching placed both on it; else the straight tip path between the
        // two lines' tips and the slerp of their realised axes
        let (pa, na) = m.forward(&a.axes)?;
        let (pb, nb) = m.forward(&b.axes)?;
        let seg = owner[w].and_then(|(k, s1)| {
            let s0 = match owner[w - 1] {
                Some((k0, s)) if k0 == k => s,
                Some((k0, _)) if k0 + 1 == k => 0.0,
                _ => return None,
            };
            let (t0, t1) = (pts[k.saturating_sub(1)], pts[k]);
            let realised =
                |s: f64| m.realised(t0.p.lerp(t1.p, s), slerp(t0.n, t1.n, s), Some(&a.axes));
            let on = (t0.p.lerp(t1.p, s0) - pa).length() < 0.005
                && (t0.p.lerp(t1.p, s1) - pb).length() < 0.005
                && deg(realised(s0), na) < AXIS_TOL_DEG
                && deg(realised(s1), nb) < AXIS_TOL_DEG;
            on.then_some((t0, t1, s0, s1))
        });
        if seg.is_none() {
            r.fallbacks += 1;
        }
        for i in 1..samples {
            let u = i as f64 / samples as f64;
            let axes: Vec<f64> = a
                .axes
                .iter()
                .zip(&b.axes)
                .map(|(x, y)| x + (y - x) * u)
                .collect();
            let (fp, fn_) = m.forward(&axes)?;
            let (ip, inn) = match seg {
                Some((t0, t1, s0, s1)) => {
                    let s = s0 + (s1 - s0) * u;
                    (t0.p.lerp(t1.p, s), slerp(t0.n, t1.n, s))
                }
                None => (pa.lerp(pb, u), slerp(na, nb, u)),
            };
            // the machine puts the tip on the intended point and realises its share of the
            // intended axis
            let exact = (ip, m.realised(ip, inn, Some(&a.axes)));
            let dp = (fp - exact.0).length();
            let da = deg(fn_, exact.1);
            if da > r.worst_interp_deg {
                r.worst_line = b.number;
                r.worst_detail = format!(
                    "u {u} seg {:?} na {na:?} nb {nb:?} fw {fn_:?} exact {:?} inn {inn:?}",
                    seg.map(|(t0, t1, s0, s1)| (t0.n, t1.n, s0, s1)),
                    exact.1
                );
            }
            r.worst_interp_mm = r.worst_interp_mm.max(dp);
            r.worst_interp_deg = r.worst_interp_deg.max(da);
        }
    }
    if r.worst_interp_mm > INTERP_MM || r.worst_interp_deg > INTERP_DEG {
        return Err(format!(
            "interpolation error {:.5} mm / {:.4}° beyond the bound (worst at output line {}: {})",
            r.worst_interp_mm, r.worst_interp_deg, r.worst_line, r.worst_detail
        ));
    }
    Ok(r)
}
