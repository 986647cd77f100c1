//! The independent checker of a written unwarp (issue 17): it reads the slicer's G-code and
//! warpslice's 3-axis output with the tests' own reader ([`super::written`]), maps them with
//! the warps in closed form ([`super::closed`]), classifies skirt and object by itself, and
//! checks the README's promises on the **written** file:
//!
//! 1. the placement in the header is the slicer's known one (the warped STL's bounding box
//!    centred on the bed centre) within [`REGISTRATION_TOLERANCE`];
//! 2. every object vertex, and every chord sampled [`CHORD_SAMPLES`] times, lies on one of the
//!    slicer's layer surfaces T_z = z_k within [`VERTEX_TOLERANCE`] / the unwarp tolerance +
//!    [`CHORD_ROUNDING`] (as a distance: |T_z − z_k| / |∇T_z|);
//! 3. no object extrusion is longer than `--max-segment` (+ rounding);
//! 4. E per class: flat moves (skirt, brim) keep the slicer's E; the object's E is the slicer's
//!    less the anchor layer, each move divided by det J at its midpoint (computed here), within
//!    [`OBJECT_E_TOLERANCE`];
//! 5. travels: a travel never passes more than [`DIRECT_SLACK`] below a bead printed before it
//!    within [`NOZZLE_RADIUS`] (its ends' neighbourhood, [`NEAR_END`], excepted: the nozzle just
//!    printed or is about to print there), and a lifted travel's lifted part clears every such
//!    bead by the clearance (1 mm) less [`LIFT_SLACK`];
//! 6. every retraction between two extrusions is undone before the second (net E of the
//!    non-printing moves between them is 0 within [`RETRACT_BALANCE`]), except as often as the
//!    input itself leaves such a net between two of its extrusions (a file that extrudes while
//!    retracted: the unwarp keeps it, it must not invent one);
//! 7. nothing below the bed, and at most [`CLAMPED_FRACTION`] of the object vertices on it
//!    (clamped).

use std::collections::{HashMap, HashSet};

use glam::{DVec2, DVec3};
use warpslice::job::Job;
use warpslice::mesh::Mesh;

use super::closed::Closed;
use super::machine::to_segment;
use super::written::{self, Move, Typed};

/// The registration's required accuracy against the slicer's placement, mm (issue 17).
pub const REGISTRATION_TOLERANCE: f64 = 0.02;
/// A written vertex lies this close to its layer surface: the exact vertex is on it, and writing
/// X, Y, Z with 3 decimals moves it by at most √3·0.0005 = 0.00087 mm (rounded up), mm.
pub const VERTEX_TOLERANCE: f64 = 0.001;
/// A written chord may sit this much farther from the surface than the unwarp tolerance (the
/// rounding of its two ends, as for [`VERTEX_TOLERANCE`]), mm.
pub const CHORD_ROUNDING: f64 = 0.001;
/// Points sampled inside each written object extrusion (besides its two ends).
pub const CHORD_SAMPLES: usize = 15;
/// A written piece may be this much longer than `--max-segment` (rounding of its ends), mm.
pub const LENGTH_ROUNDING: f64 = 0.002;
/// Object E written vs the closed-form expectation, relative: the expectation takes det J at
/// each slicer move's midpoint (the blend's det J varies by < 1 % over a 1 mm piece), and points
/// clamped to the bed lose a little E (bounded by [`CLAMPED_FRACTION`]).
pub const OBJECT_E_TOLERANCE: f64 = 0.01;
/// Flat (skirt, brim) E written vs the slicer's, relative (5-decimal rounding of E).
pub const FLAT_E_TOLERANCE: f64 = 1e-4;
/// An object vertex written at most this above the bed (+ z offset) counts as clamped, mm.
pub const CLAMP_Z: f64 = 0.0015;
/// At most this fraction of the object's vertices may be clamped to the bed (README: "a point
/// mapped below z = 0 is clamped", hundredths of a millimetre on a steep warp's first layer).
pub const CLAMPED_FRACTION: f64 = 0.02;
/// Lowest z any move may reach, mm (rounding).
pub const BED_TOLERANCE: f64 = -0.001;
/// First-layer extrusions of an untyped file farther than this (XY) from the warped mesh's
/// first-layer slab are the skirt: the three slicers keep a skirt ≥ 2 mm away (PrusaSlicer and
/// Slic3r 6 mm, CuraEngine 3 mm), object beads lie within half a line of the section, mm.
pub const SKIRT_GAP: f64 = 2.0;
/// A printed bead within this (XY) of a travel's path is under the nozzle, mm.
pub const NOZZLE_RADIUS: f64 = 0.5;
/// A straight travel may pass this far below the top of a bead printed before it (the README's
/// rule grazes beads just printed by 0.05 mm; beads are sampled every 0.25 mm here), mm.
pub const DIRECT_SLACK: f64 = 0.1;
/// Within this (XY) of a travel's start or end the nozzle is at the bead it just printed or is
/// about to print: the README's rule excepts that neighbourhood (1.5 mm of coarse 1 mm cells
/// and their neighbours, ≤ 1.5 + √2 + 0.25 mm from the path), mm.
pub const NEAR_END: f64 = 3.5;
/// A lifted travel's lifted part clears the beads under it by the clearance less this, mm.
pub const LIFT_SLACK: f64 = 0.1;
/// A travel counts as lifted when it rises this far above both its ends, mm.
pub const LIFT_DETECT: f64 = 0.1;
/// Net E of the non-printing moves between two extrusions: zero within this (mm of filament,
/// 5-decimal E on both sides of a retraction).
pub const RETRACT_BALANCE: f64 = 1e-4;
/// Spacing of the bead samples and the travel samples, mm.
const STEP: f64 = 0.25;

