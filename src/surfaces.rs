//! Layer surfaces of a job, for display (the page colours them by tilt).
//!
//! Every `every`-th slicing plane z' = k·h is sampled on a `grid` × `grid` lattice over the
//! model's XY bounding box and mapped back to the model frame by T⁻¹: layer k is the surface
//! T_z(p) = k·h (see [`crate::warp`]).

use glam::DVec3;

use crate::job::Job;
use crate::warp::WarpError;

/// Numbers per sample in [`layer_surfaces`]'s output: x y z (model frame, mm), tilt of the
/// tool axis from +Z (degrees), layer index k.
pub const SAMPLE_STRIDE: usize = 5;

/// The samples (see the module documentation); samples whose z falls outside the model's z
/// range are skipped. `grid` is clamped to 2…256.
pub fn layer_surfaces(job: &Job, every: u32, grid: u32) -> Result<Vec<f64>, WarpError> {
    let mut params = job.warp.clone();
    let warp = params.build(&job.model_bbox)?;
    let (b, h) = (job.model_bbox, job.layer_height);
    let every = i64::from(every.max(1));
    let grid = grid.clamp(2, 256);
    let zt_min = job.warped_bbox.min.z - job.stl_z_offset;
    let zt_max = job.warped_bbox.max.z - job.stl_z_offset;
    let mut out = Vec::new();
    if !h.is_finite() || h <= 0.0 {
        return Ok(out);
    }
    let k0 = (zt_min / h).floor() as i64;
    let k1 = (zt_max / h).ceil() as i64;
    let mut k = k0;
    while k <= k1 {
        let zq = k as f64 * h;
        for i in 0..grid {
            for j in 0..grid {
                let x = b.min.x + (b.max.x - b.min.x) * f64::from(i) / f64::from(grid - 1);
                let y = b.min.y + (b.max.y - b.min.y) * f64::from(j) / f64::from(grid - 1);
                let p = warp.inverse(DVec3::new(x, y, zq));
                if p.z < b.min.z || p.z > b.max.z || !p.is_finite() {
                    continue;
                }
                let tilt = crate::num::deg(crate::num::angle_between(warp.tool_axis(p), DVec3::Z));
                out.extend_from_slice(&[p.x, p.y, p.z, tilt, k as f64]);
            }
        }
        k += every;
    }
    Ok(out)
}
