//! An independent confirmation of a collision finding (issue 10 §5, "refused with a named
//! finding that an independent test helper confirms"). It shares nothing with
//! `warpslice::collision`: its own G-code reading, the tests' forward kinematics
//! ([`super::machine::fk::Fk`]), the head's solids read from the machine file's data (`MachineSpec::head`,
//! `bed`: the JSON, or the kind's documented defaults), printed material as **points** of the
//! beads (not a height field), and a point-in-solid test per part.
//!
//! - Material: every extruding move before the finding's line, its tip path sampled every
//!   [`STEP_MM`] through the kinematics, each sample giving bead points at the tip, ±w/4 and
//!   ±w/2 across (horizontally, perpendicular to the path), each also h/2 and h lower (w, h: the
//!   slicer's `;WIDTH:`, `;HEIGHT:`; 0.45 and 0.2 mm without them).
//! - The move: its axes interpolated linearly (as the firmware moves them) at [`POSES`] poses.
//! - The part at a pose, in the tool frame (origin the tip, z the tool axis n): cone `from ≤ s ≤
//!   from + length`, `ρ ≤ r_tip + (s − from) tan ψ`; cylinder; box in the frame the machine turns
//!   (docs/machines.md, src/machine/head.rs module documentation): B head `R_y(B)`, RTN
//!   `R_z(φ)·R_y(tilt)` with φ the azimuth of n, PAX `R_z(A − offset)·R_y(B)`, cartesian the
//!   identity; the machines that turn the part (the head fixed in the machine, its frame the
//!   machine's axes seen from the part): A/B table `R(b_dir, −B)·R(a_dir, −A)` (seed 004, the
//!   inverse of the table's turn, as the tests' kinematics writes n), polar `R_z(−C)·R_y(B)`;
//!   the triple-Z bed and the lathe check a box as the cylinder about the tool axis that
//!   contains it (a larger solid: such a confirmation is weaker, and says so).
//! - Contact (docs/machines.md, "Collision check"): a material point inside the part that starts
//!   at the tip counts only above the contact surface `s > (ρ + w/2)·tan 30°`, and by more than
//!   a layer height when it is of the move's own layer.
//! - The bed: the part's corners / rim points below the bed's top over the bed.
//!
//! A finding is confirmed when some material point (or, for the bed, some point of the part)
//! is inside the named part at some pose of the move.
//!
//! ## Depth
//! The checker reports the largest vertical overlap of the part with a material column (or the
//! bed). The helper measures its own: for every material point `q` inside the part at a pose,
//! the vertical line through `q` enters the part (the nozzle: the part of it above the contact
//! surface) at `z_in`, found by bisection — the part is convex (a frustum, a box, and for the
//! nozzle the cone cut by `s − ρ·tan 30° > c`, a superlevel set of a concave function), so the
//! line meets it in one interval — and the depth is the largest `q.z − z_in`; for the bed, the
//! bed's top less the lowest boundary point of the part over the bed. The two agree within
//! [`DEPTH_TOLERANCE_MM`].

use glam::{DMat3, DVec3};
use warpslice::machine::head::{BedSpec, HeadPart};
use warpslice::machine::MachineSpec;

use super::machine::fk::{rotate, Fk};

/// Spacing of the bead samples along the path, mm (a quarter of the line width).
pub const STEP_MM: f64 = 0.1;
/// Poses per move computed; the part is judged at those of them whose points moved at least
/// [`POSE_STEP_MM`] since the last judged one (and at the first and last).
pub const POSES: usize = 400;
/// Least motion of any point of the judged part between two judged poses, mm (a quarter of a
/// bead sample, [`STEP_MM`]): a rigid motion moves the part's points by at most
/// `|Δtip| + reach·θ` (θ the angle between the frames, or between the tool axes when the frame
/// is unknown), so skipped poses lie within it of a judged one.
pub const POSE_STEP_MM: f64 = 0.025;

