//! The toolpath in machine coordinates, for drawing a moving-bed machine (the web preview's
//! "machine coordinates" view).
//!
//! For a toolpath point (tip p, tool axis n, output frame) the machine's inverse kinematics
//! gives its axes; [`Machine::head_position`] turns them into where the head is in the
//! machine's own frame, H(p). Solving p + e_k (k = x, y, z) with the same n and the previous
//! axes (so all four share p's rotary axes) gives the part's pose at that point: the rigid map
//! part → machine is q ↦ H(p) + R (q − p) with R's columns H(p + e_k) − H(p).

use glam::DVec3;

use super::{Machine, MachineError};

/// Numbers per point in the output of [`head_frames`]: H(p) (3), then R's columns (3 × 3).
pub const FRAME_STRIDE: usize = 12;

/// `points`: 6 numbers per point (p, n). Returns [`FRAME_STRIDE`] numbers per point (see the
/// module documentation). An unreachable point is an error naming its index.
pub fn head_frames(machine: &dyn Machine, points: &[f64]) -> Result<Vec<f64>, MachineError> {
    if !points.len().is_multiple_of(6) {
        return Err(MachineError::BadCsv {
            line: points.len() / 6 + 1,
            message: format!(
                "{} numbers is not a whole number of points (6 per point: px py pz nx ny nz)",
                points.len()
            ),
        });
    }
    let mut out = Vec::with_capacity(points.len() / 6 * FRAME_STRIDE);
    let mut previous: Option<Vec<f64>> = None;
    for q in points.chunks_exact(6) {
        let p = DVec3::new(q[0], q[1], q[2]);
        let n = DVec3::new(q[3], q[4], q[5]);
        let axes = machine.inverse(p, n, previous.as_deref())?;
        let h0 = machine.head_position(&axes);
        out.extend_from_slice(&h0.to_array());
        for e in [DVec3::X, DVec3::Y, DVec3::Z] {
            let a = machine.inverse(p + e, n, Some(&axes))?;
            out.extend_from_slice(&(machine.head_position(&a) - h0).to_array());
        }
        previous = Some(axes);
    }
    Ok(out)
}

/// Each point's axes (the machine's order; linear mm, rotary degrees), the previous point's
/// axes picking the branch.
pub fn axes_of(machine: &dyn Machine, points: &[f64]) -> Result<Vec<f64>, MachineError> {
    let k = machine.limits().len();
    let mut out = Vec::with_capacity(points.len() / 6 * k);
    let mut previous: Option<Vec<f64>> = None;
    for q in points.chunks_exact(6) {
        let axes = machine.inverse(
            DVec3::new(q[0], q[1], q[2]),
            DVec3::new(q[3], q[4], q[5]),
            previous.as_deref(),
        )?;
        out.extend_from_slice(&axes);
        previous = Some(axes);
    }
    Ok(out)
}
