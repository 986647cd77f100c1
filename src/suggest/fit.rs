//! The fitted field of `suggest` (issue 15 item 3a): a bicubic B-spline height g over the
//! footprint ([`crate::warp::spline`]) that leaves no more overhang than the best warp of the
//! seed families, found by a pattern search on its coefficients.
//!
//! **Objective** J(c) = A(c) + λ·R(c): A the overhang area left (mm², the search's measure on the
//! facets that can overhang, [`crate::overhang::Facets`]), R = Σ ((Δ²ₓc)² + (Δ²ᵧc)²)/h² over the
//! interior knots (dimensionless: the squared change of slope between neighbouring cells, a
//! discrete ∫|∇²g|²) and λ = [`SMOOTHNESS_GAINS`] × the least area gain the family search moves
//! for, so smoothness only decides between fields that leave about the same area.
//!
//! **Constraints**: every candidate is measured only when admissible at the coarse samples
//! ([`super::admissible`]: the machine's tilt limit, i.e. |∇g| ≤ tan(limit) without a base
//! blend, its realised axis, the base blend's monotonicity — the field keeps the start's
//! blend — and the anchor rule), and a move must not leave more overhang than the larger of
//! the best family warp's and the current field's: so a fit whose start leaves no more than
//! the family warp ends no worse.
//!
//! **The field**: g = g_family + Σ c·B — a B-spline correction over a family warp
//! ([`crate::warp::over`], the `--over` flag), or a B-spline alone.
//!
//! **Solver**: the starts are, first, each family's best warp **exactly** (as the family part,
//! all c = 0: the same g, so J = its area, and the fit starts at the family optimum and can only
//! improve — a B-spline alone rounds a cone's apex off and left more than the cone on the
//! sphere), then the family warps' g sampled at the knots with no family part (c = g(knot): a
//! B-spline with those coefficients keeps each of g's slopes along x and y within their range;
//! at each of [`START_SCALES`], scaled down by [`START_SHRINK`] until admissible); the start of
//! least J wins; then a pattern search: each
//! coefficient in turn moves by ±step to the first neighbour that lowers J by more than the
//! tie (the correction's coefficients only; the family part stays), sweeps repeat until none
//! moves, then the step halves ([`FIT_HALVINGS`] times).
//! **Cost**: one measure per candidate (a tool axis per coarse sample and per facet that can
//! overhang, like one family candidate), at most [`MAX_FIT_EVALS`] candidates and
//! [`FIT_FACET_BUDGET`] facet measures in all; J is
//! non-increasing sweep by sweep (the trace is [`super::search::Search::fit_trace`]).

use super::family::{Family, Point};
use super::search::{Scored, Search, AREA_TIE_MM2};
use crate::warp::spline::Spline;
use crate::warp::{Direction, WarpParams, WarpSpec};

/// Cells of the B-spline grid along the footprint's longer side (the shorter gets as many of
/// the same size as cover it): a 10-cell side has 13 knots.
pub const FIT_CELLS: usize = 10;
/// λ of the objective in units of the family search's least area gain per unit of R.
pub const SMOOTHNESS_GAINS: f64 = 1.0;
/// The pattern search's first step, as a share of the knot spacing times tan of the tilt
/// bound (a coefficient moved by this tilts its cells by about a quarter of the bound).
pub const FIRST_STEP_SHARE: f64 = 0.25;
/// Halvings of the step before the fit stops.
pub const FIT_HALVINGS: usize = 3;
/// Most candidates the fit measures.
pub const MAX_FIT_EVALS: usize = 1000;
/// Most facet measures (candidates × facets that can overhang) the fit spends, so that
/// `suggest` keeps near issue 15's 2 s on a 225 000-triangle model: on the bench sphere the fit
/// then costs 0.1–0.3 s of CPU (`examples/suggest_bench`, which prints `suggest` with and
/// without the field; 2026-11-28 00:15 UTC, load 4.5: ratrig-vcore3-3z 1.76 s with, 1.49 s
/// without; pax-5axis 2.18 s, 2.04 s, where the fit stops after its exact starts: the cone
/// leaves 0; 1e7 measures cost 1.4–1.7 s more); models below ~1 000 such facets get the full
/// [`MAX_FIT_EVALS`].
pub const FIT_FACET_BUDGET: usize = 1_000_000;
/// The scales each family warp's sampled height is tried at as a start: a family's best warp
/// often puts facets exactly at the overhang angle (a ledge under a 45° belt at θ = 45°), where
/// the sampled copy's rounding tips them over; a slightly steeper copy stays on the good side.
pub const START_SCALES: &[f64] = &[1.0, 1.01, 1.03, 1.1];
/// Factor the start's coefficients are scaled by while it is not admissible.
pub const START_SHRINK: f64 = 0.9;
/// Most shrinks of the start before the fit gives up.
pub const MAX_SHRINKS: usize = 12;

