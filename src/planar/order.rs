//! Travel ordering: nearest neighbour within a group of paths.
//!
//! From the nozzle's position, the next path is the one with the nearest entry point: any
//! vertex of a closed loop (the loop is then started there and run once round, back to that
//! vertex) or either end of an open line (run from that end). Ties go to the earlier path in the
//! list, so the order is deterministic. Paths of fewer than two points are left out.

use super::{Path, Role};

/// A travel longer than this retracts first, mm (PrusaSlicer's `retract_before_travel`
/// default): shorter hops stay inside the part's own lines, where an ooze does not show.
pub const RETRACT_BEFORE_TRAVEL: f64 = 2.0;

fn dist2(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
}

/// A loop of `role` through `contour`, or an open line.
pub fn loop_path(role: Role, contour: Vec<[f64; 2]>) -> Path {
    Path {
        role,
        points: contour,
        closed: true,
        section: Vec::new(),
    }
}

/// The paths in nearest-neighbour order from `at`, each made ready to print (a loop starts at
/// its entry vertex and ends back on it; an open line runs from its entry end). `at` is left at
/// the last path's end.
pub fn nearest_neighbour(mut paths: Vec<Path>, at: &mut [f64; 2]) -> Vec<Path> {
    paths.retain(|p| p.points.len() >= 2);
    let mut out = Vec::with_capacity(paths.len());
    while !paths.is_empty() {
        let mut best = (f64::INFINITY, 0usize, 0usize);
        for (i, p) in paths.iter().enumerate() {
            let entries: Box<dyn Iterator<Item = (usize, &[f64; 2])>> = if p.closed {
                Box::new(p.points.iter().enumerate())
            } else {
                let last = p.points.len().saturating_sub(1);
                Box::new([(0, &p.points[0]), (last, &p.points[last])].into_iter())
            };
            for (k, q) in entries {
                let d = dist2(*at, *q);
                if d < best.0 {
                    best = (d, i, k);
                }
            }
        }
        let mut p = paths.remove(best.1);
        if p.closed {
            p.points.rotate_left(best.2);
            p.points.push(p.points[0]);
            if !p.section.is_empty() {
                p.section.rotate_left(best.2);
                p.section.push(p.section[0]);
            }
        } else if best.2 != 0 {
            p.points.reverse();
            p.section.reverse();
        }
        if let Some(&end) = p.points.last() {
            *at = end;
        }
        out.push(p);
    }
    out
}
