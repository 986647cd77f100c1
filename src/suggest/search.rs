//! The deterministic search of `suggest`: a coarse grid over each family's parameters, then a
//! pattern search (coordinate steps, halved when no neighbour improves) from the best grid
//! points of each family, each with and without the flat base blend, over the admissible set.
//!
//! Order: a candidate ranks before another by smaller overhang area (to 10⁻⁶ mm²), then by
//! smaller largest tilt, then by family and flags, so equal inputs give equal lists.
//!
//! Cost: every candidate costs one tool-axis evaluation per facet that can overhang at the
//! search's largest tilt ([`crate::overhang::Facets::that_can_overhang`]) and per coarse
//! sample ([`super::model::Model::coarse_samples`]); a few hundred candidates in all.

use std::cmp::Ordering;
use std::collections::BTreeMap;

use super::admissible::{admissible, MachineLimits};
use super::family::{flags, resolution, Family, Point};
use super::model::Model;
use crate::machine::LIMIT_SLACK_DEG;
use crate::overhang::Facets;
use crate::warp::{Direction, WarpParams};

/// The steepest layers the search tries, degrees from horizontal (and the tilt bound on
/// machines without a limit, such as the 3-axis printer): a 60° cone already stretches the
/// warped part to twice its height (tan 60° ≈ 1.73 per mm of radius).
pub const MAX_SEARCH_TILT_DEG: f64 = 60.0;

/// The coarse grid's layer angles, degrees (the machine's limit and fixed tilt are added).
pub const GRID_ANGLES_DEG: &[f64] = &[10.0, 20.0, 30.0, 40.0, 50.0, 60.0];
/// The coarse grid's strengths of the curved warp (its tilt at the far edge is atan 2s).
pub const GRID_STRENGTHS: &[f64] = &[0.1, 0.2, 0.35, 0.5, 0.7];
/// The coarse grid's belt directions, degrees (azimuth of `toward`).
pub const GRID_AZIMUTHS_DEG: &[f64] = &[0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0];
/// The pattern search moves only for this share of the planar overhang area or more (a
/// step that gains less is noise on a smooth model and costs a measure per neighbour).
pub const REFINE_MIN_GAIN: f64 = 1e-3;
/// The pattern search moves to an equal area for this much less tilt or more, degrees.
pub const TILT_GAIN_DEG: f64 = 0.05;
/// Most facets the coarse grid's area estimate sums.
pub const ROUGH_FACETS: usize = 20_000;
/// Grid points of each family × direction the pattern search starts from.
pub const STARTS_PER_GROUP: usize = 2;
/// Grid points the conic family's pattern search starts from, per direction: its space has a
/// 2-D centre besides the angle, with more local minima (np_moon on the triple-Z bed: from
/// two starts the best cone left 0.118 mm², 9 % over the brute-force grid's 0.108; from three,
/// 0.078).
pub const CONIC_STARTS_PER_GROUP: usize = 3;
/// Areas within this of each other tie (then the smaller tilt ranks first), mm²; also the
/// slack of the pattern search's cutoff.
pub const AREA_TIE_MM2: f64 = 1e-6;
/// Halvings of the pattern search's steps before it stops (a 5° first step ends at 0.3°).
pub const HALVINGS: usize = 4;
/// The base-blend variant of a refined warp starts its pattern search at this halving (it
/// starts near the warp it varies).
pub const BASE_FIRST_HALVING: usize = 2;

/// No step below its coordinate's resolution (a smaller one rounds back to the same warp: on
/// a model a few mm wide, wx/8 can be).
fn floor_at_resolution(steps: &mut [f64; 3], family: Family) {
    for (s, r) in steps.iter_mut().zip(resolution(family)) {
        if *s != 0.0 {
            *s = s.max(r);
        }
    }
}

/// One measured, admissible (at the coarse samples) candidate.
#[derive(Clone, Debug)]
pub struct Scored {
    /// The point of its family's space.
    pub point: Point,
    /// The warp.
    pub params: WarpParams,
    /// The flags that give it to `warpslice warp`.
    pub flags: String,
    /// Its overhang area, mm².
    pub area_mm2: f64,
    /// Its largest tilt over the coarse samples, degrees.
    pub largest_tilt_deg: f64,
}

impl Scored {
    /// The ranking order (see the module documentation).
    pub fn rank(&self, other: &Scored) -> Ordering {
        let q = |v: f64| (v / AREA_TIE_MM2).round();
        q(self.area_mm2)
            .total_cmp(&q(other.area_mm2))
            .then(q(self.largest_tilt_deg).total_cmp(&q(other.largest_tilt_deg)))
            .then(self.point.family.cmp(&other.point.family))
            .then(self.flags.cmp(&other.flags))
    }
}

