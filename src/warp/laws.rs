//! The law test every warp must pass (shared by the native tests, the property tests and the
//! wasm tests): round trip, Jacobian against finite differences, tool axis against the numeric
//! gradient of T_z.

use glam::DVec3;

use super::Warp;

/// |T⁻¹(T(p)) − p| bound, mm.
pub const ROUND_TRIP_TOLERANCE: f64 = 1e-9;
/// Central-difference step, mm.
pub const FD_STEP: f64 = 1e-5;
/// Allowed difference between an analytic Jacobian entry and its central difference
/// (truncation O(h²·T‴) plus rounding O(ε·|T|/h)).
pub const FD_TOLERANCE: f64 = 1e-6;

/// Check the warp laws at `p` (model frame). (Comparisons are written `!(err <= tol)` so that a
/// NaN fails them.) Points within `2·FD_STEP` of a kink (crease, apex)
/// must be excluded by the caller from the derivative checks: pass `check_derivatives = false`.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn check_point(warp: &dyn Warp, p: DVec3, check_derivatives: bool) -> Result<(), String> {
    let q = warp.forward(p);
    let back = warp.inverse(q);
    let err = (back - p).length();
    if !(err <= ROUND_TRIP_TOLERANCE) {
        return Err(format!(
            "{warp:?}: inverse(forward({p})) = {back}, error {err:e} mm"
        ));
    }
    if !check_derivatives {
        return Ok(());
    }
    let j = warp.jacobian(p);
    let cols = [j.x_axis, j.y_axis, j.z_axis];
    for (k, axis) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
        let fd =
            (warp.forward(p + axis * FD_STEP) - warp.forward(p - axis * FD_STEP)) / (2.0 * FD_STEP);
        let d = (fd - cols[k]).abs().max_element();
        if !(d <= FD_TOLERANCE * (1.0 + cols[k].abs().max_element())) {
            return Err(format!(
                "{warp:?}: Jacobian column {k} at {p} is {} but finite differences give {fd}",
                cols[k]
            ));
        }
    }
    let det_fd = j.determinant();
    let det = warp.jacobian_det(p);
    if !((det - det_fd).abs() <= FD_TOLERANCE * (1.0 + det.abs())) {
        return Err(format!(
            "{warp:?}: jacobian_det at {p} is {det} but det(J) is {det_fd}"
        ));
    }
    let n = warp.tool_axis(p);
    let grad = DVec3::new(
        (warp.forward(p + DVec3::X * FD_STEP).z - warp.forward(p - DVec3::X * FD_STEP).z)
            / (2.0 * FD_STEP),
        (warp.forward(p + DVec3::Y * FD_STEP).z - warp.forward(p - DVec3::Y * FD_STEP).z)
            / (2.0 * FD_STEP),
        (warp.forward(p + DVec3::Z * FD_STEP).z - warp.forward(p - DVec3::Z * FD_STEP).z)
            / (2.0 * FD_STEP),
    );
    let ng = grad.normalize();
    if !((n.length() - 1.0).abs() <= 1e-12 && (n - ng).length() <= FD_TOLERANCE) {
        return Err(format!(
            "{warp:?}: tool axis at {p} is {n} but the numeric gradient gives {ng}"
        ));
    }
    Ok(())
}
