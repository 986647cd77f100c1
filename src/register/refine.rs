//! Fine registration: the placement that puts the printed outer walls a constant bead inset
//! inside the warped mesh's cross-sections, layer by layer.
//!
//! The bounding-box match ([`super::Scanner::finish`]) is off by up to slope × h/2 (the
//! extremes of a sloped wall fall between the slicer's planes) and by whatever the slicer did
//! not print (fins thinner than a line move the extrusions' box). Here, for up to
//! [`MAX_LAYERS`] layers of the pass-1 sample ([`super::sample`]), the warped mesh is cut at
//! the slicer's plane z − h/2 (the middle of the layer, where PrusaSlicer, Slic3r and
//! CuraEngine slice); the cut is sampled every [`SECTION_STEP`] with its outward normal n (the
//! face normal's XY part); each sample b (STL frame) is matched to the nearest extrusion e of
//! that layer (G-code frame) within [`MATCH_RADIUS`]. The unknowns, the translation t and the
//! bead inset c (how far the outer walls' centre lines sit inside the surface, ≈ half a line
//! width), minimise Σ ρ(n·(b + t − e) − c) (point-to-plane ICP, Gauss–Newton with Huber
//! weights ρ, [`HUBER_MM`]; matches further than [`OUTLIER_MM`] from the median residual are
//! dropped: a feature the slicer did not print, an inner wall). Everything the slicer did not
//! print simply has no match.
//!
//! The fit is refused ([`super::RegisterError::Undetermined`]) when fewer than
//! [`MIN_MATCHES`] samples match or the normals do not pin both directions (a single straight
//! wall): then the placement cannot be known to the bead.

use glam::{DMat3, DVec2, DVec3};
use rstar::primitives::Line;
use rstar::{PointDistance, RTree};

use super::sample::Sample;
use super::RegisterError;
use crate::mesh::Mesh;

/// Spacing of the samples along a cross-section, mm.
pub const SECTION_STEP: f64 = 0.25;
/// Largest distance from a section sample to the extrusion matched with it, mm (a bead inset
/// is ≈ 0.2–0.3 mm; the bounding-box start is within ≈ 0.5 mm).
pub const MATCH_RADIUS: f64 = 1.0;
/// Layers of the sample used, spread over the part's height.
pub const MAX_LAYERS: usize = 32;
/// Residuals below this are weighted fully (Huber), mm.
pub const HUBER_MM: f64 = 0.05;
/// Matches whose residual is further than this from the median are dropped, mm.
pub const OUTLIER_MM: f64 = 0.25;
/// Largest |cos| between a matched extrusion's direction and the surface normal: a wall's
/// bead runs along the surface (cos ≈ 0); above this it crosses it.
pub const WALL_ALIGNMENT: f64 = 0.5;
/// After the first iterations, matches further than this many robust standard deviations
/// (1.4826 × the median absolute deviation) from the median are dropped too, but never
/// closer than [`HUBER_MM`].
pub const OUTLIER_SIGMAS: f64 = 3.0;

/// Two line widths in bead insets (an outer wall's centre sits half a line inside): a cut
/// narrower than this many insets holds at most single lines.
pub const TWO_LINES_IN_INSETS: f64 = 4.0;

/// Fewest matches for a determined fit.
pub const MIN_MATCHES: usize = 40;
/// Smallest eigenvalue of the normals' mean outer product Σ n nᵀ / N: below it one direction
/// is not pinned by the walls (1 = a circle's 0.5 each way; a square gives 0.5).
pub const MIN_SPREAD: f64 = 0.02;
/// Gauss–Newton iterations (each re-matches); stops earlier once a step is below 1e-6 mm.
pub const ITERATIONS: usize = 12;
/// A face whose normal's XY part is shorter than this is (nearly) horizontal: its cut is no
/// wall and is skipped.
pub const WALL_NORMAL_XY: f64 = 0.2;

/// The fine registration's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// STL → G-code translation (dx, dy), mm.
    pub translation: [f64; 2],
    /// Bead inset c: how far the matched extrusions sit inside the surface, mm.
    pub inset: f64,
    /// RMS of the residuals n·(b + t − e) − c over the matches kept, mm.
    pub rms: f64,
    /// Matches kept.
    pub matched: usize,
    /// Layers used.
    pub layers: usize,
}

