//! A part's stretch of poses that shares one list of the cells it may reach, carried from move
//! to move while the part stays near the stretch's first pose and no deposit lands within its
//! reach ([`super::Checker`]).
//!
//! ## The law
//! Let `G` be the part at the stretch's first pose grown by `Δ` ([`super::solid::Posed::dilated`];
//! for the nozzle also its contact surface moved back by `Δ`,
//! [`super::contact::ContactSurface::grown`]). The list holds every cell whose column enters
//! `G` (above the grown surface) more than the tolerance below the material's top. A pose whose
//! points are all within `Δ` of the first pose's lies inside `G` (and, where the contact rule
//! applies at it, its counted region inside the grown one), so it reaches no cell outside the
//! list **with the material of the search**. The list's test is monotone in a cell's top `h`
//! (the depth `min(h, z_out) − z_in` above the surface only grows with `h`), so a deposit can
//! only add cells, and only among those it raised: the stretch survives a deposit exactly when
//! none of the deposit's cells passes the same test (`Checker::deposit` runs that search restricted to the deposit's rectangle). A wider bead later (the
//! contact surface's `w` grows) only lowers what is counted, so the list stays a superset.
//!
//! The stretch is the same bound as within one move (law test
//! `a_stretch_lists_every_cell_any_of_its_poses_reaches` in `sweep.rs`); carrying it over moves
//! and deposits is checked by `a_stretch_carried_over_moves_and_deposits_lists_every_cell_reached`.

use super::contact::ContactSurface;
use super::sweep::{displacement, Pose};

/// A stretch of poses of one part (see the module documentation): the first pose, the growth
/// `delta` its list was searched with, whether the nozzle's contact rule bounded the search.
#[derive(Clone, Debug)]
pub(crate) struct Stretch {
    /// The pose the part was grown about.
    pub first: Pose,
    /// The growth, mm: the largest displacement of the part's points from `first` it covers.
    pub delta: f64,
    /// The contact surface bounded the list (so it covers only poses where the rule applies).
    pub contact: bool,
}

impl Stretch {
    /// Whether the list covers `pose` of a part of reach `reach` (its farthest point from the
    /// tip): every point within `delta` of its place at `first`, and the contact rule applying
    /// at `pose` when it bounded the list (widths: the bead width of the contact surface).
    pub fn covers(&self, pose: &Pose, reach: f64, width: f64) -> bool {
        displacement(&self.first, pose, reach) <= self.delta
            && (!self.contact || ContactSurface::new(pose.p, pose.n, width).applies())
    }
}