/// The search over one model and machine.
#[derive(Clone)]
pub struct Search<'a> {
    pub(super) model: &'a Model,
    pub(super) limits: &'a MachineLimits,
    pub(super) overhang_angle_deg: f64,
    pub(super) layer_height: f64,
    /// The steepest layer angle tried, degrees.
    pub(super) bound_deg: f64,
    /// The machine's fixed tilt (rotating nozzles), else 0, degrees.
    pub(super) fixed_deg: f64,
    /// The facets that can overhang at tilts up to `bound_deg`.
    pub(super) subset: Facets,
    /// Every k-th of `subset` with its area ×k (at most [`ROUGH_FACETS`]): the coarse grid's
    /// estimate, which only picks where the pattern search starts.
    rough: Facets,
    /// Every candidate measured, by flags (`None`: not admissible).
    seen: BTreeMap<String, Option<Scored>>,
    /// The fitted field's objective after each sweep of its pattern search ([`super::fit`]).
    pub(super) fit_trace: Vec<f64>,
    /// The least area gain the pattern search moves for, mm² ([`REFINE_MIN_GAIN`] of the
    /// planar overhang, at least [`AREA_TIE_MM2`]).
    pub(super) min_gain: f64,
    /// Candidates whose area passed a cutoff before it was summed, by flags: the cutoff, mm².
    cut: BTreeMap<String, f64>,
}