/// What the case is: the job, the warped STL it was sliced from, where the slicer put it, and
/// the unwarp options used.
pub struct Expect<'a> {
    pub job: &'a Job,
    /// The warped STL as written by `warp` (STL frame).
    pub warped: &'a Mesh,
    /// The slicer's translation of the STL frame onto its bed (known independently: the
    /// slicers centre the bounding box on the bed centre).
    pub placement: DVec2,
    pub max_segment: f64,
    pub tolerance: f64,
    pub clearance: f64,
}

/// What the checker measured.
#[derive(Debug, Default, Clone)]
pub struct Checked {
    pub vertices: usize,
    pub samples: usize,
    pub worst_vertex: f64,
    pub worst_chord: f64,
    pub longest: f64,
    pub registration_error: f64,
    pub e_object: f64,
    pub e_object_expected: f64,
    pub e_anchor: f64,
    pub e_flat: f64,
    pub e_flat_in: f64,
    pub clamped: usize,
    pub travels: usize,
    pub lifted: usize,
    /// Smallest clearance of a lifted part over the beads under it, mm (∞: none lifted).
    pub lift_clearance: f64,
    /// Deepest a direct travel went below a bead printed before it, mm.
    pub direct_dip: f64,
    pub gaps: usize,
    pub min_z: f64,
    /// E over the whole written file: (net, extruded) ([`written::Written::e_totals`]).
    pub e_totals: (f64, f64),
}

/// The first-layer slab of the warped mesh: its triangles clipped to z ≤ top, projected.
struct Slab {
    polys: Vec<(DVec2, DVec2, Vec<DVec2>)>,
}

impl Slab {
    fn new(mesh: &Mesh, top: f64) -> Slab {
        let mut polys = Vec::new();
        for t in &mesh.triangles {
            let v = [0, 1, 2].map(|k| mesh.vertices[t[k] as usize]);
            // Sutherland–Hodgman against the half-space z ≤ top
            let mut out = Vec::new();
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                if a.z <= top {
                    out.push(a.truncate());
                }
                if (a.z <= top) != (b.z <= top) {
                    let s = (top - a.z) / (b.z - a.z);
                    out.push(a.lerp(b, s).truncate());
                }
            }
            if out.is_empty() {
                continue;
            }
            let lo = out
                .iter()
                .fold(DVec2::splat(f64::INFINITY), |m, p| m.min(*p));
            let hi = out
                .iter()
                .fold(DVec2::splat(f64::NEG_INFINITY), |m, p| m.max(*p));
            polys.push((lo, hi, out));
        }
        Slab { polys }
    }

    /// Whether p is farther than `gap` from every clipped triangle.
    fn farther_than(&self, p: DVec2, gap: f64) -> bool {
        for (lo, hi, poly) in &self.polys {
            if p.x < lo.x - gap || p.y < lo.y - gap || p.x > hi.x + gap || p.y > hi.y + gap {
                continue;
            }
            if dist_to_convex(p, poly) <= gap {
                return false;
            }
        }
        true
    }
}