/// How far the helper's depth may differ from the checker's, mm. The two sample differently:
/// - material: the helper's bead points lie every [`STEP_MM`] along, w/4 across and h/2 down,
///   so the deepest column is within (0.05, w/8) ≈ 0.075 mm of a point horizontally — times
///   the steepest lower face of a default part, the 40° nozzle cone (1/tan 40° = 1.19):
///   0.09 mm — and h/2 = 0.1 mm vertically;
/// - the bead top: the checker's follows the layer's slope across the bead (`src/collision/
///   bead.rs`), up to (w/2)·tan 30° = 0.13 mm above the helper's flat bead at the edge on the
///   30° cone layers; and it keeps one top per 0.2 mm cell (≤ 0.14 mm × tan 30° = 0.08 mm);
/// - the poses: the checker's are at most 0.2 mm of head motion apart, so its largest overlap
///   may be short of the move's by half a step times (1 + 1.19): 0.22 mm; the helper's 400
///   poses are closer.
///
/// Sum: 0.62 mm, rounded up to 0.65. A depth beyond it on either side is a disagreement.
pub const DEPTH_TOLERANCE_MM: f64 = 0.65;

/// The overlap the helper may miss between its points, mm: its bead points are within 0.075 mm
/// horizontally of any bead point (see [`DEPTH_TOLERANCE_MM`]), and a part's lower face rises
/// at most 1.19 mm per mm (the 40° nozzle cone), so an overlap shallower than 0.075 × 1.19 =
/// 0.09 mm may lie wholly between the points. On a sloped layer the checker's material also
/// stands higher than the helper's flat beads (see [`unseen_depth_mm`]).
pub const UNSEEN_DEPTH_MM: f64 = 0.09;

/// Half the diagonal of the checker's 0.2 mm material cell, mm, rounded up: a cell keeps the
/// highest bead top in it, up to this far across from where the helper has its point.
pub const CELL_REACH_MM: f64 = 0.14;

/// The shallowest overlap the helper is sure to see on a move whose tool axis is tilted by up to
/// `tilt_deg` from the part's vertical with beads `w` mm wide, mm: [`UNSEEN_DEPTH_MM`] between
/// the points, plus how much higher the checker's material may stand than the helper's flat
/// beads — its bead top follows the layer's slope (the tool axis is the layer's normal) across
/// the half-width, and its cell keeps the highest top within [`CELL_REACH_MM`]: `(w/2 +
/// CELL_REACH_MM)·tan(tilt)`. At 30° and w = 0.45: 0.09 + 0.21 = 0.30 mm. A finding shallower
/// than this that the helper does not re-find is reported as below its resolution, not as
/// confirmed.
pub fn unseen_depth_mm(tilt_deg: f64, w: f64) -> f64 {
    UNSEEN_DEPTH_MM + (0.5 * w + CELL_REACH_MM) * tilt_deg.to_radians().tan()
}

/// A finding the helper did not re-find: why, and the shallowest overlap it is sure to see on
/// that move ([`unseen_depth_mm`] at the move's largest tilt).
#[derive(Clone, Debug)]
pub struct Missed {
    pub why: String,
    pub unseen_mm: f64,
}

/// How far a part may reach beyond the bounding box of its [`boundary`] points, mm: the box
/// corners are exact, and the true end circles (every part is convex, the hull of its
/// boundary's circles or corners) lie within `rad·(1 − cos 2.5°)` < 0.001·rad of the 72-gon —
/// under 0.1 mm for any radius up to 100 mm.
const BOX_MARGIN_MM: f64 = 0.1;

/// Side of a [`Grid`] column, mm.
const GRID_MM: f64 = 1.0;

/// The material points near a move in columns of [`GRID_MM`] × [`GRID_MM`], each column's
/// points highest first, so that a pose visits only the points in its part's bounding box
/// (the same points the plain loop over all of them would find inside: a speed-up only).
struct Grid {
    lo: [i64; 2],
    nx: usize,
    ny: usize,
    /// Per column (x-major), indices into the points, by z descending.
    columns: Vec<Vec<u32>>,
}

impl Grid {
    fn cell(v: f64) -> i64 {
        (v / GRID_MM).floor() as i64
    }

