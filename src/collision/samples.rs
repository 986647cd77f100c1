//! The poses the check sampled along the last move, kept so that the moves' shared ends and the
//! bead laid along the same move ([`super::Checker`]'s deposit) reuse them instead of solving
//! the kinematics again.
//!
//! ## Why a kept pose is the pose that would be computed
//! The check samples the move from axes `a` to `b` at `t_j = j / n` for `0 < j < n`
//! (`Checker::pose_between`: each axis `a + (b − a)·t`, then the machine's forward kinematics,
//! a function of the axes only); its ends are the poses of `a` and `b` themselves (not
//! `a + (b − a)·1`, which may differ from `b` in the last bit). The bead's piece `k` of `m` ends at
//! `t = k / m`. When `k·n = j·m` the two quotients are the same rational number, and IEEE
//! division rounds it correctly both times, so `k as f64 / m as f64` and `j as f64 / n as f64`
//! are the same double (`k, m, j, n` < 2⁵³ are exact): the axes, hence the pose, are bit for
//! bit the same. A move's start `a` equals the last move's end only when its axes are the same
//! doubles (compared bit for bit): the same pose again. Nothing else is reused.

use super::sweep::Pose;
use crate::num::same_bits;

/// The poses sampled along one move (`poses[j]` at `t = j / n`, `n = poses.len() − 1`).
#[derive(Clone, Debug, Default)]
pub(crate) struct Samples {
    from: Vec<f64>,
    to: Vec<f64>,
    poses: Vec<Pose>,
}

impl Samples {
    /// Keep the poses `poses` sampled from axes `from` to `to` (at least the two ends).
    pub fn keep(&mut self, from: &[f64], to: &[f64], poses: Vec<Pose>) {
        self.from.clear();
        self.from.extend_from_slice(from);
        self.to.clear();
        self.to.extend_from_slice(to);
        self.poses = poses;
    }

    /// Forget the kept poses (a test's reference without them).
    #[cfg(test)]
    pub fn forget(&mut self) {
        self.poses.clear();
    }

    /// How many poses are kept.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.poses.len()
    }

    /// The pose of axes `axes` if it is one of the kept move's ends.
    pub fn end(&self, axes: &[f64]) -> Option<Pose> {
        let (first, last) = (self.poses.first()?, self.poses.last()?);
        if same_bits(axes, &self.to) {
            Some(*last)
        } else if same_bits(axes, &self.from) {
            Some(*first)
        } else {
            None
        }
    }

    /// The pose at `t = k / m` (`0 < k < m`) of the move from `from` to `to`, if it is the kept
    /// move and `k / m` is one of its interior sample parameters (`k·n` a multiple of `m`).
    /// Not the ends: those are the poses of `from` and `to` themselves ([`Samples::end`]),
    /// which `a + (b − a)·1` need not reproduce to the last bit.
    pub fn at(&self, from: &[f64], to: &[f64], k: usize, m: usize) -> Option<Pose> {
        let n = self.poses.len().checked_sub(1)?;
        if k == 0 || k >= m || !same_bits(from, &self.from) || !same_bits(to, &self.to) {
            return None;
        }
        let kn = k.checked_mul(n)?;
        (kn % m == 0)
            .then(|| self.poses.get(kn / m).copied())
            .flatten()
    }
}