/// Distance from p to a convex polygon (0 inside), either orientation.
fn dist_to_convex(p: DVec2, poly: &[DVec2]) -> f64 {
    let n = poly.len();
    if n >= 3 {
        let (mut pos, mut neg) = (false, false);
        for k in 0..n {
            let (a, b) = (poly[k], poly[(k + 1) % n]);
            let c = (b - a).perp_dot(p - a);
            pos |= c > 0.0;
            neg |= c < 0.0;
        }
        if !(pos && neg) {
            return 0.0;
        }
    }
    (0..n)
        .map(|k| {
            to_segment(
                p.extend(0.0),
                poly[k].extend(0.0),
                poly[(k + 1) % n].extend(0.0),
            )
            .0
        })
        .fold(f64::INFINITY, f64::min)
}

/// Beads printed so far, sampled every [`STEP`], in a hash grid of [`NOZZLE_RADIUS`] cells.
#[derive(Default)]
struct Beads {
    cells: HashMap<(i64, i64), Vec<DVec3>>,
}

impl Beads {
    fn key(p: DVec2) -> (i64, i64) {
        (
            (p.x / NOZZLE_RADIUS).floor() as i64,
            (p.y / NOZZLE_RADIUS).floor() as i64,
        )
    }
    fn add(&mut self, m: &Move) {
        let n = ((m.length() / STEP).ceil() as usize).max(1);
        for k in 0..=n {
            let p = m.at(k as f64 / n as f64);
            self.cells
                .entry(Beads::key(p.truncate()))
                .or_default()
                .push(p);
        }
    }
    /// The highest bead within [`NOZZLE_RADIUS`] of p (XY).
    fn top(&self, p: DVec2) -> f64 {
        let (i, j) = Beads::key(p);
        let mut top = f64::NEG_INFINITY;
        for dj in -1..=1 {
            for di in -1..=1 {
                for b in self.cells.get(&(i + di, j + dj)).into_iter().flatten() {
                    if (b.truncate() - p).length() <= NOZZLE_RADIUS {
                        top = top.max(b.z);
                    }
                }
            }
        }
        top
    }
}

fn key3(p: DVec3) -> (i64, i64, i64) {
    let r = |v: f64| (v * 1000.0).round() as i64;
    (r(p.x), r(p.y), r(p.z))
}