    fn new(points: &[&Point]) -> Grid {
        let (mut lo, mut hi) = ([i64::MAX; 2], [i64::MIN; 2]);
        for pt in points {
            for (k, v) in [pt.q.x, pt.q.y].into_iter().enumerate() {
                lo[k] = lo[k].min(Self::cell(v));
                hi[k] = hi[k].max(Self::cell(v));
            }
        }
        if points.is_empty() {
            return Grid {
                lo: [0, 0],
                nx: 0,
                ny: 0,
                columns: Vec::new(),
            };
        }
        let (nx, ny) = ((hi[0] - lo[0] + 1) as usize, (hi[1] - lo[1] + 1) as usize);
        let mut columns = vec![Vec::new(); nx * ny];
        for (i, pt) in points.iter().enumerate() {
            let (cx, cy) = (Self::cell(pt.q.x) - lo[0], Self::cell(pt.q.y) - lo[1]);
            columns[cx as usize * ny + cy as usize].push(i as u32);
        }
        for c in &mut columns {
            c.sort_by(|&a, &b| points[b as usize].q.z.total_cmp(&points[a as usize].q.z));
        }
        Grid {
            lo,
            nx,
            ny,
            columns,
        }
    }

    /// The points inside the box [`blo`, `bhi`].
    fn within<'p>(
        &'p self,
        points: &'p [&'p Point],
        blo: DVec3,
        bhi: DVec3,
    ) -> impl Iterator<Item = &'p Point> + 'p {
        let clamp = |v: f64, k: usize, n: usize| (Self::cell(v) - self.lo[k]).clamp(-1, n as i64);
        let (x0, x1) = (clamp(blo.x, 0, self.nx).max(0), clamp(bhi.x, 0, self.nx));
        let (y0, y1) = (clamp(blo.y, 1, self.ny).max(0), clamp(bhi.y, 1, self.ny));
        let x1 = x1.min(self.nx as i64 - 1);
        let y1 = y1.min(self.ny as i64 - 1);
        (x0..=x1)
            .flat_map(move |x| (y0..=y1).map(move |y| x as usize * self.ny + y as usize))
            .flat_map(move |c| {
                self.columns[c]
                    .iter()
                    .map(move |&i| points[i as usize])
                    .skip_while(move |pt| pt.q.z > bhi.z)
                    .take_while(move |pt| pt.q.z >= blo.z)
                    .filter(move |pt| pt.q.cmpge(blo).all() && pt.q.cmple(bhi).all())
            })
    }
}

/// What the helper found for a finding.
#[derive(Clone, Debug)]
pub struct Confirmed {
    /// The helper's depth (see "Depth" above), mm.
    pub depth_mm: f64,
    /// Where and what, for the report.
    pub what: String,
    /// The box parts were checked as enclosing cylinders (no head frame for this machine).
    pub enclosing: bool,
}

/// A bead point: where, and the layer it was printed in.
#[derive(Clone, Copy)]
struct Point {
    q: DVec3,
    layer: u32,
}

/// `R_z(φ)·R_y(t)` (columns: the tool frame's x, y, z in the output frame).
fn turned(phi: f64, t: f64) -> DMat3 {
    let (sp, cp, st, ct) = (phi.sin(), phi.cos(), t.sin(), t.cos());
    DMat3::from_cols(
        DVec3::new(ct * cp, ct * sp, -st),
        DVec3::new(-sp, cp, 0.0),
        DVec3::new(st * cp, st * sp, ct),
    )
}