/// Points every [`SECTION_STEP`] along the cut of `mesh` at height `z`, with their outward
/// normals (unit, XY).
fn section(mesh: &Mesh, z: f64) -> Vec<(DVec2, DVec2)> {
    let mut out = Vec::new();
    for t in &mesh.triangles {
        let p = t.map(|i| mesh.vertices[i as usize]);
        let (lo, hi) = (
            p[0].z.min(p[1].z).min(p[2].z),
            p[0].z.max(p[1].z).max(p[2].z),
        );
        if !(lo < z && z < hi) {
            continue;
        }
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let nxy = DVec2::new(n.x, n.y);
        if nxy.length() < WALL_NORMAL_XY * n.length() {
            continue;
        }
        let nxy = nxy.normalize();
        let mut ends = Vec::with_capacity(2);
        for (a, b) in [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])] {
            if (a.z < z) != (b.z < z) {
                let s = (z - a.z) / (b.z - a.z);
                let q = a + (b - a) * s;
                ends.push(DVec2::new(q.x, q.y));
            }
        }
        if ends.len() != 2 {
            continue;
        }
        let len = (ends[1] - ends[0]).length();
        let k = (len / SECTION_STEP).ceil().max(1.0) as usize;
        for i in 0..k {
            let s = (i as f64 + 0.5) / k as f64;
            out.push((ends[0].lerp(ends[1], s), nxy));
        }
    }
    out
}

/// Fewest of the cut's samples that must match a printed wall (a fraction): the G-code of
/// another model matches far fewer; a part whose thin features were not printed (fins, ribs)
/// still matches its body.
pub const MIN_MATCHED_FRACTION: f64 = 0.3;
/// Layers used to choose among the starting placements (then all [`MAX_LAYERS`]).
pub const START_LAYERS: usize = 8;
/// Iterations from each starting placement.
pub const START_ITERATIONS: usize = 4;

/// One layer's cut samples and its extrusions' index.
type LayerData = (Vec<(DVec2, DVec2)>, RTree<Line<[f64; 2]>>);

/// Up to `n` layers of the sample, spread over its height (the first skipped: a flattened
/// first layer or the anchor is not sliced mid-layer), cut and indexed.
fn layer_data(mesh: &Mesh, sample: &Sample, h: f64, n: usize) -> Vec<LayerData> {
    let usable: Vec<_> = sample.layers().iter().skip(1).collect();
    let step = (usable.len() as f64 / n as f64).max(1.0);
    let mut data = Vec::new();
    let mut k = 0.0;
    while (k as usize) < usable.len() && data.len() < n {
        let l = usable[k as usize];
        k += step;
        let cut = section(mesh, l.z - h / 2.0);
        if cut.is_empty() {
            continue;
        }
        let lines: Vec<Line<[f64; 2]>> = l
            .segs
            .iter()
            .map(|s| Line::new(s.a.to_array(), s.b.to_array()))
            .collect();
        data.push((cut, RTree::bulk_load(lines)));
    }
    data
}

/// The fit (see the module documentation), from the best of the starting placements `starts`
/// (the bounding-box match and its variants: the box's sides aligned instead of its centre,
/// for parts whose thin features were not printed). `mesh` is the warped STL (its own frame),
/// `h` the layer height.
pub fn refine(
    mesh: &Mesh,
    sample: &Sample,
    h: f64,
    starts: &[[f64; 2]],
) -> Result<Fit, RegisterError> {
    let few = layer_data(mesh, sample, h, START_LAYERS);
    let mut best: Option<(usize, [f64; 2])> = None;
    for &s in starts {
        if let Ok(f) = fit_from(&few, s, START_ITERATIONS) {
            if best.is_none_or(|(m, _)| f.matched > m) {
                best = Some((f.matched, f.translation));
            }
        }
    }
    let start = best.map_or(starts[0], |b| b.1);
    let data = layer_data(mesh, sample, h, MAX_LAYERS);
    let f = fit_from(&data, start, ITERATIONS)?;
    // a part narrower than two lines is printed as single lines down its middle: both sides
    // match the same bead and its ends are no walls, so nothing pins it to the bead (judged
    // on the widest layer: the cuts of a warped part may be small islands on many layers)
    let widths: Vec<f64> = data
        .iter()
        .map(|(cut, _)| {
            let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
            for (b, _) in cut {
                lo = lo.min(*b);
                hi = hi.max(*b);
            }
            (hi - lo).min_element()
        })
        .collect();
    let widest = widths.iter().copied().fold(0.0, f64::max);
    if widest < TWO_LINES_IN_INSETS * f.inset {
        return Err(RegisterError::Undetermined {
            matched: f.matched,
            needed: MIN_MATCHES,
            reason: "the part is narrower than two lines (it is printed as single lines down its middle)",
        });
    }
    let samples: usize = data.iter().map(|d| d.0.len()).sum();
    if (f.matched as f64) < MIN_MATCHED_FRACTION * samples as f64 {
        return Err(RegisterError::Undetermined {
            matched: f.matched,
            needed: (MIN_MATCHED_FRACTION * samples as f64).ceil() as usize,
            reason: "too little of the warped mesh's surface has a printed wall next to it (is this the G-code of this job's STL?)",
        });
    }
    Ok(f)
}