/// Check one case: the slicer's G-code `input` and warpslice's 3-axis `output` of it.
pub fn check(x: &Expect<'_>, input: &[u8], output: &[u8]) -> Result<Checked, String> {
    let warp = Closed::of(x.job)?;
    let inp = written::read(input).map_err(|e| format!("input: {e}"))?;
    let out = written::read(output).map_err(|e| format!("output: {e}"))?;
    let mut c = Checked {
        lift_clearance: f64::INFINITY,
        min_z: f64::INFINITY,
        e_totals: out.e_totals(),
        ..Checked::default()
    };

    // 1. placement
    let m2o = out
        .model_to_output
        .ok_or("the output has no `; warpslice model_to_output` line")?;
    c.registration_error = (m2o.truncate() - x.placement).length();
    if c.registration_error > REGISTRATION_TOLERANCE {
        return Err(format!(
            "1. placement {:?} is {:.4} mm from the slicer's {:?}",
            m2o.truncate(),
            c.registration_error,
            x.placement
        ));
    }

    // classify the input's extrusions
    let first_z = inp
        .extrusions()
        .map(|m| m.to.z)
        .fold(f64::INFINITY, f64::min);
    if !first_z.is_finite() {
        return Err("the input has no extrusion".into());
    }
    let slab = (!inp.typed).then(|| Slab::new(x.warped, first_z + 1e-6));
    let flat_in = |m: &Move| match m.typed {
        Typed::Flat => true,
        Typed::Object => false,
        Typed::Untyped => {
            m.to.z <= first_z + 1e-6
                && slab.as_ref().is_some_and(|s| {
                    s.farther_than(((m.from + m.to) * 0.5).truncate() - x.placement, SKIRT_GAP)
                })
        }
    };
    let first_object_z = inp
        .extrusions()
        .filter(|m| !flat_in(m))
        .map(|m| m.to.z)
        .fold(f64::INFINITY, f64::min);
    let mut layers: Vec<f64> = Vec::new();
    let mut flat_ends = HashSet::new();
    let shift = DVec3::new(x.placement.x, x.placement.y, x.job.stl_z_offset);
    for m in inp.extrusions() {
        layers.push(m.to.z);
        if flat_in(m) {
            c.e_flat_in += m.e;
            flat_ends.insert(key3(m.to));
        } else if x.job.anchor.is_some() && m.to.z <= first_object_z + 1e-6 {
            c.e_anchor += m.e;
        } else {
            let p = warp.inverse((m.from + m.to) * 0.5 - shift);
            c.e_object_expected += m.e / warp.det(p);
        }
    }
    layers.sort_by(f64::total_cmp);
    layers.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    let level = |z: f64| {
        let i = layers.partition_point(|&v| v < z);
        [i.wrapping_sub(1), i]
            .iter()
            .filter_map(|&k| layers.get(k))
            .copied()
            .min_by(|a, b| (a - z).abs().total_cmp(&(b - z).abs()))
            .unwrap_or(f64::NAN)
    };
    let flat_out = |m: &Move| match m.typed {
        Typed::Flat => true,
        Typed::Object => false,
        Typed::Untyped => flat_ends.contains(&key3(m.to)),
    };

    // 2–4, 7: the output's extrusions
    let on_surface = |p: DVec3| -> Option<f64> {
        let pm = p - m2o;
        (pm.z > CLAMP_Z).then(|| {
            let t = warp.tz(pm) + x.job.stl_z_offset;
            warp.distance_to_level(pm, level(t) - x.job.stl_z_offset)
        })
    };
    for m in &out.moves {
        if m.moves() {
            c.min_z = c.min_z.min(m.to.z);
        }
        if !m.extrudes() {
            continue;
        }
        if flat_out(m) {
            c.e_flat += m.e;
            continue;
        }
        c.e_object += m.e;
        c.vertices += 1;
        c.longest = c.longest.max(m.length());
        if m.length() > x.max_segment + LENGTH_ROUNDING {
            return Err(format!(
                "3. line {}: an object extrusion {:.4} mm long (--max-segment {})",
                m.line,
                m.length(),
                x.max_segment
            ));
        }
        for (t, tol) in
            std::iter::once((1.0, VERTEX_TOLERANCE)).chain((1..=CHORD_SAMPLES).map(|k| {
                (
                    k as f64 / (CHORD_SAMPLES + 1) as f64,
                    x.tolerance + CHORD_ROUNDING,
                )
            }))
        {
            let p = m.at(t);
            match on_surface(p) {
                None if t == 1.0 => c.clamped += 1,
                None => {}
                Some(d) => {
                    if t == 1.0 {
                        c.worst_vertex = c.worst_vertex.max(d);
                    } else {
                        c.samples += 1;
                        c.worst_chord = c.worst_chord.max(d);
                    }
                    if d > tol {
                        return Err(format!(
                            "2. line {}: {} {p} lies {d:.4} mm off every layer surface (allowed {tol})",
                            m.line,
                            if t == 1.0 { "the vertex" } else { "a chord point" }
                        ));
                    }
                }
            }
        }
    }
    if c.vertices == 0 {
        return Err("no object extrusion in the output".into());
    }
    if c.min_z < BED_TOLERANCE {
        return Err(format!("7. a move reaches z = {} below the bed", c.min_z));
    }
    if c.clamped as f64 > CLAMPED_FRACTION * c.vertices as f64 {
        return Err(format!(
            "7. {} of {} object vertices clamped to the bed",
            c.clamped, c.vertices
        ));
    }
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-9);
    if rel(c.e_object, c.e_object_expected) > OBJECT_E_TOLERANCE {
        return Err(format!(
            "4. object E {:.4} mm written vs {:.4} mm expected (slicer object E over det J, anchor {:.4} mm dropped)",
            c.e_object, c.e_object_expected, c.e_anchor
        ));
    }
    if (c.e_flat - c.e_flat_in).abs() > FLAT_E_TOLERANCE * c.e_flat_in.max(1.0) {
        return Err(format!(
            "4. flat (skirt/brim) E {:.4} mm written vs the slicer's {:.4} mm",
            c.e_flat, c.e_flat_in
        ));
    }

    // 5–6: travels and retractions, in print order, between the first and the last object
    // extrusion
    let printing: Vec<usize> = (0..out.moves.len())
        .filter(|&i| out.moves[i].extrudes())
        .collect();
    let mut beads = Beads::default();
    // the input's own unbalanced gaps (a file that extrudes while retracted, e.g. a retraction
    // swapped with an extrusion): the unwarp keeps each of them, it must not invent one
    let mut input_unbalanced: Vec<f64> = gap_nets(&inp.moves)
        .into_iter()
        .filter(|n| n.abs() > RETRACT_BALANCE)
        .collect();
    for w in printing.windows(2) {
        let (i, j) = (w[0], w[1]);
        beads.add(&out.moves[i]);
        let gap = &out.moves[i + 1..j];
        if gap.is_empty() {
            continue;
        }
        c.gaps += 1;
        let net = net_e(gap);
        let inherited = input_unbalanced
            .iter()
            .position(|x| (x - net).abs() <= RETRACT_BALANCE);
        if let (true, Some(k)) = (net.abs() > RETRACT_BALANCE, inherited) {
            input_unbalanced.swap_remove(k);
        } else if net.abs() > RETRACT_BALANCE {
            return Err(format!(
                "6. lines {}–{}: the moves between two extrusions leave {net:+.5} mm of E (a retraction not undone, or an extra prime)",
                out.moves[i].line,
                out.moves[j].line
            ));
        }
        let (a, b) = (out.moves[i].to, out.moves[j].from);
        if !gap
            .iter()
            .any(|m| m.moves() && m.from.truncate() != m.to.truncate())
        {
            continue;
        }
        c.travels += 1;
        let base = a.z.max(b.z);
        let lifted = gap.iter().any(|m| m.to.z > base + LIFT_DETECT);
        c.lifted += lifted as usize;
        for m in gap.iter().filter(|m| m.moves()) {
            let n = ((m.length() / STEP).ceil() as usize).max(1);
            for k in 0..=n {
                let q = m.at(k as f64 / n as f64);
                let top = beads.top(q.truncate());
                if !top.is_finite() {
                    continue;
                }
                let near = (q.truncate() - a.truncate()).length() < NEAR_END
                    || (q.truncate() - b.truncate()).length() < NEAR_END;
                if lifted && q.z > base + LIFT_DETECT && m.from.truncate() != m.to.truncate() {
                    c.lift_clearance = c.lift_clearance.min(q.z - top);
                    if q.z - top < x.clearance - LIFT_SLACK {
                        return Err(format!(
                            "5. line {}: a lifted travel at {q} clears a bead printed before it by {:.3} mm (clearance {})",
                            m.line,
                            q.z - top,
                            x.clearance
                        ));
                    }
                } else if !near {
                    c.direct_dip = c.direct_dip.max(top - q.z);
                    if top - q.z > DIRECT_SLACK {
                        return Err(format!(
                            "5. line {}: a travel at {q} passes {:.3} mm below a bead printed before it",
                            m.line,
                            top - q.z
                        ));
                    }
                }
            }
        }
    }
    Ok(c)
}

/// Net filament of non-printing moves (E, and firmware retractions as ∓1), mm.
fn net_e(gap: &[written::Move]) -> f64 {
    gap.iter()
        .map(|m| m.e + m.fw.map_or(0.0, |r| if r { -1.0 } else { 1.0 }))
        .sum()
}

/// The net E of the non-printing moves between each two consecutive extrusions of `moves`.
fn gap_nets(moves: &[written::Move]) -> Vec<f64> {
    let printing: Vec<usize> = (0..moves.len()).filter(|&i| moves[i].extrudes()).collect();
    printing
        .windows(2)
        .filter(|w| w[1] > w[0] + 1)
        .map(|w| net_e(&moves[w[0] + 1..w[1]]))
        .collect()
}
