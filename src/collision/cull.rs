//! Which cells of the height field a posed head part may reach: exact culls that skip the
//! per-cell work ([`super::sweep`]) for cells that cannot give a finding.
//!
//! A cell with material top `h` gives a finding only when more than `tol`
//! ([`super::sweep::CONTACT_TOLERANCE_MM`]) of its column lies inside the part (and, for the
//! nozzle, above its contact surface). For a block of cells whose highest top is `top`, let
//! `m = top − tol`; a cell can give a finding only where
//!
//! - the solid reaches below `m`: within the disc [`Posed::disc_below`] (outside it the solid
//!   lies above `m`, so at most `h − m ≤ tol` of the column is inside it);
//! - for the nozzle, the region above its contact surface reaches below `m`: within
//!   [`ContactSurface::disc_below`], and on each row within the x-interval
//!   [`ContactSurface::above_on_row`] at height `m` (the region above the surface on a
//!   vertical line is one interval ending at the top, so a point `(x, y, m)` under the surface
//!   leaves at most `h − m ≤ tol` of the column above it).
//!
//! A block is skipped when the part's floor over its square ([`Posed::floor_over_square`],
//! [`ContactSurface::floor_over_square`]) is above its highest top but for `tol`, when no point
//! of its square at height `m` lies above the nozzle's contact surface (the concave `excess`
//! under its tangent plane at the square's centre, [`ContactSurface::excess_over_square`]; the
//! surface's rule applying, every point of a line under `m` is then under it too), when its
//! square meets no such disc, or when the solid's distance from
//! the block's bounding sphere ([`Posed::distance`]) says it cannot reach it. The search for
//! one pose's deepest overlap raises `tol` to the deepest depth found so far
//! ([`Reach::raise`]): a later cell replaces the deepest only when it is deeper. Every cut
//! removes only cells the per-cell test rejects, so the findings are the same with and without
//! it (law tests: `tests/collision_check.rs` against [`super::Checker::exhaustive`], and
//! `sweep.rs`'s `a_stretch_lists_every_cell_any_of_its_poses_reaches`).

use glam::{DVec2, DVec3};

use super::contact::ContactSurface;
use super::solid::{square_distance, Posed};

/// Added to a disc's radius and chord, mm: the cut and the per-cell test compute the same
/// distances in f64; this keeps a cell centre that lies on a circle (to rounding) in.
const DISC_SLACK_MM: f64 = 1e-9;

/// A posed part (and the nozzle's contact surface) seen by the height field's cells.
pub struct Reach<'a> {
    /// The part at its pose (possibly grown over a stretch of poses).
    solid: &'a Posed,
    /// The nozzle's contact surface, where its rule applies.
    contact: Option<&'a ContactSurface>,
    /// The depth a cell must exceed to matter, mm: the tolerance
    /// ([`super::sweep::CONTACT_TOLERANCE_MM`]), raised by [`Reach::raise`] to the deepest
    /// overlap found so far when only a deeper one can change the result.
    bar: std::cell::Cell<f64>,
    /// The solid's lowest point's height, mm (the block's bounding sphere spans from it).
    zlow: f64,
    /// Whether the solid's floor over a block can be above its lowest point (a frustum, a box
    /// not standing square: else the floor test repeats the query's own "above the lowest
    /// point" and is skipped).
    floor_varies: bool,
}

