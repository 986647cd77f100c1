//! Collision checking of machine output: the head's solids ([`crate::machine::head`]) swept
//! along every move against the material printed so far and the bed.
//!
//! - [`solid`]: a head part placed in the output frame (frustum or oriented box): where a
//!   vertical line crosses it, its distance from a point.
//! - [`material`]: the printed material, a sparse height field of the bead tops.
//! - [`bead`]: a bead's top across its width (the layer's slope, bounded by the tool face's).
//! - [`contact`]: where the nozzle's flat face may touch the material it prints on (the
//!   contact surface `s ≤ (ρ + w/2)·tan 30°`, and a layer height into the current layer).
//! - [`sweep`]: the [`Checker`]: poses sampled along a move (every head point moves at most
//!   [`SAMPLE_STEP_MM`] between samples), the overlap of each part with material and bed
//!   beyond the contact surface, up to [`CONTACT_TOLERANCE_MM`] not reported.
//! - [`walk`]: a machine G-code through the checker ([`check_gcode`], [`Walker`] for streams).
//! - [`posed_head`]: the head's parts at one pose, as the check places them, for drawing.
//!
//! Everything happens in the **output frame** (the part's): the material and the bed do not
//! move in it; the head's pose there comes from the machine's forward kinematics
//! ([`crate::machine::Machine::forward`], [`crate::machine::Machine::head_frame`]), so a
//! turning table and a turning head are the same question.
//!
//! The unwarp runs it on every machine output (`check_collisions`, on by default; every refusal
//! of the real-slicer matrix is confirmed by the independent helper `tests/common/collide.rs`;
//! `allow_collisions` writes the file and lists the findings instead of refusing it with
//! [`crate::machine::MachineError::Collision`] at the first one).
//!
//! ## Speed
//! Per move and part, before its poses are chosen: its box at the move's first pose grown by
//! the bound of its points' travel (`sweep::grown_box`, the turn's angle bounded without an arc
//! cosine by `turn.rs`) against the material's block maxima and the bed skips a part that cannot
//! reach anything; then the union of the part's boxes at its checked poses does the same; a translation (the pose fixed) finds the cells
//! its frustum parts can reach once ([`Checker`]'s swept cells, from the parts' floor bounds
//! [`solid::Posed::floor_at`] and [`contact::ContactSurface::floor_at`]), skipping a block of
//! the height field whose highest top is under the floor at the block's least distance from
//! the tip's path, and on each row of a block the cells farther from the path than the radius
//! where that floor comes below the row's highest top ([`cull::capsule_row`]), and each of its
//! checked poses gets only the cells within that radius of its own tip (`Checker::by_pose`,
//! [`cull::TipLine`]); per pose only
//! cells within the tip radius under which the part can reach the
//! highest material are visited, and a pose's search for its deepest overlap skips what
//! cannot be deeper than the deepest found so far ([`cull::Reach::raise`]). Every other move (the head turns, or a box part translates)
//! finds the cells a part may reach once per **stretch** of its checked poses whose points stay
//! within [`sweep::STRETCH_MM`] of the stretch's first pose: that pose's solid grown by the
//! stretch's largest displacement ([`solid::Posed::dilated`]), and for the nozzle above its
//! contact surface moved back by the same ([`contact::ContactSurface::grown`]), contains the
//! part and its counted region at every pose of the stretch; each pose then visits only those
//! cells (law test `a_stretch_lists_every_cell_any_of_its_poses_reaches` in `sweep.rs`, against
//! each pose's own columns). A part's last stretch of a move is carried into the next moves
//! while their poses stay within its growth and no deposit raises a cell its list's own test
//! passes (`stretch.rs`, law test `a_stretch_carried_over_moves_and_deposits_lists_every_cell_reached`);
//! a part without the contact rule whose last list was empty grows by
//! [`sweep::CLEAR_STRETCH_MM`]. Each part is checked only at the poses its own reach needs
//! (`checked_poses`). The poses sampled along a move are kept for its bead and the next move's
//! start (`samples.rs`: the same axes or the same correctly rounded parameter, so the same
//! pose bit for bit), instead of solving the kinematics again. [`Checker::exhaustive`] switches every bound off: the law test
//! in `tests/collision_check.rs` compares the findings. The
//! bench (`cargo run --release --example bench`) gives the check's cost beside `unwarp
//! --machine`.

pub mod bead;
pub mod contact;
pub mod cull;
pub mod material;
pub mod posed_head;
mod samples;
pub mod solid;
mod stretch;
pub mod sweep;
mod turn;
pub mod walk;

pub use sweep::{CheckStats, Checker, CONTACT_TOLERANCE_MM, SAMPLE_STEP_MM};
pub use walk::{walk_line, AxisMove, AxisReader, ReadLine, Walker, DEFAULT_LINE_WIDTH_MM};

use crate::emit::CollisionFinding;
use crate::machine::{MachineError, MachineSpec};

/// Check a whole machine G-code: every finding in file order, and the counts.
pub fn check_gcode(
    gcode: &[u8],
    spec: &MachineSpec,
) -> Result<(Vec<CollisionFinding>, CheckStats), MachineError> {
    let mut w = Walker::new(spec)?;
    w.push(gcode)?;
    let (f, c) = w.finish()?;
    Ok((f, c.stats()))
}

/// The refusal for the first of `findings` (named error `machine.collision`).
pub fn refusal(machine: &str, findings: &[CollisionFinding]) -> Option<MachineError> {
    let f = findings.first()?;
    Some(MachineError::Collision {
        machine: machine.to_string(),
        finding: Box::new(f.clone()),
        total: findings.len(),
    })
}