/// The tool frame for written axes (`None`: not known, boxes as enclosing cylinders).
fn frame(fk: &Fk, axes: &[f64], n: DVec3) -> Option<DMat3> {
    match fk {
        Fk::Cartesian { .. } => Some(DMat3::IDENTITY),
        Fk::BHead { .. } => Some(turned(0.0, axes[3].to_radians())),
        Fk::Rtn { .. } => Some(turned(n.y.atan2(n.x), n.z.clamp(-1.0, 1.0).acos())),
        Fk::Pax { offset_deg, .. } => Some(turned(
            (axes[3] - offset_deg).to_radians(),
            axes[4].to_radians(),
        )),
        Fk::AbTable { a_dir, b_dir, .. } => {
            let (a, b) = (axes[3].to_radians(), axes[4].to_radians());
            let col = |e: DVec3| rotate(rotate(e, *a_dir, -a), *b_dir, -b);
            Some(DMat3::from_cols(
                col(DVec3::X),
                col(DVec3::Y),
                col(DVec3::Z),
            ))
        }
        Fk::RTheta { .. } => Some(turned(-axes[1].to_radians(), axes[3].to_radians())),
        _ => None,
    }
}

/// A part posed at tip `p`, axis `n`, frame `r`, against beads of width `w`; for the tip part
/// the contact surface is raised by `press` (mm along the axis).
struct Posed<'a> {
    part: &'a HeadPart,
    p: DVec3,
    n: DVec3,
    r: Option<&'a DMat3>,
    w: f64,
    press: f64,
    /// tan 30° (the contact surface's slope).
    t30: f64,
    /// The cone's tan ψ (0 for other parts).
    tan_psi: f64,
}

/// Whether `q` (output frame) is inside the posed part (the tip part: above its contact
/// surface).
fn inside(at: &Posed<'_>, q: DVec3) -> bool {
    let Posed {
        part,
        p,
        n,
        r,
        w,
        press,
        t30,
        tan_psi,
    } = *at;
    let d = q - p;
    let s = n.dot(d);
    let rho = (d.length_squared() - s * s).max(0.0).sqrt();
    match part {
        HeadPart::Cone {
            tip_radius_mm,
            length_mm,
            from_mm,
            ..
        } => {
            let inside = s >= *from_mm
                && s <= from_mm + length_mm
                && rho <= tip_radius_mm + (s - from_mm) * tan_psi;
            let tip = *from_mm <= 0.0;
            inside && (!tip || s > (rho + w / 2.0) * t30 + press)
        }
        HeadPart::Cylinder {
            radius_mm,
            from_mm,
            to_mm,
            ..
        } => s >= *from_mm && s <= *to_mm && rho <= *radius_mm,
        HeadPart::Box { min, max, .. } => match r {
            Some(r) => {
                let l = r.transpose() * d;
                (0..3).all(|i| l[i] >= min[i] && l[i] <= max[i])
            }
            None => {
                let rad = [min[0], max[0]]
                    .iter()
                    .flat_map(|x| [min[1], max[1]].map(|y| x.hypot(y)))
                    .fold(0.0, f64::max);
                s >= min[2] && s <= max[2] && rho <= rad
            }
        },
        _ => false,
    }
}

/// Points of the part's boundary (for the bed): box corners, the cone's and cylinder's end
/// circles at 72 angles.
fn boundary(part: &HeadPart, p: DVec3, n: DVec3, r: Option<&DMat3>) -> Vec<DVec3> {
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let circle = |s: f64, rad: f64| -> Vec<DVec3> {
        (0..72)
            .map(|k| {
                let a = k as f64 * 5f64.to_radians();
                p + n * s + (u * a.cos() + v * a.sin()) * rad
            })
            .collect()
    };
    match part {
        HeadPart::Cone {
            tip_radius_mm,
            half_angle_deg,
            length_mm,
            from_mm,
            ..
        } => {
            let mut c = circle(*from_mm, *tip_radius_mm);
            c.extend(circle(
                from_mm + length_mm,
                tip_radius_mm + length_mm * half_angle_deg.to_radians().tan(),
            ));
            c
        }
        HeadPart::Cylinder {
            radius_mm,
            from_mm,
            to_mm,
            ..
        } => {
            let mut c = circle(*from_mm, *radius_mm);
            c.extend(circle(*to_mm, *radius_mm));
            c
        }
        HeadPart::Box { min, max, .. } => match r {
            Some(r) => (0..8)
                .map(|c| {
                    let l = DVec3::new(
                        if c & 1 == 0 { min[0] } else { max[0] },
                        if c & 2 == 0 { min[1] } else { max[1] },
                        if c & 4 == 0 { min[2] } else { max[2] },
                    );
                    p + *r * l
                })
                .collect(),
            None => {
                let rad = [min[0], max[0]]
                    .iter()
                    .flat_map(|x| [min[1], max[1]].map(|y| x.hypot(y)))
                    .fold(0.0, f64::max);
                let mut c = circle(min[2], rad);
                c.extend(circle(max[2], rad));
                c
            }
        },
        _ => Vec::new(),
    }
}