impl<'a> Reach<'a> {
    /// The reach of `solid` (and `contact`) for depths above `tol`; `zlow` the solid's lowest
    /// height (its [`Posed::aabb`]'s, which the caller has).
    pub fn new(
        solid: &'a Posed,
        contact: Option<&'a ContactSurface>,
        tol: f64,
        zlow: f64,
    ) -> Reach<'a> {
        Reach {
            solid,
            contact,
            bar: std::cell::Cell::new(tol),
            zlow,
            floor_varies: !solid.floor_is_flat(),
        }
    }
    /// Count only depths above `depth` from now on (when it exceeds the bar): the search for
    /// the deepest overlap of one pose ([`super::Checker`]'s `penetrations`) keeps the first
    /// cell of the greatest depth, and a cell no deeper than the deepest found before it cannot
    /// replace it. Every test here bounds a cell's depth from above by `top − m` for a height
    /// `m` the part (or the region above the contact surface) does not come below; with
    /// `m = top − bar` a skipped cell's depth is at most the bar.
    pub fn raise(&self, depth: f64) {
        if depth > self.bar.get() {
            self.bar.set(depth);
        }
    }

    fn discs(&self, m: f64) -> [Option<(DVec2, f64)>; 2] {
        [
            self.solid.disc_below(m),
            self.contact.and_then(|c| c.disc_below(m)),
        ]
    }

    /// The part of `rect` whose cells may give a finding when the highest material top in it
    /// is `m + tol` (`None`: none): within the solid's [`Posed::below_in_rect`] and the
    /// contact surface's disc below `m`.
    pub fn rect(&self, rect: (f64, f64, f64, f64), m: f64) -> Option<(f64, f64, f64, f64)> {
        let (mut x0, mut y0, mut x1, mut y1) = self.solid.below_in_rect(rect, m)?;
        if let Some((o, r)) = self.contact.and_then(|c| c.disc_below(m)) {
            let r = r + DISC_SLACK_MM;
            (x0, y0) = (x0.max(o.x - r), y0.max(o.y - r));
            (x1, y1) = (x1.min(o.x + r), y1.min(o.y + r));
        }
        (x0 <= x1 && y0 <= y1).then_some((x0, y0, x1, y1))
    }

    /// Whether no cell of the block (centre `c`, half diagonal `half_diag` seen from above,
    /// highest top `top`) can give a finding.
    pub fn skips_block(&self, c: DVec2, half_diag: f64, top: f64) -> bool {
        let half = half_diag * std::f64::consts::FRAC_1_SQRT_2;
        // the part (and the region above the contact surface) enters every line of the block
        // above its highest top, but for tol
        let mut floor = if self.floor_varies {
            self.solid.floor_over_square(c, half)
        } else {
            f64::NEG_INFINITY
        };
        if let Some(k) = self.contact {
            floor = floor.max(k.floor_over_square(c, half));
        }
        // (every line enters the solid at or above its lowest point)
        if top - floor.max(self.zlow) <= self.bar.get() {
            return true;
        }
        // the region above the contact surface misses the square at `top − tol`, hence below
        // it (where the rule applies, "above" is the top of each vertical line)
        if self.contact.is_some_and(|k| {
            k.applies() && k.excess_over_square(c, half, top - self.bar.get()) <= -DISC_SLACK_MM
        }) {
            return true;
        }
        let far_from_disc = self
            .discs(top - self.bar.get())
            .iter()
            .flatten()
            .any(|(o, r)| square_distance(*o, c, half) > r + DISC_SLACK_MM);
        if far_from_disc {
            return true;
        }
        let centre = DVec3::new(c.x, c.y, 0.5 * (self.zlow + top));
        let dz = 0.5 * (top - self.zlow);
        self.solid.distance(centre) > (half_diag * half_diag + dz * dz).sqrt() + DISC_SLACK_MM
    }

    /// The x-interval of the row `y` of a block of highest top `top` whose cells may give a
    /// finding (`None`: none).
    pub fn row(&self, y: f64, top: f64) -> Option<(f64, f64)> {
        let m = top - self.bar.get();
        if m <= self.zlow {
            return None;
        }
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        // the contact surface's interval first: on a row beside a tilted nozzle it is often
        // empty, and the discs' chords (two radii, a square root each) are then not needed;
        // the interval is the intersection either way (max and min round nothing)
        if let Some(c) = self.contact {
            (lo, hi) = c.above_on_row(y, m)?;
        }
        for (o, r) in self.discs(m).iter().flatten() {
            let dy = y - o.y;
            let r = r + DISC_SLACK_MM;
            let chord2 = r * r - dy * dy;
            if chord2 < 0.0 {
                return None;
            }
            let half = chord2.sqrt() + DISC_SLACK_MM;
            lo = lo.max(o.x - half);
            hi = hi.min(o.x + half);
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// The x-interval of the row `y` whose points lie within `r` (seen from above) of the segment
/// from `a` to `a + d` (`None`: none), widened by [`DISC_SLACK_MM`]: the row's chord of the
/// capsule, the cells of a translating part's row that may lie under its floor
/// (`super::sweep`, the swept cells). The capsule is convex, the union of the discs about the
/// two ends and the band `{q : 0 ≤ t(q) ≤ 1, |e(q)| ≤ r}` (`t = (q − a)·d/|d|²` the
/// projection's parameter, `e = (q − a) × d/|d|` the signed distance from the line); on the
/// row both are linear in x, so the band's part is an interval cut by four half-lines, each
/// disc's a chord, and the capsule's chord the hull of the three.
pub fn capsule_row(a: DVec2, d: DVec2, r: f64, y: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for c in [a, a + d] {
        let dy = y - c.y;
        let chord2 = r * r - dy * dy;
        if chord2 >= 0.0 {
            let h = chord2.sqrt();
            lo = lo.min(c.x - h);
            hi = hi.max(c.x + h);
        }
    }
    let l2 = d.length_squared();
    if l2 > 0.0 {
        // on the row q = (x, y): t·|d|² = (x − a_x) d_x + (y − a_y) d_y ∈ [0, |d|²] and
        // e·|d| = (x − a_x) d_y − (y − a_y) d_x ∈ [−r|d|, r|d|]: α x + β ∈ [u, v] each
        let l = l2.sqrt();
        let dy = y - a.y;
        let (mut blo, mut bhi) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut empty = false;
        for (alpha, beta, u, v) in [
            (d.x, -a.x * d.x + dy * d.y, 0.0, l2),
            (d.y, -a.x * d.y - dy * d.x, -r * l, r * l),
        ] {
            if alpha == 0.0 {
                empty |= beta < u || beta > v;
            } else {
                let (x0, x1) = ((u - beta) / alpha, (v - beta) / alpha);
                blo = blo.max(x0.min(x1));
                bhi = bhi.min(x0.max(x1));
            }
        }
        if !empty && blo <= bhi {
            lo = lo.min(blo);
            hi = hi.max(bhi);
        }
    }
    (lo <= hi).then_some((lo - DISC_SLACK_MM, hi + DISC_SLACK_MM))
}

/// The tips of a translation's checked poses (the pose fixed, the tip moving along the segment
/// from `a` by `d`, seen from above), to find at which of them a cell lies within a radius of
/// the tip without measuring its distance to every one ([`super::Checker`]'s per-pose lists of
/// a translation).
///
/// ## The bound
/// Each tip `q_k` has the parameter `t_k = (q_k − a)·d / |d|²` of its foot `f_k = a + t_k d`
/// on the path's line, and lies `δ_k = |q_k − f_k|` off it (0 to rounding for a translation;
/// `δ = max δ_k` is measured, not assumed). For a cell `c` with foot parameter `t_c` and
/// distance `e` from the line, Pythagoras on the line gives `|c − f_k|² = e² + (t_k − t_c)²|d|²`,
/// and the triangle inequality `|c − q_k| ≥ |c − f_k| − δ`. So `|c − q_k| ≤ r` implies
/// `e² + (t_k − t_c)²|d|² ≤ (r + δ)²`: `|t_k − t_c| ≤ √((r + δ)² − e²) / |d|`, an interval of
/// `t`, and with the `t_k` in order (checked) a range of the tips.
#[derive(Clone, Debug)]
pub struct TipLine {
    a: DVec2,
    d: DVec2,
    l2: f64,
    /// The tips' parameters, non-decreasing.
    t: Vec<f64>,
    /// `δ`: the farthest tip from the line, mm.
    off: f64,
}

impl TipLine {
    /// The tips `tips` of a path from `a` by `d` (`None` when the path has no horizontal
    /// length or the tips' parameters are not in order: the caller then checks every tip).
    pub fn new(a: DVec2, d: DVec2, tips: &[DVec2]) -> Option<TipLine> {
        let l2 = d.length_squared();
        if l2 <= 0.0 || !l2.is_finite() {
            return None;
        }
        let mut off = 0.0f64;
        let mut t = Vec::with_capacity(tips.len());
        for q in tips {
            let tk = (*q - a).dot(d) / l2;
            off = off.max((*q - (a + d * tk)).length());
            t.push(tk);
        }
        if t.windows(2).any(|w| w[1] < w[0]) || !off.is_finite() {
            return None;
        }
        Some(TipLine { a, d, l2, t, off })
    }

    /// The range of the tips (indices into `tips` of [`TipLine::new`]) that may lie within `r`
    /// of `c` horizontally: every tip within `r` is in it (see the type's documentation; the
    /// radius gets [`DISC_SLACK_MM`] for rounding).
    pub fn within(&self, c: DVec2, r: f64) -> std::ops::Range<usize> {
        let tc = (c - self.a).dot(self.d) / self.l2;
        let e = (c - (self.a + self.d * tc)).length();
        let big = r + self.off + DISC_SLACK_MM;
        if e > big {
            return 0..0;
        }
        let hw = ((big * big - e * e).max(0.0) / self.l2).sqrt();
        let lo = self.t.partition_point(|&t| t < tc - hw);
        let hi = self.t.partition_point(|&t| t <= tc + hw);
        lo..hi.max(lo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point of a row within `r` of the segment (the distance to the segment from the
    /// clamped projection, `crate::emit::clearance::segment_distance`) lies in the row's interval, and the interval's
    /// ends are such points (within the grid step): random segments, radii and rows, a 0.001 mm
    /// grid along each row.
    #[test]
    fn a_capsules_row_interval_holds_every_point_within_the_radius_and_little_else() {
        let mut seed = 99u64;
        let mut rnd = |lo: f64, hi: f64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
        };
        // the distance to the segment: the travel planner's (not the code checked here)
        let dist =
            |a: DVec2, d: DVec2, q: DVec2| crate::emit::clearance::segment_distance(q, a, a + d);
        let mut rows_met = 0;
        for k in 0..400 {
            let a = DVec2::new(rnd(-2.0, 2.0), rnd(-2.0, 2.0));
            let d = match k % 4 {
                0 => DVec2::ZERO,
                1 => DVec2::new(rnd(-3.0, 3.0), 0.0),
                2 => DVec2::new(0.0, rnd(-3.0, 3.0)),
                _ => DVec2::new(rnd(-3.0, 3.0), rnd(-3.0, 3.0)),
            };
            let r = rnd(0.05, 2.0);
            let y = rnd(-5.0, 5.0);
            let xs: Vec<f64> = (-8000..=8000)
                .map(|i| i as f64 * 0.001)
                .filter(|&x| dist(a, d, DVec2::new(x, y)) <= r)
                .collect();
            match capsule_row(a, d, r, y) {
                None => assert!(xs.is_empty(), "case {k}: None but {} points", xs.len()),
                Some((lo, hi)) => {
                    rows_met += 1;
                    for &x in &xs {
                        assert!(x >= lo && x <= hi, "case {k}: {x} outside [{lo}, {hi}]");
                    }
                    if let (Some(f), Some(l)) = (xs.first(), xs.last()) {
                        assert!(
                            f - lo <= 0.0011 && hi - l <= 0.0011,
                            "case {k}: [{lo}, {hi}] vs [{f}, {l}]"
                        );
                    }
                }
            }
        }
        assert!(rows_met > 100, "only {rows_met} rows met a capsule");
    }

    /// Every tip within `r` of a cell (measured directly, `DVec2::distance`) is in
    /// [`TipLine::within`]'s range: random paths with tips off the line by up to 0.05 mm, in
    /// order along it, random cells and radii; and the range is not the whole set of tips for
    /// most of the cells far from the path.
    #[test]
    fn a_tip_lines_range_holds_every_tip_within_the_radius() {
        let mut seed = 7u64;
        let mut rnd = |lo: f64, hi: f64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
        };
        let (mut met, mut narrowed) = (0, 0);
        for case in 0..300 {
            let a = DVec2::new(rnd(-5.0, 5.0), rnd(-5.0, 5.0));
            let d = DVec2::new(rnd(-20.0, 20.0), rnd(-20.0, 20.0));
            let normal = d.perp().normalize();
            let n = 2 + (rnd(0.0, 60.0) as usize);
            let jitter = if case % 2 == 0 { 0.0 } else { 0.05 };
            let tips: Vec<DVec2> = (0..n)
                .map(|k| a + d * (k as f64 / (n - 1) as f64) + normal * rnd(-jitter, jitter))
                .collect();
            let Some(line) = TipLine::new(a, d, &tips) else {
                panic!("case {case}: tips in order refused");
            };
            for _ in 0..50 {
                let c = a + d * rnd(-0.3, 1.3) + normal * rnd(-4.0, 4.0);
                let r = rnd(0.0, 5.0);
                let range = line.within(c, r);
                for (k, q) in tips.iter().enumerate() {
                    if q.distance(c) <= r {
                        met += 1;
                        assert!(
                            range.contains(&k),
                            "case {case}: tip {k} at {q} is {} from {c} (r {r}) but outside {range:?}",
                            q.distance(c)
                        );
                    }
                }
                narrowed += usize::from(range.len() < n / 2);
            }
        }
        assert!(
            met > 1000 && narrowed > 3000,
            "met {met}, narrowed {narrowed}"
        );
    }
}
