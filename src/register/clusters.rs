//! How many separate things a G-code prints: its extrusions grouped by touching footprints.
//!
//! Each extruding move's footprint is its XY bounding box. Two footprints belong to one group
//! when their boxes, each grown by half of [`OBJECT_GAP`], overlap; a group is kept as the union
//! box of its members (so a group that surrounds another, e.g. a skirt loop around the part,
//! swallows it). The walls and infill of one object touch from layer to layer, so a single
//! object is one group; PrusaSlicer's `--duplicate 2` copies (6 mm apart by default), a wipe or
//! prime tower beside the part, or a second model on the plate are groups of their own.
//!
//! Used only to name what a G-code prints beside the model when its object is larger than the
//! warped mesh ([`super::RegisterError::MoreThanTheModel`]); a part with islands (two posts on
//! a plate) may count several groups, which is harmless there.

use glam::DVec2;

/// Smallest gap between two footprints that makes them separate things, mm (less than
/// PrusaSlicer's default 6 mm between copies and any wipe tower's distance from the part, more
/// than the 0.4–0.5 mm between a slicer's neighbouring lines).
pub const OBJECT_GAP: f64 = 1.0;

/// Groups kept at most; past it a footprint joins the nearest group (a bound on the work per
/// move, far above the handful of objects of a real plate).
pub const MAX_GROUPS: usize = 64;

/// The groups found so far: union boxes (min, max) in XY, mm.
#[derive(Clone, Debug, Default)]
pub struct Clusters {
    groups: Vec<(DVec2, DVec2)>,
}

impl Clusters {
    /// Add the footprint of a move from `a` to `b` (XY, mm).
    pub fn add(&mut self, a: DVec2, b: DVec2) {
        let half = 0.5 * OBJECT_GAP;
        let (mut lo, mut hi) = (a.min(b) - half, a.max(b) + half);
        // merge every group the grown box touches, repeatedly (a merged box may reach more)
        loop {
            let touching = self
                .groups
                .iter()
                .position(|&(gl, gh)| lo.cmple(gh).all() && gl.cmple(hi).all());
            let Some(i) = touching else { break };
            let (gl, gh) = self.groups.swap_remove(i);
            lo = lo.min(gl);
            hi = hi.max(gh);
        }
        if self.groups.len() >= MAX_GROUPS {
            let c = 0.5 * (lo + hi);
            let nearest = self
                .groups
                .iter()
                .enumerate()
                .map(|(i, &(gl, gh))| (i, (0.5 * (gl + gh) - c).length()))
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .map(|(i, _)| i);
            if let Some(i) = nearest {
                let (gl, gh) = self.groups.swap_remove(i);
                lo = lo.min(gl);
                hi = hi.max(gh);
            }
        }
        self.groups.push((lo, hi));
    }

    /// How many separate groups.
    pub fn count(&self) -> usize {
        self.groups.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(c: &mut Clusters, x: f64, y: f64, s: f64) {
        let p = [(x, y), (x + s, y), (x + s, y + s), (x, y + s), (x, y)];
        for w in p.windows(2) {
            c.add(DVec2::new(w[0].0, w[0].1), DVec2::new(w[1].0, w[1].1));
        }
    }

    #[test]
    fn two_copies_six_millimetres_apart_are_two_groups() {
        let mut c = Clusters::default();
        for z in 0..3 {
            let _ = z;
            square(&mut c, 0.0, 0.0, 20.0);
            square(&mut c, 26.0, 0.0, 20.0);
        }
        assert_eq!(c.count(), 2);
    }

    #[test]
    fn lines_half_a_millimetre_apart_are_one_group_and_a_ring_swallows_its_inside() {
        let mut c = Clusters::default();
        for k in 0..10 {
            let y = 0.45 * f64::from(k);
            c.add(DVec2::new(0.0, y), DVec2::new(10.0, y));
        }
        assert_eq!(c.count(), 1);
        square(&mut c, -6.0, -6.0, 25.0);
        assert_eq!(c.count(), 1);
    }
}