fn covers(bed: &BedSpec, q: DVec3) -> Option<f64> {
    match bed {
        BedSpec::Plate { min, max, top_mm } => {
            (q.x >= min[0] && q.x <= max[0] && q.y >= min[1] && q.y <= max[1]).then_some(*top_mm)
        }
        BedSpec::Disc {
            center,
            radius_mm,
            top_mm,
        } => ((q.x - center[0]).hypot(q.y - center[1]) <= *radius_mm).then_some(*top_mm),
        _ => None,
    }
}

/// Confirm the finding "`part` into `obstacle` (`material` or `bed`) on output line `line`
/// (1-based)" in the machine G-code `gcode` written for `spec`: `Ok(description)` when the
/// helper finds the part there too.
pub fn confirm(
    spec: &MachineSpec,
    gcode: &str,
    line: usize,
    part: &str,
    obstacle: &str,
) -> Result<Confirmed, String> {
    confirm_or_miss(spec, gcode, line, part, obstacle).map_err(|m| m.why)
}

/// [`confirm`], saying on a miss how shallow an overlap the helper may miss on that move.
pub fn confirm_or_miss(
    spec: &MachineSpec,
    gcode: &str,
    line: usize,
    part: &str,
    obstacle: &str,
) -> Result<Confirmed, Missed> {
    walk(spec, gcode, line, part, obstacle).unwrap_or_else(|why| {
        Err(Missed {
            why,
            unseen_mm: UNSEEN_DEPTH_MM,
        })
    })
}