/// R(c) of the module documentation.
pub fn roughness(s: &Spline) -> f64 {
    let [nx, ny] = s.size;
    let c = |i: usize, j: usize| s.c[j * nx + i];
    let mut r = 0.0;
    for j in 0..ny {
        for i in 1..nx.saturating_sub(1) {
            let d = c(i - 1, j) - 2.0 * c(i, j) + c(i + 1, j);
            r += d * d;
        }
    }
    for j in 1..ny.saturating_sub(1) {
        for i in 0..nx {
            let d = c(i, j - 1) - 2.0 * c(i, j) + c(i, j + 1);
            r += d * d;
        }
    }
    r / (s.step[0] * s.step[1])
}

/// The field warp of spline `s` (rounded to its text) over the family warp `over` (its text,
/// [`crate::warp::over`]) with the base blend `base`.
pub fn field_params(s: &Spline, over: Option<&str>, base: Option<[f64; 2]>) -> WarpParams {
    WarpParams {
        spec: WarpSpec::Field {
            expr: String::new(),
            grid: Some(s.rounded().to_text()),
            over: over.map(str::to_string),
        },
        base,
    }
}

impl Search<'_> {
    /// Fit the field from `start` (the best family warp); the best field found, if any start
    /// was admissible. Every field measured joins the search's candidates.
    pub fn fit_field(&mut self, starts: &[Scored]) -> Option<Scored> {
        let lambda = SMOOTHNESS_GAINS * self.min_gain;
        let objective = |sc: &Scored, s: &Spline| sc.area_mm2 + lambda * roughness(&s.rounded());
        let budget = MAX_FIT_EVALS.min(FIT_FACET_BUDGET / self.subset.areas.len().max(1));
        let mut evals = 0;
        // first the exact starts (the family warp plus a zero spline: J = its area, so the
        // fit never ends above the best family warp), then the sampled ones (a plane, a belt
        // warp, is sampled exactly; a cone's apex is rounded off). J ≥ 0: a start at J = 0
        // (no overhang left, no correction) is a least J, and ends the fit.
        let mut begun: Option<(Scored, Spline, Option<String>, Scored)> = None;
        let at_least = |b: &Option<(Scored, Spline, Option<String>, Scored)>| {
            b.as_ref()
                .is_some_and(|(b, bs, _, _)| objective(b, bs) <= 0.0)
        };
        let exact = starts.iter().map(|st| (st, None));
        let sampled = starts
            .iter()
            .flat_map(|st| START_SCALES.iter().map(move |&k| (st, Some(k))));
        for (start, scale) in exact.chain(sampled) {
            // the starts share the budget (the exact ones are always measured)
            if (scale.is_some() && begun.is_some() && evals >= budget) || at_least(&begun) {
                break;
            }
            let found = match scale {
                None => self.start_over(start, &mut evals),
                Some(k) => self.start_from(start, k, &mut evals),
            };
            let Some((sc, s, over)) = found else {
                continue;
            };
            if begun
                .as_ref()
                .is_none_or(|(b, bs, _, _)| objective(&sc, &s) < objective(b, bs))
            {
                begun = Some((sc, s, over, start.clone()));
            }
        }
        let (mut best, mut s, over, start) = begun?;
        let family_best = starts
            .iter()
            .map(|s| s.area_mm2)
            .fold(f64::INFINITY, f64::min);
        let base = start.params.base;
        let point = best.point;
        let mut j_best = objective(&best, &s);
        self.fit_trace = vec![j_best];
        if j_best <= 0.0 {
            return Some(best);
        }
        let bound = crate::num::tan(crate::num::rad(self.bound_deg.max(self.fixed_deg)));
        let mut step = FIRST_STEP_SHARE * s.step[0] * bound;
        for _ in 0..=FIT_HALVINGS {
            loop {
                let mut moved = false;
                // move k < n: coefficient k by ±step; k = n: every coefficient scaled by
                // 1 ± step/|c|max (the whole field steeper or flatter)
                let top = s.c.iter().fold(0.0f64, |m, c| m.max(c.abs())).max(1e-9);
                for k in 0..=s.c.len() {
                    // an all-zero correction has nothing to scale
                    if k == s.c.len() && top <= 1e-9 {
                        continue;
                    }
                    for sign in [-1.0, 1.0] {
                        if evals >= budget {
                            break;
                        }
                        let mut t = s.clone();
                        if k == s.c.len() {
                            let f = 1.0 + sign * step / top;
                            t.c.iter_mut().for_each(|c| *c *= f);
                        } else {
                            t.c[k] += sign * step;
                        }
                        let cap = best.area_mm2.max(family_best);
                        evals += 1;
                        let Some(sc) = self.measure(
                            point,
                            field_params(&t, over.as_deref(), base),
                            cap + AREA_TIE_MM2,
                        ) else {
                            continue;
                        };
                        let j = objective(&sc, &t);
                        if j < j_best - AREA_TIE_MM2 && sc.area_mm2 <= cap + AREA_TIE_MM2 {
                            s = t;
                            best = sc;
                            j_best = j;
                            moved = true;
                            break;
                        }
                    }
                }
                self.fit_trace.push(j_best);
                if !moved || evals >= budget {
                    break;
                }
            }
            step /= 2.0;
        }
        Some(best)
    }

    /// The field of `start` itself: its warp as the field's family part and a zero spline
    /// (the same g, so the same area and tilt); measured, its spline and family text.
    fn start_over(
        &mut self,
        start: &Scored,
        evals: &mut usize,
    ) -> Option<(Scored, Spline, Option<String>)> {
        let mut spec = start.params.spec.clone();
        spec.resolve(&self.model.bbox);
        let over = crate::warp::over::to_text(&spec)?;
        let s = Spline::over(&self.model.bbox, FIT_CELLS);
        *evals += 1;
        let sc = self.measure(
            field_point(start.params.base),
            field_params(&s, Some(&over), start.params.base),
            f64::INFINITY,
        )?;
        Some((sc, s, Some(over)))
    }

    /// The field of `start`'s height sampled at the knots (c = g(knot)), with `start`'s base
    /// blend, scaled by [`START_SHRINK`] until admissible; measured, and its spline.
    fn start_from(
        &mut self,
        start: &Scored,
        scale: f64,
        evals: &mut usize,
    ) -> Option<(Scored, Spline, Option<String>)> {
        let mut spec = start.params.spec.clone();
        spec.resolve(&self.model.bbox);
        let g0 = spec.height()?;
        let base = start.params.base;
        let mut s = Spline::over(&self.model.bbox, FIT_CELLS);
        for j in 0..s.size[1] {
            for i in 0..s.size[0] {
                let [x, y] = s.knot(i, j);
                s.c[j * s.size[0] + i] = scale * g0.g(x, y);
            }
        }
        for _ in 0..=MAX_SHRINKS {
            *evals += 1;
            if let Some(sc) = self.measure(
                field_point(base),
                field_params(&s, None, base),
                f64::INFINITY,
            ) {
                return Some((sc, s, None));
            }
            for c in &mut s.c {
                *c *= START_SHRINK;
            }
        }
        None
    }

    /// The fitted field's objective J at the start and after each sweep (empty when no field
    /// was fitted).
    pub fn fit_trace(&self) -> &[f64] {
        &self.fit_trace
    }
}

/// The search point every field is filed under.
fn field_point(base: Option<[f64; 2]>) -> Point {
    Point {
        family: Family::Field,
        direction: Direction::Outward,
        x: [0.0; 3],
        base: base.is_some(),
    }
}