impl<'a> Search<'a> {
    /// A search on `model` for `limits` with the printable angle `overhang_angle_deg` and the
    /// layer height `layer_height` (mm, the anchor rule).
    pub fn new(
        model: &'a Model,
        limits: &'a MachineLimits,
        overhang_angle_deg: f64,
        layer_height: f64,
    ) -> Search<'a> {
        let bound_deg = limits
            .capabilities
            .max_tilt_deg
            .map_or(MAX_SEARCH_TILT_DEG, |m| m.min(MAX_SEARCH_TILT_DEG));
        let fixed_deg = limits.capabilities.fixed_tilt_deg.unwrap_or(0.0);
        let subset = model
            .facets
            .that_can_overhang(overhang_angle_deg, bound_deg.max(fixed_deg));
        let min_gain =
            (REFINE_MIN_GAIN * subset.area(None, overhang_angle_deg).0).max(AREA_TIE_MM2);
        let rough = subset.every_kth(subset.areas.len().div_ceil(ROUGH_FACETS).max(1));
        Search {
            model,
            rough,
            limits,
            overhang_angle_deg,
            layer_height,
            bound_deg,
            fixed_deg,
            subset,
            min_gain,
            seen: BTreeMap::new(),
            cut: BTreeMap::new(),
            fit_trace: Vec::new(),
        }
    }

    /// Measure a point (cached by its flags): `None` when it is outside its family's range, not
    /// admissible at the coarse samples, or (with a finite `cutoff`, mm²) when its overhang
    /// area passes `cutoff` (it cannot beat the warp the cutoff came from).
    pub fn eval(&mut self, point: Point, cutoff: f64) -> Option<Scored> {
        let point = point.rounded();
        let params = point.params(&self.model.bbox)?;
        self.measure(point, params, cutoff)
    }

    /// [`Search::eval`] of a warp given as its parameters (`point` names its family, direction
    /// and base: the fitted field's, which has no coordinates).
    pub fn measure(&mut self, point: Point, params: WarpParams, cutoff: f64) -> Option<Scored> {
        let key = flags(&params);
        if let Some(s) = self.seen.get(&key) {
            return s.clone();
        }
        // area > c ≥ cutoff: cut again (against a larger cutoff it is measured anew)
        if self.cut.get(&key).is_some_and(|&c| c >= cutoff) {
            return None;
        }
        let bound = self.bound_deg.max(self.fixed_deg) + LIMIT_SLACK_DEG;
        let admitted = match admissible(
            &params,
            self.model,
            self.limits,
            &self.model.coarse_samples,
            self.layer_height,
        ) {
            Ok(a) if a.largest_tilt_deg <= bound => a,
            _ => {
                self.seen.insert(key, None);
                return None;
            }
        };
        let Some((area_mm2, _)) = self.subset.area_up_to(
            Some(admitted.warp.as_ref()),
            self.overhang_angle_deg,
            cutoff,
        ) else {
            self.cut.insert(key, cutoff);
            return None;
        };
        let scored = Scored {
            point,
            flags: key.clone(),
            area_mm2,
            largest_tilt_deg: admitted.largest_tilt_deg,
            params,
        };
        self.seen.insert(key, Some(scored.clone()));
        Some(scored)
    }

    /// The layer angles of the coarse grid: [`GRID_ANGLES_DEG`] up to the bound, the bound
    /// itself and the machine's fixed tilt.
    fn angles(&self) -> Vec<f64> {
        let mut v: Vec<f64> = GRID_ANGLES_DEG
            .iter()
            .copied()
            .filter(|&a| a <= self.bound_deg)
            .collect();
        v.push(self.bound_deg);
        if let Some(f) = self.limits.capabilities.fixed_tilt_deg {
            v.push(f);
        }
        v.sort_by(f64::total_cmp);
        v.dedup();
        v.retain(|&a| a > 0.0 && a < 90.0);
        v
    }

    /// The coarse grid of `family`.
    pub fn grid(&self, family: Family) -> Vec<Point> {
        let size = self.model.bbox.size();
        let (wx, wy) = (size.x, size.y);
        let [bx, by] = self.model.bed_centroid;
        let dirs = [Direction::Outward, Direction::Inward];
        let offsets = [-wx / 2.0, -wx / 4.0, 0.0, wx / 4.0, wx / 2.0, -bx];
        let mut out = Vec::new();
        let point = |direction, x| Point {
            family,
            direction,
            x,
            base: false,
        };
        match family {
            Family::Conic => {
                let centres = [
                    [0.0, 0.0],
                    [wx / 4.0, 0.0],
                    [-wx / 4.0, 0.0],
                    [0.0, wy / 4.0],
                    [0.0, -wy / 4.0],
                    [bx, by],
                ];
                for d in dirs {
                    for a in self.angles() {
                        for c in centres {
                            out.push(point(d, [a, c[0], c[1]]));
                        }
                    }
                }
            }
            Family::Belt => {
                for a in self.angles() {
                    for &z in GRID_AZIMUTHS_DEG {
                        out.push(point(Direction::Outward, [a, z, 0.0]));
                    }
                }
            }
            Family::Curved => {
                for d in dirs {
                    for &s in GRID_STRENGTHS {
                        for o in offsets {
                            out.push(point(d, [s, o, 0.0]));
                        }
                    }
                }
            }
            Family::Tilted => {
                for d in dirs {
                    for a in self.angles() {
                        for o in offsets {
                            out.push(point(d, [a, o, 0.0]));
                        }
                    }
                }
            }
            // fitted from the others' best ([`super::fit`]), not gridded
            Family::Field => {}
        }
        out
    }

    /// The pattern search's first steps for `family`'s coordinates.
    fn steps(&self, family: Family) -> [f64; 3] {
        let size = self.model.bbox.size();
        match family {
            Family::Conic => [5.0, size.x / 8.0, size.y / 8.0],
            Family::Belt => [5.0, 22.5, 0.0],
            Family::Curved => [0.05, size.x / 8.0, 0.0],
            Family::Tilted => [5.0, size.x / 8.0, 0.0],
            Family::Field => [0.0; 3],
        }
    }

    /// Improve `start` by coordinate steps (sweeping the coordinates and moving to each
    /// neighbour that [improves](Search::improves), then trying two coordinates at once, else
    /// halving the steps, up to [`HALVINGS`] times), the steps halved `first_halving` times to
    /// begin with.
    pub fn refine(&mut self, start: Scored, first_halving: usize) -> Scored {
        let mut best = start;
        let mut steps = self.steps(best.point.family);
        for s in &mut steps {
            *s /= (1u32 << first_halving) as f64;
        }
        floor_at_resolution(&mut steps, best.point.family);
        for _ in first_halving..=HALVINGS {
            // sweep the coordinates, moving at once to any neighbour that improves
            loop {
                let mut moved = false;
                for (k, &step) in steps.iter().enumerate() {
                    if step == 0.0 {
                        continue;
                    }
                    for sign in [-1.0, 1.0] {
                        let mut p = best.point;
                        p.x[k] += sign * step;
                        let bar = best.area_mm2 + AREA_TIE_MM2;
                        if let Some(s) = self.eval(p, bar) {
                            if self.improves(&s, &best) {
                                best = s;
                                moved = true;
                            }
                        }
                    }
                }
                // no single coordinate helps: try two at once (a cone's angle with its centre)
                if !moved {
                    moved = self.diagonal_move(&mut best, &steps);
                }
                if !moved {
                    break;
                }
            }
            for s in &mut steps {
                *s /= 2.0;
            }
            floor_at_resolution(&mut steps, best.point.family);
        }
        best
    }

    /// Move `best` to the first improving neighbour that changes two coordinates by their
    /// steps at once; whether one did.
    fn diagonal_move(&mut self, best: &mut Scored, steps: &[f64; 3]) -> bool {
        for i in 0..3 {
            for j in i + 1..3 {
                if steps[i] == 0.0 || steps[j] == 0.0 {
                    continue;
                }
                for (si, sj) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
                    let mut p = best.point;
                    p.x[i] += si * steps[i];
                    p.x[j] += sj * steps[j];
                    let bar = best.area_mm2 + AREA_TIE_MM2;
                    if let Some(s) = self.eval(p, bar) {
                        if self.improves(&s, best) {
                            *best = s;
                            return true;
                        }
                    }
                }
            }
        }
        false
    }

    /// Whether the pattern search moves from `best` to `s`: at least `min_gain` less overhang,
    /// or as little with [`TILT_GAIN_DEG`] less tilt.
    fn improves(&self, s: &Scored, best: &Scored) -> bool {
        s.area_mm2 < best.area_mm2 - self.min_gain
            || (s.area_mm2 <= best.area_mm2 + AREA_TIE_MM2
                && s.largest_tilt_deg < best.largest_tilt_deg - TILT_GAIN_DEG)
    }

    /// The coarse grid's estimate of a point: its overhang area on the rough facets (`None`:
    /// out of range or not admissible at the coarse samples). Not cached: only the ranking of
    /// the grid uses it.
    fn estimate(&self, point: Point) -> Option<(Point, f64)> {
        let point = point.rounded();
        let params = point.params(&self.model.bbox)?;
        let bound = self.bound_deg.max(self.fixed_deg) + LIMIT_SLACK_DEG;
        let a = admissible(
            &params,
            self.model,
            self.limits,
            &self.model.coarse_samples,
            self.layer_height,
        )
        .ok()
        .filter(|a| a.largest_tilt_deg <= bound)?;
        let area = self
            .rough
            .area(Some(a.warp.as_ref()), self.overhang_angle_deg)
            .0;
        Some((point, area))
    }

    /// Run the search over `families`; returns every admissible candidate measured in full,
    /// best first. The pattern search starts from the best grid point (by the rough estimate)
    /// of each family × direction ([`STARTS_PER_GROUP`], [`CONIC_STARTS_PER_GROUP`]), then from its result with the base
    /// blend.
    pub fn run(&mut self, families: &[Family]) -> Vec<Scored> {
        let searched: Vec<Family> = families
            .iter()
            .copied()
            .filter(|&f| self.limits.prints(f) && f != Family::Field)
            .collect();
        // Natively each family is searched in its own thread, on a copy of the search: a
        // family's candidates (flags that begin with its `--warp`) and their memo are its own,
        // so the merged maps — ordered by flags — are the sequential search's, and the ranking
        // below does not depend on which thread finished first. wasm has no threads here: one
        // after another.
        #[cfg(not(target_arch = "wasm32"))]
        {
            let found: Vec<Search<'a>> = std::thread::scope(|scope| {
                let threads: Vec<_> = searched
                    .iter()
                    .map(|&family| {
                        let mut copy = self.clone();
                        scope.spawn(move || {
                            copy.search_family(family);
                            copy
                        })
                    })
                    .collect();
                threads
                    .into_iter()
                    .map(|t| t.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                    .collect()
            });
            for copy in found {
                self.seen.extend(copy.seen);
                self.cut.extend(copy.cut);
            }
        }
        #[cfg(target_arch = "wasm32")]
        for &family in &searched {
            self.search_family(family);
        }
        if families.contains(&Family::Field) && self.limits.prints(Family::Field) {
            let mut ranked: Vec<Scored> = self.seen.values().flatten().cloned().collect();
            ranked.sort_by(|a, b| a.rank(b));
            // the best of each family starts the fit
            let mut starts: Vec<Scored> = Vec::new();
            for c in ranked {
                if !starts.iter().any(|s| s.point.family == c.point.family) {
                    starts.push(c);
                }
            }
            self.fit_field(&starts);
        }
        let mut all: Vec<Scored> = self.seen.values().flatten().cloned().collect();
        all.sort_by(|a, b| a.rank(b));
        all
    }

    /// One family's search: the coarse grid's estimates, then the pattern search from the best
    /// grid points of each direction, each also with the base blend.
    fn search_family(&mut self, family: Family) {
        let mut coarse: Vec<(Point, f64)> = self
            .grid(family)
            .into_iter()
            .filter_map(|p| self.estimate(p))
            .collect();
        coarse.sort_by(|a, b| a.1.total_cmp(&b.1));
        let mut starts = Vec::new();
        for d in [Direction::Outward, Direction::Inward] {
            starts.extend(
                coarse
                    .iter()
                    .filter(|c| c.0.direction == d)
                    .take(if family == Family::Conic {
                        CONIC_STARTS_PER_GROUP
                    } else {
                        STARTS_PER_GROUP
                    })
                    .filter_map(|c| self.eval(c.0, f64::INFINITY)),
            );
        }
        for start in starts {
            let flat = self.refine(start, 0);
            let mut with_base = flat.point;
            with_base.base = true;
            if let Some(b) = self.eval(with_base, f64::INFINITY) {
                self.refine(b, BASE_FIRST_HALVING);
            }
        }
    }

    /// How many distinct candidates were measured.
    pub fn measured(&self) -> usize {
        self.seen.len()
    }
}