/// Reads the file up to `line` and judges that move: `Err` when the file cannot be read so far.
fn walk(
    spec: &MachineSpec,
    gcode: &str,
    line: usize,
    part: &str,
    obstacle: &str,
) -> Result<Result<Confirmed, Missed>, String> {
    let fk = Fk::from_spec(spec)?;
    let letters: Vec<String> = spec
        .axis_names()
        .map_err(|e| e.to_string())?
        .iter()
        .map(|n| n[..1].to_ascii_uppercase())
        .collect();
    let head = spec.head().map_err(|e| e.to_string())?;
    let bed = spec.bed().map_err(|e| e.to_string())?;
    let the_part = head
        .parts
        .iter()
        .find(|p| p.name() == part)
        .ok_or(format!("no head part '{part}'"))?
        .clone();
    let (mut raw, mut offset) = (vec![0.0; letters.len()], vec![0.0; letters.len()]);
    let (mut rel_e, mut e_last) = (true, 0.0);
    let (mut w, mut h, mut layer) = (0.45, 0.2, 0u32);
    let mut points: Vec<Point> = Vec::new();
    for (i, text) in gcode.lines().enumerate() {
        let number = i + 1;
        let (code, comment) = match text.find(';') {
            Some(k) => (&text[..k], text[k + 1..].trim()),
            None => (text, ""),
        };
        if comment.starts_with("LAYER_CHANGE") || comment.starts_with("LAYER:") {
            layer += 1;
        } else if let Some(v) = comment.strip_prefix("WIDTH:") {
            w = v.trim().parse().unwrap_or(w);
        } else if let Some(v) = comment.strip_prefix("HEIGHT:") {
            h = v.trim().parse().unwrap_or(h);
        }
        let words: Vec<(String, f64)> = code
            .split_whitespace()
            .filter_map(|t| Some((t[..1].to_ascii_uppercase(), t[1..].parse().ok()?)))
            .collect();
        let get = |l: &str| words.iter().find(|(k, _)| k == l).map(|(_, v)| *v);
        match (get("G"), get("M")) {
            (_, Some(82.0)) => rel_e = false,
            (_, Some(83.0)) => rel_e = true,
            (Some(91.0), _) => return Err("G91 is not read by this helper".into()),
            (Some(92.0), _) => {
                if let Some(e) = get("E") {
                    e_last = e;
                }
                for (k, l) in letters.iter().enumerate() {
                    if let Some(v) = get(l) {
                        offset[k] = raw[k] - v;
                    }
                }
            }
            (Some(g), _) if g == 0.0 || g == 1.0 => {
                let from = raw.clone();
                let mut to = from.clone();
                let mut any = false;
                for (k, l) in letters.iter().enumerate() {
                    if let Some(v) = get(l) {
                        to[k] = v + offset[k];
                        any = true;
                    }
                }
                let extrudes = get("E").is_some_and(|e| if rel_e { e > 0.0 } else { e > e_last });
                if let (Some(e), false) = (get("E"), rel_e) {
                    e_last = e;
                }
                if !any {
                    continue;
                }
                let at = |t: f64| -> Vec<f64> {
                    from.iter().zip(&to).map(|(a, b)| a + (b - a) * t).collect()
                };
                if number == line {
                    return judge(&fk, &the_part, obstacle, &bed, &points, layer, w, h, &at);
                }
                if extrudes {
                    let (p0, _) = fk.forward(&from)?;
                    let (p1, _) = fk.forward(&to)?;
                    let k = ((p1 - p0).length() / STEP_MM).ceil().max(1.0) as usize;
                    let dir = (p1 - p0).truncate();
                    let across = if dir.length() > 1e-9 {
                        DVec3::new(-dir.y, dir.x, 0.0).normalize()
                    } else {
                        DVec3::ZERO
                    };
                    for j in 0..=k {
                        let (q, _) = fk.forward(&at(j as f64 / k as f64))?;
                        for c in [-0.5, -0.25, 0.0, 0.25, 0.5] {
                            for dz in [0.0, 0.5, 1.0] {
                                points.push(Point {
                                    q: q + across * (c * w) - DVec3::Z * (dz * h),
                                    layer,
                                });
                            }
                        }
                    }
                }
                raw = to;
            }
            _ => {}
        }
    }
    Err(format!("line {line} is not a move of the file"))
}

