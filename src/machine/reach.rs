//! The reach check of every written move: each raw axis value inside its travel
//! ([`super::travel::AxisBounds`]), and the range written per axis for the report's margins.
//!
//! For axis i with travel `[minᵢ, maxᵢ]` a written value v is inside when
//! `minᵢ − s ≤ v ≤ maxᵢ + s`, s = [`crate::tolerance::LENGTH_EPSILON`] (mm) on a linear axis and
//! [`super::LIMIT_SLACK_DEG`] on a rotary one (a value computed exactly at a limit passes).
//! Over the file, `margin_minᵢ = min(v) − minᵢ` and `margin_maxᵢ = maxᵢ − max(v)`: how far the
//! file stays from each end (negative never in the emitter's output, where a violation stops
//! the output; negative in `warpslice check` of a file that leaves the travel).

use super::travel::AxisBounds;
use crate::emit::AxisReport;

/// The range written so far, per axis.
#[derive(Clone, Debug)]
pub struct Reach {
    bounds: Vec<AxisBounds>,
    /// `(minᵢ − s, maxᵢ + s)` per axis, computed once (the check runs on every written move).
    inside: Vec<(f64, f64)>,
    lowest: Vec<f64>,
    highest: Vec<f64>,
}

impl Reach {
    /// For these axes (machine order).
    pub fn new(bounds: Vec<AxisBounds>) -> Reach {
        let n = bounds.len();
        let inside = bounds
            .iter()
            .map(|b| {
                let s = if b.rotary {
                    super::LIMIT_SLACK_DEG
                } else {
                    crate::tolerance::LENGTH_EPSILON
                };
                (b.min - s, b.max + s)
            })
            .collect();
        Reach {
            bounds,
            inside,
            lowest: vec![f64::INFINITY; n],
            highest: vec![f64::NEG_INFINITY; n],
        }
    }

    /// The axes.
    pub fn bounds(&self) -> &[AxisBounds] {
        &self.bounds
    }

    /// Check raw `axes` (machine order): `Err(i)` names the first axis outside its travel (the
    /// move is not recorded); otherwise the values join the range written.
    pub fn check(&mut self, axes: &[f64]) -> Result<(), usize> {
        if let Some(i) = self.outside(axes).next() {
            return Err(i);
        }
        self.observe(axes);
        Ok(())
    }

    /// The axes of raw `axes` (machine order) outside their travel, in order (see the module
    /// documentation for the slack).
    pub fn outside<'a>(&'a self, axes: &'a [f64]) -> impl Iterator<Item = usize> + 'a {
        self.inside
            .iter()
            .zip(axes)
            .enumerate()
            .filter(|(_, (&(lo, hi), &v))| !(v >= lo && v <= hi))
            .map(|(i, _)| i)
    }

    /// Add raw `axes` to the range written, inside their travel or not (`warpslice check`
    /// reports a file's range as it is: a margin is then negative).
    pub fn observe(&mut self, axes: &[f64]) {
        for (i, &v) in axes.iter().enumerate().take(self.bounds.len()) {
            self.lowest[i] = self.lowest[i].min(v);
            self.highest[i] = self.highest[i].max(v);
        }
    }

    /// Per axis: travel, range written, margins and largest feed (`speed_limited_moves` 0: the
    /// speed accounting fills it in).
    pub fn report(&self) -> Vec<AxisReport> {
        let finite = |v: f64| v.is_finite().then_some(v);
        self.bounds
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let (lo, hi) = (finite(self.lowest[i]), finite(self.highest[i]));
                AxisReport {
                    axis: b.name.clone(),
                    rotary: b.rotary,
                    min: finite(b.min),
                    max: finite(b.max),
                    lowest: lo,
                    highest: hi,
                    margin_min: lo.zip(finite(b.min)).map(|(v, m)| v - m),
                    margin_max: hi.zip(finite(b.max)).map(|(v, m)| m - v),
                    max_feed: finite(b.max_feed),
                    speed_limited_moves: 0,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axis(name: &str, rotary: bool, min: f64, max: f64) -> AxisBounds {
        AxisBounds {
            name: name.into(),
            rotary,
            min,
            max,
            max_feed: f64::INFINITY,
        }
    }

    #[test]
    fn the_first_axis_outside_is_named_and_margins_are_to_each_end() {
        let mut r = Reach::new(vec![
            axis("X", false, 0.0, 230.0),
            axis("Y", false, f64::NEG_INFINITY, f64::INFINITY),
            axis("B", true, -90.0, 90.0),
        ]);
        assert_eq!(r.check(&[10.0, -500.0, 30.0]), Ok(()));
        assert_eq!(r.check(&[200.0, 7.0, -45.0]), Ok(()));
        assert_eq!(r.check(&[230.5, 0.0, 0.0]), Err(0));
        assert_eq!(r.check(&[1.0, 0.0, 90.5]), Err(2));
        let rep = r.report();
        assert_eq!(
            (rep[0].margin_min, rep[0].margin_max),
            (Some(10.0), Some(30.0))
        );
        assert_eq!((rep[1].margin_min, rep[1].lowest), (None, Some(-500.0)));
        assert_eq!(
            (rep[2].margin_min, rep[2].margin_max),
            (Some(45.0), Some(60.0))
        );
    }
}