/// Gauss–Newton from `start`.
fn fit_from(data: &[LayerData], start: [f64; 2], iterations: usize) -> Result<Fit, RegisterError> {
    let mut t = DVec2::from_array(start);
    let mut c: Option<f64> = None;
    let mut last = (0usize, 0.0f64);
    for it in 0..iterations {
        // match: residual without c, normal
        let mut m: Vec<(f64, DVec2)> = Vec::new();
        for (cut, tree) in data {
            for &(b, n) in cut {
                let q = (b + t).to_array();
                let Some(line) = tree.nearest_neighbor(&q) else {
                    continue;
                };
                if line.distance_2(&q) > MATCH_RADIUS * MATCH_RADIUS {
                    continue;
                }
                // a wall runs along the surface: an extrusion crossing it (an infill end, a
                // thin feature's single line seen end-on) is no wall
                let dir = DVec2::from_array(line.to) - DVec2::from_array(line.from);
                if dir.length() > 0.0 && dir.normalize().dot(n).abs() > WALL_ALIGNMENT {
                    continue;
                }
                let e = DVec2::from_array(line.nearest_point(&q));
                m.push((n.dot(b + t - e), n));
            }
        }
        if m.len() < MIN_MATCHES {
            return Err(RegisterError::Undetermined {
                matched: m.len(),
                needed: MIN_MATCHES,
                reason: "too few of the cut's points have a printed wall within 1 mm",
            });
        }
        let mut rs: Vec<f64> = m.iter().map(|x| x.0).collect();
        rs.sort_by(f64::total_cmp);
        let median = rs[rs.len() / 2];
        let c0 = *c.get_or_insert(median);
        let mut dev: Vec<f64> = rs.iter().map(|r| (r - median).abs()).collect();
        dev.sort_by(f64::total_cmp);
        let sigma = 1.4826 * dev[dev.len() / 2];
        // the start may be off by the bounding box's error: first every match (Huber weights
        // only), then the fixed band, then the robust scale of what is left
        let limit = match it {
            0 => MATCH_RADIUS,
            1 => OUTLIER_MM,
            _ => (OUTLIER_SIGMAS * sigma).clamp(HUBER_MM, OUTLIER_MM),
        };
        let kept: Vec<_> = m
            .into_iter()
            .filter(|(r, _)| (r - median).abs() <= limit)
            .collect();
        // normal equations for (tx, ty, c): r = d − c with d = n·(b + t − e), J = (n, −1)
        let mut a = DMat3::ZERO;
        let mut g = DVec3::ZERO;
        let mut spread = [[0.0f64; 2]; 2];
        let mut sq = 0.0;
        for (d, n) in &kept {
            let r = d - c0;
            let w = if r.abs() <= HUBER_MM {
                1.0
            } else {
                HUBER_MM / r.abs()
            };
            let j = DVec3::new(n.x, n.y, -1.0);
            a += DMat3::from_cols(j * j.x, j * j.y, j * j.z) * w;
            g -= j * (w * r);
            spread[0][0] += n.x * n.x;
            spread[0][1] += n.x * n.y;
            spread[1][1] += n.y * n.y;
            sq += r * r;
        }
        let nk = kept.len().max(1) as f64;
        let (sxx, sxy, syy) = (spread[0][0] / nk, spread[0][1] / nk, spread[1][1] / nk);
        let min_eig = (sxx + syy) / 2.0 - (((sxx - syy) / 2.0).powi(2) + sxy * sxy).sqrt();
        if kept.len() < MIN_MATCHES || min_eig < MIN_SPREAD {
            return Err(RegisterError::Undetermined {
                matched: kept.len(),
                needed: MIN_MATCHES,
                reason: "the printed walls do not pin the placement in both directions",
            });
        }
        if a.determinant().abs() < 1e-12 {
            return Err(RegisterError::Undetermined {
                matched: kept.len(),
                needed: MIN_MATCHES,
                reason: "the fit is singular",
            });
        }
        let delta = a.inverse() * g;
        t += DVec2::new(delta.x, delta.y);
        c = Some(c0 + delta.z);
        last = (kept.len(), (sq / nk).sqrt());
        if delta.truncate().length() < 1e-6 {
            break;
        }
    }
    Ok(Fit {
        translation: t.to_array(),
        inset: c.unwrap_or(0.0),
        rms: last.1,
        matched: last.0,
        layers: data.len(),
    })
}