/// Where the vertical line through `q` (inside the part) enters it from below: bisection
/// between `q` and `below` mm under it, outside the part (the part and the contact-cut nozzle
/// are convex, so the line meets them in one interval), to 1e-6 mm.
fn entry_z(at: &Posed<'_>, q: DVec3, below: f64) -> f64 {
    let (mut lo, mut hi) = (q.z - below, q.z);
    while hi - lo > 1e-6 {
        let mid = 0.5 * (lo + hi);
        if inside(at, DVec3::new(q.x, q.y, mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The farthest point of `part` from the tip, mm: a point of its rim circles or corners
/// ([`boundary`] in the tool frame), since every part is convex.
fn reach(part: &HeadPart) -> f64 {
    boundary(part, DVec3::ZERO, DVec3::Z, Some(&DMat3::IDENTITY))
        .iter()
        .map(|q| q.length())
        .fold(0.0, f64::max)
}

#[allow(clippy::too_many_arguments)]
fn judge(
    fk: &Fk,
    part: &HeadPart,
    obstacle: &str,
    bed: &BedSpec,
    points: &[Point],
    layer: u32,
    w: f64,
    h: f64,
    at: &dyn Fn(f64) -> Vec<f64>,
) -> Result<Result<Confirmed, Missed>, String> {
    let far = reach(part);
    let mut best: Option<Confirmed> = None;
    let mut enclosing = false;
    // the material near the move: within the part's reach of some pose's tip (poses every
    // 1/POSES of the move; the tip moves less than a bead sample between two of them on the
    // matrix's moves, and the margin of a line width covers it)
    let poses: Vec<(Vec<f64>, DVec3, DVec3)> = (0..=POSES)
        .map(|k| {
            let axes = at(k as f64 / POSES as f64);
            fk.forward(&axes).map(|(p, n)| (axes, p, n))
        })
        .collect::<Result<_, _>>()?;
    let (lo, hi) = poses.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), (_, p, _)| (lo.min(*p), hi.max(*p)),
    );
    let margin = DVec3::splat(far + w);
    let near: Vec<&Point> = points
        .iter()
        .filter(|pt| pt.q.cmpge(lo - margin).all() && pt.q.cmple(hi + margin).all())
        .collect();
    let grid = Grid::new(&near);
    let t30 = 30f64.to_radians().tan();
    let tan_psi = match part {
        HeadPart::Cone { half_angle_deg, .. } => half_angle_deg.to_radians().tan(),
        _ => 0.0,
    };
    let mut last: Option<(DVec3, DVec3, Option<DMat3>)> = None;
    for (k, (axes, p, n)) in poses.iter().enumerate() {
        let (p, n) = (*p, *n);
        let r = frame(fk, axes, n);
        // judged when its points moved POSE_STEP_MM since the last judged pose (the ends always)
        if let (Some((lp, ln, lr)), true) = (&last, k > 0 && k < POSES) {
            let theta = match (lr, &r) {
                (Some(a), Some(b)) => {
                    let m = *b * a.transpose();
                    ((m.x_axis.x + m.y_axis.y + m.z_axis.z - 1.0) / 2.0)
                        .clamp(-1.0, 1.0)
                        .acos()
                }
                _ => ln.angle_between(n),
            };
            if (p - *lp).length() + far * theta < POSE_STEP_MM {
                continue;
            }
        }
        last = Some((p, n, r));
        enclosing |= r.is_none() && matches!(part, HeadPart::Box { .. });
        let mut deepest = |depth: f64, what: String| {
            if best.as_ref().is_none_or(|b| depth > b.depth_mm) {
                best = Some(Confirmed {
                    depth_mm: depth,
                    what,
                    enclosing,
                });
            }
        };
        if obstacle == "bed" {
            for q in boundary(part, p, n, r.as_ref()) {
                if let Some(top) = covers(bed, q) {
                    if q.z < top {
                        deepest(
                            top - q.z,
                            format!("the {} reaches below the bed at {q}", part.name()),
                        );
                    }
                }
            }
        } else {
            // only the points in the part's bounding box at this pose (see [`Grid`])
            let (blo, bhi) = boundary(part, p, n, r.as_ref()).iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), q| (lo.min(*q), hi.max(*q)),
            );
            let (blo, bhi) = (
                blo - DVec3::splat(BOX_MARGIN_MM),
                bhi + DVec3::splat(BOX_MARGIN_MM),
            );
            for pt in grid.within(&near, blo, bhi) {
                if (pt.q - p).length() > far {
                    continue;
                }
                let at = Posed {
                    part,
                    p,
                    n,
                    r: r.as_ref(),
                    w,
                    press: if pt.layer == layer { h } else { 0.0 },
                    t30,
                    tan_psi,
                };
                if inside(&at, pt.q) {
                    let z_in = entry_z(&at, pt.q, 3.0 * far);
                    deepest(
                        pt.q.z - z_in,
                        format!(
                            "bead point {} of layer {} is inside the {} (tip {p}, axis {n})",
                            pt.q,
                            pt.layer,
                            part.name()
                        ),
                    );
                }
            }
        }
    }
    // the largest tilt of the tool axis from the part's vertical over the move (the layer's
    // slope there: the tool axis is the layer's normal)
    let tilt = poses
        .iter()
        .map(|(_, _, n)| n.z.clamp(-1.0, 1.0).acos().to_degrees())
        .fold(0.0, f64::max);
    Ok(best.ok_or(Missed {
        why: format!(
            "no {obstacle} inside the {} over the move's {POSES} poses (tilt up to {tilt:.1}°)",
            part.name()
        ),
        unseen_mm: unseen_depth_mm(tilt, w),
    }))
}
