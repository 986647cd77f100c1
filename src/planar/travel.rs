//! Travel inside the part (PrusaSlicer's `avoid_crossing_perimeters`): a travel whose straight
//! line leaves the part and comes back (across a hole, or across a notch of its outline) goes
//! round along the external perimeter's line instead, the shorter way.
//!
//! With the contours C of the layer's region offset inward by w/2 (the external perimeters'
//! lines, [`super::walls`]), a travel a → b is cut by each contour at the parameters
//! `0 < t < 1` where the segment crosses it. A contour crossed an even number of times is left
//! and re-entered: each pair of crossings (p, q), taken in order along the segment, is replaced
//! by the contour's own path from p to q, forwards or backwards, whichever is shorter. A
//! contour crossed an odd number of times means that a or b is not inside the lines (a skirt, a
//! point of another layer): the travel stays straight (the simple case only; PrusaSlicer's
//! full planner also routes between islands).

use super::region::{line_crossing, Contour};

/// Crossings closer than this to the travel's ends (as a fraction of its length) do not count:
/// a travel to the start of an external perimeter ends on its contour.
pub const END_SLACK: f64 = 1e-6;

/// The points a travel from `a` to `b` passes through, `a` and `b` left out (empty: straight).
pub fn route(contours: &[Contour], a: [f64; 2], b: [f64; 2]) -> Vec<[f64; 2]> {
    let d = [b[0] - a[0], b[1] - a[1]];
    // (t along a→b, contour, edge, crossing point)
    let mut detours: Vec<(f64, Vec<[f64; 2]>)> = Vec::new();
    for c in contours {
        let n = c.len();
        let mut hits: Vec<(f64, usize, [f64; 2])> = Vec::new();
        for i in 0..n {
            let Some((t, u)) = line_crossing(a, d, c[i], c[(i + 1) % n]) else {
                continue;
            };
            if t > END_SLACK && t < 1.0 - END_SLACK && (0.0..1.0).contains(&u) {
                hits.push((t, i, [a[0] + t * d[0], a[1] + t * d[1]]));
            }
        }
        if hits.len() % 2 == 1 {
            return Vec::new();
        }
        hits.sort_by(|x, y| x.0.total_cmp(&y.0));
        for pair in hits.chunks_exact(2) {
            let ((t, i, p), (_, j, q)) = (pair[0], pair[1]);
            detours.push((t, along(c, p, i, q, j)));
        }
    }
    detours.sort_by(|x, y| x.0.total_cmp(&y.0));
    detours.into_iter().flat_map(|(_, v)| v).collect()
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

fn length(points: &[[f64; 2]]) -> f64 {
    points.windows(2).map(|s| dist(s[0], s[1])).sum()
}

/// The shorter way along contour `c` from `p` (on its edge i) to `q` (on its edge j): p, the
/// contour's vertices between, q.
fn along(c: &Contour, p: [f64; 2], i: usize, q: [f64; 2], j: usize) -> Vec<[f64; 2]> {
    let n = c.len();
    // forwards: p, c[i+1], …, c[j], q
    let mut fwd = vec![p];
    let mut k = (i + 1) % n;
    if i != j {
        loop {
            fwd.push(c[k]);
            if k == j {
                break;
            }
            k = (k + 1) % n;
        }
    }
    fwd.push(q);
    // backwards: p, c[i], …, c[j+1], q
    let mut back = vec![p];
    if i != j {
        let mut k = i;
        loop {
            back.push(c[k]);
            if k == (j + 1) % n {
                break;
            }
            k = (k + n - 1) % n;
        }
    }
    back.push(q);
    if length(&back) < length(&fwd) {
        back
    } else {
        fwd
    }
}
