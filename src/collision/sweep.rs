//! The swept check: the head's solids at poses sampled along a move, against the material
//! printed so far and the bed.
//!
//! ## Sampling
//! The firmware moves every axis linearly, so the pose at `t ∈ [0, 1]` is
//! `forward(a₀ + t (a₁ − a₀))` (tip, tool axis and [`crate::machine::Machine::head_frame`]).
//! Between two consecutive samples no point of the head moves more than
//! [`SAMPLE_STEP_MM`]: the bound `|Δtip| + R·θ` (R the farthest head point from the tip, θ the
//! rotation angle between the two frames; the angle between the tool axes when the frame is
//! unknown) is checked for every pair, doubling the samples until it holds (at most
//! [`MAX_SAMPLES`]; the report counts moves that hit it). Each part is then checked at as few
//! of these poses as keep its own points within the step between two checked poses (its own
//! reach in the bound: the 4.5 mm nozzle turning with a 55 mm head needs a fraction of the
//! samples; `checked_poses`). So a bead of a line width (≥ 0.4 mm) cannot pass between two
//! checked poses of a head part.
//!
//! ## Depth
//! For each sampled pose and part, every height-field cell under the part: the vertical line
//! through its centre enters the part at `z_in`, leaves at `z_out`; the material fills the
//! column up to `h`; the overlap is `min(h, z_out) − z_in`; for the nozzle (the part that
//! starts at the tip) only the part of it above the contact surface counts, less a layer height
//! for the current layer's beads ([`super::contact`]). The bed is a column up to its top over
//! its plate. A finding is an overlap above [`CONTACT_TOLERANCE_MM`], kept per (move, part,
//! obstacle) with its largest depth.

use glam::{DMat3, DVec3};

use super::bead;
use super::contact::ContactSurface;
use super::cull::{capsule_row, Reach, TipLine};
use super::material::{cell_of, centre, Material, CELL_MM};
use super::samples::Samples;
use super::solid::Posed;
use super::stretch::Stretch;
use super::turn::{acos_bracket, exceeds_bracketed, BRACKET_MARGIN};
use crate::emit::CollisionFinding;
use crate::machine::head::{BedSpec, HeadPart};
use crate::machine::{Machine, MachineError, MachineSpec};
use crate::num;

/// Largest displacement of any head point between two sampled poses of a move, mm: half the
/// thinnest line width (0.4 mm) the check is built for.
pub const SAMPLE_STEP_MM: f64 = 0.2;
/// Overlaps up to this depth (mm) are not reported: the 3-decimal output rounding (0.0005 mm),
/// the firmware interpolation bound (0.02 mm) and the height field's f32 heights, with margin.
/// The nozzle's contact with the layer it prints is the contact surface's business
/// ([`super::contact`]), not this tolerance's.
pub const CONTACT_TOLERANCE_MM: f64 = 0.05;
/// The layer height when the G-code gives none (`;HEIGHT:`), mm: the slicers' usual 0.2 mm
/// (and `../shared/tools/slice.sh`'s).
pub const DEFAULT_LAYER_HEIGHT_MM: f64 = 0.2;
/// Largest displacement of a part's points within one stretch of poses whose reachable cells
/// are found once ([`Checker::cells_near`]: the part at the stretch's first pose grown by it),
/// mm. Larger: fewer searches of the height field, but longer lists checked at every pose
/// (the nozzle's grown face takes in the layer it rides on): on the PrusaSlicer idler, conic
/// 30°, 0.3 mm was the best of 0.15–2.5 for the long RTN/RotBot nozzles and within 15 % of the
/// best for the PAX head (`cargo run --release --example bench`, section 3).
pub const STRETCH_MM: f64 = 0.3;
/// [`STRETCH_MM`] for a part without the contact rule (heater block, heat sink) whose last list
/// was empty, mm: such a part is usually far from the material, its grown solid still reaches
/// nothing, and one search covers many more poses (and moves: `collision/stretch.rs`).
pub const CLEAR_STRETCH_MM: f64 = 1.0;
/// Most samples of one move.
pub const MAX_SAMPLES: usize = 1 << 14;
/// Most axes of a machine the check reads (the presets have 3 to 6; a pose is interpolated on
/// the stack).
pub const MAX_AXES: usize = 8;

/// Counts of the check.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CheckStats {
    /// Moves checked.
    pub moves: u64,
    /// Poses sampled.
    pub samples: u64,
    /// Moves whose sampling stopped at [`MAX_SAMPLES`] before the step bound held.
    pub under_sampled: u64,
}

/// A head part, as checked: its name, and the solid in the tool frame (origin the tip, z the
/// tool axis).
#[derive(Clone, Debug)]
struct Part {
    name: String,
    shape: Local,
    /// Farthest point from the tip, mm.
    reach: f64,
    /// The part starts at the tip (the nozzle): the contact rule applies to it
    /// ([`super::contact`]).
    tip: bool,
}

#[derive(Clone, Copy, Debug)]
enum Local {
    Frustum { s0: f64, s1: f64, r0: f64, k: f64 },
    Box { min: DVec3, max: DVec3 },
}

impl Part {
    fn new(p: &HeadPart) -> Part {
        let (shape, reach) = match p {
            HeadPart::Cone {
                tip_radius_mm,
                half_angle_deg,
                length_mm,
                from_mm,
                ..
            } => {
                let k = num::tan(num::rad(*half_angle_deg));
                let s1 = from_mm + length_mm;
                (
                    Local::Frustum {
                        s0: *from_mm,
                        s1,
                        r0: *tip_radius_mm,
                        k,
                    },
                    s1.hypot(tip_radius_mm + k * length_mm),
                )
            }
            HeadPart::Cylinder {
                radius_mm,
                from_mm,
                to_mm,
                ..
            } => (
                Local::Frustum {
                    s0: *from_mm,
                    s1: *to_mm,
                    r0: *radius_mm,
                    k: 0.0,
                },
                from_mm.abs().max(to_mm.abs()).hypot(*radius_mm),
            ),
            HeadPart::Box { min, max, .. } => {
                let (min, max) = (DVec3::from_array(*min), DVec3::from_array(*max));
                (Local::Box { min, max }, min.abs().max(max.abs()).length())
            }
        };
        let tip = match shape {
            Local::Frustum { s0, .. } => s0 <= 0.0,
            Local::Box { min, .. } => min.z <= 0.0,
        };
        Part {
            name: p.name().to_string(),
            shape,
            reach,
            tip,
        }
    }

    /// The part at tip `p`, tool axis `n`, frame `frame` (None: the box as the cylinder about
    /// the tool axis that contains it).
    fn pose(&self, p: DVec3, n: DVec3, frame: Option<&DMat3>) -> Posed {
        match (self.shape, frame) {
            (Local::Frustum { s0, s1, r0, k }, _) => Posed::Frustum {
                o: p,
                a: n,
                s0,
                s1,
                r0,
                k,
            },
            (Local::Box { min, max }, Some(r)) => Posed::Box {
                o: p,
                r: *r,
                min,
                max,
            },
            (Local::Box { min, max }, None) => {
                let rad = [min.x, max.x]
                    .iter()
                    .flat_map(|x| [min.y, max.y].map(|y| x.hypot(y)))
                    .fold(0.0, f64::max);
                Posed::Frustum {
                    o: p,
                    a: n,
                    s0: min.z,
                    s1: max.z,
                    r0: rad,
                    k: 0.0,
                }
            }
        }
    }
}

/// A material cell a part may reach during a move ([`Checker::swept_cells`]): its centre,
/// top and bead.
#[derive(Clone, Copy, Debug)]
struct SweptCell {
    x: f64,
    y: f64,
    h: f64,
    bead: u32,
}

/// The cells each part may reach over one move ([`Checker::lists`]).
struct Lists {
    /// The lists.
    cells: Vec<Vec<SweptCell>>,
    /// `of[part][pose]`: the pose's list (None: the part is not checked there, or not against
    /// the material's cells this way).
    of: Vec<Vec<Option<usize>>>,
    /// The stretches still open at the move's end (part, stretch, list).
    open: Vec<(usize, Stretch, usize)>,
}

/// One sampled pose.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pose {
    /// The tip.
    pub p: DVec3,
    /// The tool axis.
    pub n: DVec3,
    /// The head frame, where the machine knows it.
    pub frame: Option<DMat3>,
}

/// Upper bound of the displacement between poses `a` and `b` of any head point within `reach`
/// of the tip, mm: `|Δtip| + reach·θ`, θ the angle of the rotation between the two frames (a
/// point at distance ρ ≤ reach from the tip moves by at most `2ρ sin(θ/2) ≤ ρθ` about it), or
/// the angle between the tool axes when the frame is unknown (the solids are then of
/// revolution about the axis: [`Part::pose`]).
pub(crate) fn displacement(a: &Pose, b: &Pose, reach: f64) -> f64 {
    let theta = match cos_turn(a, b) {
        Some(c) => num::acos(c),
        None => a.n.angle_between(b.n),
    };
    (b.p - a.p).length() + reach * theta
}

/// The cosine of the rotation angle between the frames of poses `a` and `b`, from the trace of
/// `R_b R_aᵀ` (`tr = 1 + 2 cos θ`), clamped to [−1, 1]; `None` when a frame is unknown.
fn cos_turn(a: &Pose, b: &Pose) -> Option<f64> {
    match (&a.frame, &b.frame) {
        (Some(ra), Some(rb)) => {
            let r = *rb * ra.transpose();
            Some(((r.x_axis.x + r.y_axis.y + r.z_axis.z - 1.0) * 0.5).clamp(-1.0, 1.0))
        }
        _ => None,
    }
}

/// Whether [`displacement`]`(a, b, reach) > limit`: the same answer, the frames' turn decided
/// from [`acos_bracket`] where it can ([`exceeds_bracketed`]; the arc cosine only for sums
/// within the bracket's gap of the limit).
fn displacement_exceeds(a: &Pose, b: &Pose, reach: f64, limit: f64) -> bool {
    match cos_turn(a, b) {
        Some(c) => exceeds_bracketed((b.p - a.p).length(), reach, c, limit, num::acos),
        None => displacement(a, b, reach) > limit,
    }
}

/// Added to the upper bound of a turn's angle in [`turn_bound`], rad: the cosine from the
/// frames' trace carries a few ulps of rounding, which near `c = 1` moves the angle by up to
/// `√(2·δc)` ≈ 5·10⁻⁸ rad for `δc` ≈ 10⁻¹⁵; 10⁻⁶ rad is 0.06 µm at a 60 mm reach.
const TURN_SLACK_RAD: f64 = 1e-6;

/// An upper bound, rad, of the true angle of the turn from pose `a` to pose `b` (the frames'
/// rotation, or the tool axes' angle without frames), without an arc cosine: the upper end
/// of [`acos_bracket`] of the computed cosine plus [`TURN_SLACK_RAD`] for its rounding.
fn turn_bound(a: &Pose, b: &Pose) -> f64 {
    let c = cos_turn(a, b)
        .unwrap_or_else(|| a.n.dot(b.n) / (a.n.length_squared() * b.n.length_squared()).sqrt());
    acos_bracket(c).1 + TURN_SLACK_RAD
}

/// A horizontal radius about the tip outside which neither `solid` nor the region above
/// `contact` comes below height `m` (`None`: none known): the lesser of
/// [`Posed::radius_below`] and [`ContactSurface::radius_below`] (the depth counted at a cell
/// is at most its top less the higher of the two floors, so either one above `m` rules the
/// cell out).
fn radius_below(solid: &Posed, contact: Option<&ContactSurface>, m: f64) -> Option<f64> {
    match (
        solid.radius_below(m),
        contact.and_then(|c| c.radius_below(m)),
    ) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    }
}

/// Which of a move's sampled poses a part is checked at: the first and the last, and between
/// them as few as keep every two consecutive checked poses within [`SAMPLE_STEP_MM`] for the
/// part's own points ([`displacement`] with the part's reach). The samples are dense enough
/// for the farthest head point; a short part (the nozzle, 4.5 mm against the heat sink's 55 mm)
/// turning with the head needs fewer: a pose is kept when the next one is beyond the step from
/// the last kept one, so every pair of consecutive kept poses is within the step (the pair
/// `(last, k)` passed that test one pose earlier; an adjacent pair is within it by the
/// sampling, unless the move is under-sampled, which the stats count).
fn checked_poses(poses: &[Pose], reach: f64) -> Vec<bool> {
    let n = poses.len();
    let mut keep = vec![false; n];
    let mut last = 0;
    for k in 0..n {
        if k == 0
            || k + 1 == n
            || displacement_exceeds(&poses[last], &poses[k + 1], reach, SAMPLE_STEP_MM)
        {
            keep[k] = true;
            last = k;
        }
    }
    keep
}

/// A box holding `part` at every pose `q` of a move whose tip distance and turn from its first
/// pose `p0` are bounded by `away` (`(|q.p − p0.p|, turn_bound(p0, q))` per pose): the part's
/// box at `p0` grown by `max (|Δtip| + reach·θ)` (a point at distance ρ ≤ reach from the tip
/// moves by `|Δtip| + 2ρ sin(θ/2) ≤ |Δtip| + reach·θ`), widened by [`BRACKET_MARGIN`] for
/// rounding. Law test `a_parts_grown_box_holds_it_at_every_pose_of_the_move`.
fn grown_box(part: &Part, p0: &Pose, away: &[(f64, f64)]) -> (DVec3, DVec3) {
    let grow = away
        .iter()
        .map(|&(d, theta)| d + part.reach * theta)
        .fold(0.0, f64::max)
        * (1.0 + BRACKET_MARGIN);
    let (l, h) = part.pose(p0.p, p0.n, p0.frame.as_ref()).aabb();
    (l - grow, h + grow)
}

/// The collision checker of one machine: head, bed, material printed so far.
pub struct Checker {
    machine: Box<dyn Machine>,
    parts: Vec<Part>,
    reach: f64,
    bed: BedSpec,
    material: Material,
    stats: CheckStats,
    findings: Vec<CollisionFinding>,
    layer: u32,
    /// The widest bead deposited so far (the contact surface's w), mm.
    max_width: f64,
    /// The layer height the current layer's beads may be pressed by, mm
    /// ([`super::contact`]).
    layer_height: f64,
    /// Stop checking after the first finding ([`Checker::stop_at_first`]).
    stop: bool,
    /// Check every cell under every part at every pose, without the bounds
    /// ([`Checker::exhaustive`]).
    exhaustive: bool,
    /// Per part, the stretch whose list the next move may go on using, with the list
    /// ([`super::stretch`]).
    live: Vec<Option<(Stretch, Vec<SweptCell>)>>,
    /// Per part, whether its last searched list was empty (a part without the contact rule then
    /// searches over [`CLEAR_STRETCH_MM`]).
    clear: Vec<bool>,
    /// The poses sampled along the last move checked, reused by its bead and the next move
    /// ([`super::samples`]).
    samples: Samples,
}

impl std::fmt::Debug for Checker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Checker")
            .field("machine", &self.machine.name())
            .field("parts", &self.parts)
            .field("bed", &self.bed)
            .field("stats", &self.stats)
            .finish()
    }
}

impl Checker {
    /// The checker for `spec` (its head and bed, or the kind's defaults). The lathe is refused:
    /// its layers are not graphs over the bed, so the height field cannot hold them.
    pub fn new(spec: &MachineSpec) -> Result<Checker, MachineError> {
        let machine = spec.build()?;
        if spec.kinematics.kind_name() == "lathe-a" {
            return Err(MachineError::CollisionUnsupported {
                machine: machine.name().to_string(),
                reason: "the mandrel's layers wrap round the part, and the check's height field holds only layers that are graphs over the bed".into(),
            });
        }
        let parts: Vec<Part> = spec.head()?.parts.iter().map(Part::new).collect();
        let reach = parts.iter().map(|p| p.reach).fold(0.0, f64::max);
        let n = parts.len();
        Ok(Checker {
            machine,
            parts,
            reach,
            bed: spec.bed()?,
            material: Material::new(),
            stats: CheckStats::default(),
            findings: Vec::new(),
            layer: 0,
            max_width: 0.0,
            layer_height: DEFAULT_LAYER_HEIGHT_MM,
            stop: false,
            exhaustive: false,
            live: vec![None; n],
            clear: vec![false; n],
            samples: Samples::default(),
        })
    }

    /// The layer height of the beads deposited from now on (the slicer's `;HEIGHT:`), mm: the
    /// depth by which the nozzle's face may press the current layer's beads (contact, see
    /// [`super::contact`]). Values outside (0, 2] mm are ignored.
    pub fn set_layer_height(&mut self, h: f64) {
        if h > 0.0 && h <= 2.0 {
            self.layer_height = h;
        }
    }

    /// Stop checking moves after the first finding (a refusal needs only it; the moves after
    /// it are still deposited). Off by default: every finding is kept.
    pub fn stop_at_first(&mut self, yes: bool) {
        self.stop = yes;
    }

    /// Check without the speed bounds (off by default): every part at every pose against every
    /// material cell under its box and the bed, none skipped because a bound says it cannot
    /// reach (the move's union box against the block maxima, the swept cells of a translation,
    /// the radius about the tip and the block distances, the floors of [`Posed::floor_at`] and
    /// [`ContactSurface::floor_at`]). The findings must be the same: it is the reference of the
    /// bounds' law test (`tests/collision_check.rs`), and slow.
    pub fn exhaustive(&mut self, yes: bool) {
        self.exhaustive = yes;
    }

    /// The machine checked.
    pub fn machine(&self) -> &dyn Machine {
        self.machine.as_ref()
    }

    /// Counts so far.
    pub fn stats(&self) -> CheckStats {
        self.stats
    }

    /// The material printed so far.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// Every finding so far, in file order.
    pub fn findings(&self) -> &[CollisionFinding] {
        &self.findings
    }

    /// Every finding so far, to be completed by the caller (the input line, which only the
    /// unwarp knows).
    pub fn findings_mut(&mut self) -> &mut [CollisionFinding] {
        &mut self.findings
    }

    /// Take the findings.
    pub fn take_findings(&mut self) -> Vec<CollisionFinding> {
        std::mem::take(&mut self.findings)
    }

    fn pose(&self, axes: &[f64]) -> Result<Pose, MachineError> {
        let (p, n, frame) = self.machine.pose(axes)?;
        Ok(Pose { p, n, frame })
    }

    /// The pose of `axes`: the last move's kept end when they are its axes bit for bit
    /// ([`super::samples`]), else solved.
    fn kept_or_solved(&self, axes: &[f64]) -> Result<Pose, MachineError> {
        match self.samples.end(axes) {
            Some(p) => Ok(p),
            None => self.pose(axes),
        }
    }

    /// The pose at `t` of the way from axes `from` to `to` (each axis linear, as the firmware
    /// moves them; at most [`MAX_AXES`], interpolated on the stack).
    fn pose_between(&self, from: &[f64], to: &[f64], t: f64) -> Result<Pose, MachineError> {
        let mut buf = [0.0; MAX_AXES];
        let axes = &mut buf[..from.len().min(MAX_AXES)];
        for ((x, a), b) in axes.iter_mut().zip(from).zip(to) {
            *x = a + (b - a) * t;
        }
        self.pose(axes)
    }

    /// The head's parts at the pose of `axes` (machine order), named, each the solid the check
    /// tests at that pose ([`Part::pose`] at the machine's forward kinematics and head frame):
    /// what the page draws ([`super::posed_head`]).
    pub fn posed_head(&self, axes: &[f64]) -> Result<Vec<(String, Posed)>, MachineError> {
        let pose = self.pose(axes)?;
        Ok(self
            .parts
            .iter()
            .map(|part| {
                (
                    part.name.clone(),
                    part.pose(pose.p, pose.n, pose.frame.as_ref()),
                )
            })
            .collect())
    }

    /// How many poses the last move kept (`super::samples`), for the tests.
    #[cfg(test)]
    fn samples_kept(&self) -> usize {
        self.samples.len()
    }

    /// Upper bound of the displacement of any head point between two poses, mm.
    fn displacement(&self, a: &Pose, b: &Pose) -> f64 {
        displacement(a, b, self.reach)
    }

    /// Check the move from axes `from` to `to` (output line `line`, layer `layer`); findings
    /// are kept (see [`Checker::findings`]). `include_start` checks the pose at `from` too (the
    /// first move of a file).
    pub fn check_move(
        &mut self,
        from: &[f64],
        to: &[f64],
        line: u64,
        layer: u32,
        include_start: bool,
    ) -> Result<(), MachineError> {
        self.layer = layer;
        if self.stop && !self.findings.is_empty() {
            return Ok(());
        }
        self.stats.moves += 1;
        if from.len() > MAX_AXES {
            return Err(MachineError::BadSpec {
                machine: self.machine.name().to_string(),
                message: format!(
                    "the collision check reads at most {MAX_AXES} axes, this machine has {}",
                    from.len()
                ),
            });
        }
        let pose_at = |t: f64| self.pose_between(from, to, t);
        // the last move's end is usually this one's start (`super::samples`)
        let p0 = self.kept_or_solved(from)?;
        let p1 = self.kept_or_solved(to)?;
        let mut n = ((self.displacement(&p0, &p1) / SAMPLE_STEP_MM).ceil() as usize).max(1);
        let mut poses = Vec::with_capacity(n + 1);
        poses.push(p0);
        for k in 1..n {
            poses.push(pose_at(k as f64 / n as f64)?);
        }
        poses.push(p1);
        loop {
            let ok = poses
                .windows(2)
                .all(|w| !displacement_exceeds(&w[0], &w[1], self.reach, SAMPLE_STEP_MM));
            if ok || n >= MAX_SAMPLES {
                if !ok {
                    self.stats.under_sampled += 1;
                }
                break;
            }
            let n2 = (n * 2).min(MAX_SAMPLES);
            let mut next = Vec::with_capacity(n2 + 1);
            if n2 == 2 * n {
                // the poses at k/n are those at 2k/2n (the same quotient): keep them
                for (k, p) in poses.iter().enumerate() {
                    if k > 0 {
                        next.push(pose_at((2 * k - 1) as f64 / n2 as f64)?);
                    }
                    next.push(*p);
                }
            } else {
                next.push(p0);
                for k in 1..n2 {
                    next.push(pose_at(k as f64 / n2 as f64)?);
                }
                next.push(p1);
            }
            poses = next;
            n = n2;
        }
        // per part, whether it may reach the material or the bed at all over the move: its
        // box at the first pose grown by the largest displacement of its points from there
        // (each point within `reach` of the tip moves at most |Δtip| + reach·θ, θ at most
        // `turn_bound`) holds the part at every sampled pose, so a part whose grown box is
        // above the material's block maxima and the bed is skipped whole (the union of its
        // boxes at its checked poses below is inside the grown box: `any_above` and the bed's
        // test could only say no there too)
        let tol = CONTACT_TOLERANCE_MM;
        let away: Vec<(f64, f64)> = poses
            .iter()
            .map(|q| ((q.p - p0.p).length(), turn_bound(&p0, q)))
            .collect();
        let skip: Vec<bool> = self
            .parts
            .iter()
            .map(|part| {
                if self.exhaustive {
                    return false;
                }
                let (lo, hi) = grown_box(part, &p0, &away);
                !self
                    .material
                    .any_above((lo.x, lo.y, hi.x, hi.y), lo.z + tol)
                    && lo.z >= self.bed.top() - tol
            })
            .collect();
        // per part, the poses it is checked at (its own reach sets the step)
        let start = usize::from(!include_start);
        let checked: Vec<Vec<bool>> = self
            .parts
            .iter()
            .zip(&skip)
            .map(|(part, &skip)| {
                if skip {
                    return vec![false; poses.len()];
                }
                let mut keep = checked_poses(&poses, part.reach);
                keep[..start].fill(false);
                keep
            })
            .collect();
        // per part, over the whole move: can it reach the material or the bed at all? (the
        // union of its boxes against the material's block maxima and the bed's top)
        let reachable: Vec<(bool, bool)> = self
            .parts
            .iter()
            .zip(&checked)
            .zip(&skip)
            .map(|((part, keep), &skip)| {
                if skip {
                    return (false, false);
                }
                let (mut lo, mut hi) =
                    (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
                for (pose, _) in poses.iter().zip(keep).filter(|(_, &k)| k) {
                    let (l, h) = part.pose(pose.p, pose.n, pose.frame.as_ref()).aabb();
                    lo = lo.min(l);
                    hi = hi.max(h);
                }
                if self.exhaustive {
                    return (true, true);
                }
                (
                    self.material
                        .any_above((lo.x, lo.y, hi.x, hi.y), lo.z + tol),
                    lo.z < self.bed.top() - tol,
                )
            })
            .collect();
        // the cells a part may reach, found once for many poses: over the whole move for a
        // frustum part that translates (the pose fixed, `swept_cells`), else over stretches
        // of its checked poses whose points stay within STRETCH_MM of the stretch's first
        // (`cells_near`), the last one carried into the next moves while it covers their poses
        // (`super::stretch`); `lists.cells[lists.of[part][pose]]`
        let fixed = !self.exhaustive && p0.n.angle_between(p1.n) < 1e-12 && p0.frame == p1.frame;
        let mut lists = self.lists(&poses, &checked, &reachable, fixed);
        let mut found: Vec<CollisionFinding> = Vec::new();
        for (k, pose) in poses.iter().enumerate().skip(start) {
            self.stats.samples += 1;
            for (((part, &(mut mat, bed)), keep), list) in self
                .parts
                .iter()
                .zip(&reachable)
                .zip(&checked)
                .zip(&lists.of)
            {
                if !keep[k] {
                    continue;
                }
                let cells = list[k].map(|id| lists.cells[id].as_slice());
                if cells.is_some_and(|c| c.is_empty()) {
                    mat = false;
                }
                if !mat && !bed {
                    continue;
                }
                let solid = part.pose(pose.p, pose.n, pose.frame.as_ref());
                let contact = part
                    .tip
                    .then(|| ContactSurface::new(pose.p, pose.n, self.max_width));
                for (obstacle, depth, at, _) in
                    self.penetrations(&solid, contact.as_ref(), mat, cells, bed)
                {
                    match found
                        .iter_mut()
                        .find(|f| f.part == part.name && f.obstacle == obstacle)
                    {
                        Some(f) if f.depth_mm >= depth => {}
                        Some(f) => {
                            f.depth_mm = depth;
                            f.at = at;
                        }
                        None => found.push(CollisionFinding {
                            line,
                            layer,
                            part: part.name.clone(),
                            obstacle: obstacle.to_string(),
                            depth_mm: depth,
                            at,
                            input_line: None,
                        }),
                    }
                }
            }
        }
        self.findings.extend(found);
        self.carry(&mut lists);
        self.samples.keep(from, to, poses);
        Ok(())
    }

    /// The lists of the cells each part may reach at its checked poses of one move (`poses`,
    /// `checked[part][pose]`; `reachable[part].0`: the part may reach material at all; `fixed`:
    /// the move translates, the pose fixed): see [`Checker::check_move`].
    fn lists(
        &mut self,
        poses: &[Pose],
        checked: &[Vec<bool>],
        reachable: &[(bool, bool)],
        fixed: bool,
    ) -> Lists {
        let (p0, p1) = (poses[0], poses[poses.len() - 1]);
        let mut all: Vec<Vec<SweptCell>> = Vec::new();
        let mut list_of: Vec<Vec<Option<usize>>> = vec![vec![None; poses.len()]; self.parts.len()];
        // the stretches still open at the move's end, with their list's index
        let mut open: Vec<(usize, Stretch, usize)> = Vec::new();
        for pi in 0..self.parts.len() {
            if self.exhaustive || !reachable[pi].0 {
                continue;
            }
            let part = &self.parts[pi];
            let idx: Vec<usize> = (0..poses.len()).filter(|&k| checked[pi][k]).collect();
            if fixed {
                // a box that translates: each pose's own scan (its candidates would be every
                // cell near the box's lower faces over the whole stretch)
                if let Some(cells) = self.swept_cells(part, &p0, &p1) {
                    // each pose gets the cells near its own tip (`by_pose`)
                    match (idx.len() > 1)
                        .then(|| self.by_pose(part, poses, &idx, &cells))
                        .flatten()
                    {
                        Some(lists) => {
                            for (&k, cells) in idx.iter().zip(lists) {
                                list_of[pi][k] = Some(all.len());
                                all.push(cells);
                            }
                        }
                        _ => {
                            for &k in &idx {
                                list_of[pi][k] = Some(all.len());
                            }
                            all.push(cells);
                        }
                    }
                }
                continue;
            }
            let mut i = 0;
            // the poses the stretch carried from earlier moves still covers
            if let Some((live, cells)) = self.live[pi].take() {
                while idx
                    .get(i)
                    .is_some_and(|&k| live.covers(&poses[k], part.reach, self.max_width))
                {
                    list_of[pi][idx[i]] = Some(all.len());
                    i += 1;
                }
                if i == idx.len() {
                    open.push((pi, live, all.len()));
                }
                all.push(cells);
            }
            while i < idx.len() {
                let cap = if !part.tip && self.clear[pi] {
                    CLEAR_STRETCH_MM
                } else {
                    STRETCH_MM
                };
                let first = poses[idx[i]];
                let (mut j, mut delta) = (i + 1, 0.0f64);
                while let Some(&k) = idx.get(j) {
                    let d = displacement(&first, &poses[k], part.reach);
                    if d > cap {
                        break;
                    }
                    delta = delta.max(d);
                    j += 1;
                }
                // the contact surface bounds the nozzle's depth only where it applies at every
                // pose of the stretch (a steeper pose counts its whole overlap)
                let contact = part.tip
                    && idx[i..j].iter().all(|&k| {
                        ContactSurface::new(poses[k].p, poses[k].n, self.max_width).applies()
                    });
                // a stretch that reaches the move's end may go on into the next (grown by the
                // whole cap); not the nozzle's: the bead it lays is within its reach, so the
                // next deposit would end it
                if j == idx.len() && !part.tip {
                    delta = cap;
                    let stretch = Stretch {
                        first,
                        delta,
                        contact,
                    };
                    open.push((pi, stretch, all.len()));
                }
                for &k in &idx[i..j] {
                    list_of[pi][k] = Some(all.len());
                }
                let cells = self.cells_near(part, &first, delta, contact, None);
                self.clear[pi] = cells.is_empty();
                all.push(cells);
                i = j;
            }
        }
        Lists {
            cells: all,
            of: list_of,
            open,
        }
    }

    /// Keep the stretches still open at the move's end, with their lists, for the next moves.
    fn carry(&mut self, lists: &mut Lists) {
        for (pi, stretch, id) in lists.open.drain(..) {
            self.live[pi] = Some((stretch, std::mem::take(&mut lists.cells[id])));
        }
    }

    /// The deepest overlap of `solid` with the material and with the bed (each only if above
    /// the contact tolerance): `(obstacle, depth, [x, y, z_in])`.
    fn penetrations(
        &self,
        solid: &Posed,
        contact: Option<&ContactSurface>,
        material: bool,
        cells: Option<&[SweptCell]>,
        bed: bool,
    ) -> Vec<(&'static str, f64, [f64; 3], u32)> {
        let (lo, hi) = solid.aabb();
        let tol = CONTACT_TOLERANCE_MM;
        let mut out = Vec::new();
        let mut best: Option<(f64, [f64; 3], u32)> = None;
        let consider = |h: f64,
                        x: f64,
                        y: f64,
                        bead: u32,
                        contact: Option<&ContactSurface>,
                        best: &mut Option<(f64, [f64; 3], u32)>| {
            // the depth is at most h − z_in (the contact surface only takes from it; z_in is
            // at least the solid's lowest point), and only a depth above the tolerance and
            // above the deepest found so far changes the result
            let floor = match contact {
                _ if self.exhaustive => f64::NEG_INFINITY,
                Some(c) => solid.floor_at(x, y).max(c.floor_at(x, y)).max(lo.z),
                None => solid.floor_at(x, y).max(lo.z),
            };
            if h - floor <= best.map_or(tol, |(b, _, _)| b.max(tol)) {
                return;
            }
            if let Some((zi, zo)) = solid.column(x, y) {
                let top = h.min(zo);
                let d = match contact {
                    // the current layer's beads may be pressed by a layer height
                    Some(c) => {
                        let d = c.depth_above(x, y, zi, top);
                        if d > tol && self.material.layer_of(bead) == Some(self.layer) {
                            d - self.layer_height
                        } else {
                            d
                        }
                    }
                    None => top - zi,
                };
                if d > tol && best.is_none_or(|(b, _, _)| d > b) {
                    *best = Some((d, [x, y, zi], bead));
                }
            }
        };
        if let (true, Some(cells)) = (material, cells) {
            // one floor under every line of the pose, known before any distance: `consider`'s
            // floor is at least it (`ContactSurface::floor_anywhere`), so a cell whose top is
            // within the bar of it is one `consider` turns away at its first test
            let low = match contact {
                _ if self.exhaustive => f64::NEG_INFINITY,
                Some(c) => c.floor_anywhere().max(lo.z),
                None => lo.z,
            };
            for c in cells {
                if c.h - low <= best.map_or(tol, |(b, _, _)| b.max(tol)) {
                    continue;
                }
                consider(c.h, c.x, c.y, c.bead, contact, &mut best);
            }
        } else if material {
            let reach = Reach::new(solid, contact, tol, lo.z);
            // only the columns that reach below the highest material under the solid
            let rect = (lo.x, lo.y, hi.x, hi.y);
            let m = self.material.max_over(rect) - tol;
            let (x0, y0, x1, y1) = if self.exhaustive {
                Some(rect)
            } else {
                reach.rect(rect, m)
            }
            .unwrap_or((0.0, 0.0, -1.0, -1.0));
            let above = if self.exhaustive {
                f64::NEG_INFINITY
            } else {
                lo.z + tol
            };
            self.material.for_cells_above(
                (x0, y0, x1, y1),
                above,
                |c, r, top| !self.exhaustive && reach.skips_block(c, r, top),
                |y, top| {
                    if self.exhaustive {
                        Some((f64::NEG_INFINITY, f64::INFINITY))
                    } else {
                        reach.row(y, top)
                    }
                },
                |i, j, h, bead| {
                    consider(h, centre(i), centre(j), bead, contact, &mut best);
                    // a block, row or cell no deeper than the deepest so far cannot replace it
                    // (`Reach::raise`)
                    if let Some((d, _, _)) = best {
                        reach.raise(d);
                    }
                },
            );
        }
        if let Some((d, at, bead)) = best {
            out.push(("material", d, at, bead));
        }
        let top = self.bed.top();
        if bed && lo.z < top - tol {
            let mut best = None;
            // the bed is a plane, not beads: its contact surface has no half bead
            let bed_contact = contact.map(|c| c.for_plane());
            // without a contact surface the deepest overlap with a plane is under the solid's
            // lowest point, when the bed is there (else the cells are scanned)
            let low = solid.lowest();
            if bed_contact.is_none() && self.bed.covers(low.x, low.y) {
                consider(top, low.x, low.y, 0, None, &mut best);
            } else {
                let (mut x0, mut y0, mut x1, mut y1) = (lo.x, lo.y, hi.x, hi.y);
                if let (Some(r), Posed::Frustum { o, .. }, false) =
                    (solid.radius_below(top - tol), solid, self.exhaustive)
                {
                    (x0, y0) = (x0.max(o.x - r), y0.max(o.y - r));
                    (x1, y1) = (x1.min(o.x + r), y1.min(o.y + r));
                }
                for j in cell_of(y0)..=cell_of(y1) {
                    for i in cell_of(x0)..=cell_of(x1) {
                        let (x, y) = (centre(i), centre(j));
                        if self.bed.covers(x, y) {
                            consider(top, x, y, 0, bed_contact.as_ref(), &mut best);
                        }
                    }
                }
            }
            if let Some((d, at, _)) = best {
                out.push(("bed", d, at, 0));
            }
        }
        out
    }

    /// The part (and, for the nozzle, its contact surface) of a translation from pose `a` to
    /// `b` with its tip at the horizontal origin and the lower end's height: the floor at
    /// horizontal distance D from it ([`Posed::floor_at_distance`],
    /// [`ContactSurface::floor_at_distance`]: each `tip_z +` a function of D, growing with D)
    /// bounds from below the floor at that distance from the tip of every pose of the move,
    /// whose tips are no lower (the tip moves along the segment).
    fn lowest(&self, part: &Part, a: &Pose, b: &Pose) -> (Posed, Option<ContactSurface>) {
        let tip = DVec3::new(0.0, 0.0, a.p.z.min(b.p.z));
        (
            part.pose(tip, a.n, a.frame.as_ref()),
            part.tip
                .then(|| ContactSurface::new(tip, a.n, self.max_width)),
        )
    }

    /// Per checked pose of a translation from `a` to `b` (`poses[k]` for `k` in `idx`), the
    /// cells of its swept list `cells` ([`Checker::swept_cells`]) that may give a finding
    /// there, each list in `cells`' order (so the deepest cell, and among equal depths the
    /// first, is the same as over the whole list); `None` when the tips cannot be ordered
    /// along the path ([`TipLine::new`]).
    ///
    /// A cell of top `h` gives a finding at a pose only if the part's floor at the cell, from
    /// that pose (and the contact surface's for the nozzle), is below `h − tol`. That floor is
    /// at least the lowest pose's at the cell's horizontal distance D from the pose's tip
    /// ([`Checker::lowest`]), which is above `h − tol` for every D beyond the radius
    /// [`radius_below`] of `h − tol`: the cell is listed only at the tips within that radius
    /// ([`TipLine::within`]). Law test `a_translation_lists_every_cell_any_of_its_poses_reaches`.
    fn by_pose(
        &self,
        part: &Part,
        poses: &[Pose],
        idx: &[usize],
        cells: &[SweptCell],
    ) -> Option<Vec<Vec<SweptCell>>> {
        let (a, b) = (&poses[0], &poses[poses.len() - 1]);
        let tips: Vec<glam::DVec2> = idx.iter().map(|&k| poses[k].p.truncate()).collect();
        let line = TipLine::new(a.p.truncate(), (b.p - a.p).truncate(), &tips)?;
        let (low_solid, low_contact) = self.lowest(part, a, b);
        let mut out = vec![Vec::new(); idx.len()];
        for c in cells {
            let range =
                match radius_below(&low_solid, low_contact.as_ref(), c.h - CONTACT_TOLERANCE_MM) {
                    Some(r) => line.within(glam::DVec2::new(c.x, c.y), r),
                    None => 0..idx.len(),
                };
            for list in &mut out[range] {
                list.push(*c);
            }
        }
        Some(out)
    }

    /// The material cells a frustum part can reach while it translates from pose `a` to `b`
    /// (same tool axis and frame): `None` for other parts. The part's floor
    /// ([`Posed::floor_at`], and the contact surface's for the tip part,
    /// [`ContactSurface::floor_at`]) depends on the horizontal distance D from the tip only, and
    /// grows with D; over the move a cell is at least `D_min` (its distance from the tip's
    /// path) from the tip, and the tip at least as high as its lower end: the floor of the
    /// part at that lowest tip, placed at the path's point nearest the cell, bounds every
    /// sampled pose's floor from below, so a cell under it cannot be reached; a whole block is
    /// skipped when its highest top is under that floor at the block's least distance from the
    /// path (the floor grows with the distance), and on each row only the cells within the
    /// radius where the floor comes below the row's highest top (less the tolerance) of the
    /// path are visited ([`capsule_row`]; law test
    /// `a_translation_lists_every_cell_any_of_its_poses_reaches`).
    fn swept_cells(&self, part: &Part, a: &Pose, b: &Pose) -> Option<Vec<SweptCell>> {
        let tol = CONTACT_TOLERANCE_MM;
        let sa = part.pose(a.p, a.n, a.frame.as_ref());
        if !matches!(sa, Posed::Frustum { .. }) {
            return None;
        }
        let sb = part.pose(b.p, b.n, b.frame.as_ref());
        let (la, ha) = sa.aabb();
        let (lb, hb) = sb.aabb();
        let (lo, hi) = (la.min(lb), ha.max(hb));
        let m = self.material.max_over((lo.x, lo.y, hi.x, hi.y)) - tol;
        // the floor at horizontal distance D from the lowest tip (it depends on D only and
        // grows with it): at a cell's distance from the path it bounds the part's floor there
        // at every pose, at a block's least distance the floor of every cell of the block
        let (low_solid, low_contact) = self.lowest(part, a, b);
        let r = radius_below(&low_solid, low_contact.as_ref(), m);
        let (mut x0, mut y0, mut x1, mut y1) = (lo.x, lo.y, hi.x, hi.y);
        if let Some(r) = r {
            x0 = x0.max(a.p.x.min(b.p.x) - r);
            y0 = y0.max(a.p.y.min(b.p.y) - r);
            x1 = x1.min(a.p.x.max(b.p.x) + r);
            y1 = y1.min(a.p.y.max(b.p.y) + r);
        }
        let (pa, d) = (a.p.truncate(), (b.p - a.p).truncate());
        let l2 = d.length_squared();
        let floor_at_distance = |dist: f64| {
            let floor = low_solid.floor_at_distance(dist);
            match &low_contact {
                Some(k) => floor.max(k.floor_at_distance(dist)),
                None => floor,
            }
        };
        let mut cells = Vec::new();
        self.material.for_cells_above(
            (x0, y0, x1, y1),
            lo.z + tol,
            |c, half_diag, top| {
                let t = if l2 > 0.0 {
                    ((c - pa).dot(d) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let dist = ((c - (pa + d * t)).length() - half_diag).max(0.0);
                top - floor_at_distance(dist) <= tol
            },
            |y, rtop| {
                // a cell of the row reaches under the floor only within the radius where the
                // floor comes below the row's highest top (`Posed::radius_below`,
                // `ContactSurface::radius_below`: the floor at distance D is below m only for
                // D under it), about the tip's path
                match radius_below(&low_solid, low_contact.as_ref(), rtop - tol) {
                    Some(r) => capsule_row(pa, d, r, y),
                    None => Some((f64::NEG_INFINITY, f64::INFINITY)),
                }
            },
            |i, j, h, bead| {
                let c = glam::DVec2::new(centre(i), centre(j));
                let t = if l2 > 0.0 {
                    ((c - pa).dot(d) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                if h - floor_at_distance((c - (pa + d * t)).length()) > tol {
                    cells.push(SweptCell {
                        x: c.x,
                        y: c.y,
                        h,
                        bead,
                    });
                }
            },
        );
        Some(cells)
    }

    /// The material cells `part` may reach at any pose whose points are within `delta` of
    /// their places at pose `at` (the part there grown by `delta`, [`Posed::dilated`], contains
    /// it at every such pose): the cells whose vertical line through the centre enters the
    /// grown solid more than [`CONTACT_TOLERANCE_MM`] below the material's top. A pose's
    /// overlap at a cell is at most `h − z_in` of its own solid, whose `z_in` is at least the
    /// grown solid's, so no cell left out can give a finding. With `contact` (the nozzle, its
    /// contact rule applying at every pose of the stretch) only the part of the grown column
    /// above the grown contact surface counts ([`ContactSurface::grown`]): a pose's counted
    /// region (inside the part and above its surface) lies within `delta` of the reference
    /// pose's, so inside both grown regions. `within`: only the cells of that rectangle
    /// (x0, y0, x1, y1).
    fn cells_near(
        &self,
        part: &Part,
        at: &Pose,
        delta: f64,
        contact: bool,
        within: Option<(f64, f64, f64, f64)>,
    ) -> Vec<SweptCell> {
        let tol = CONTACT_TOLERANCE_MM;
        let solid = part.pose(at.p, at.n, at.frame.as_ref()).dilated(delta);
        let contact = contact.then(|| ContactSurface::new(at.p, at.n, self.max_width).grown(delta));
        let (lo, hi) = solid.aabb();
        let reach = Reach::new(&solid, contact.as_ref(), tol, lo.z);
        let mut rect = (lo.x, lo.y, hi.x, hi.y);
        if let Some((x0, y0, x1, y1)) = within {
            rect = (
                rect.0.max(x0),
                rect.1.max(y0),
                rect.2.min(x1),
                rect.3.min(y1),
            );
            if rect.0 > rect.2 || rect.1 > rect.3 {
                return Vec::new();
            }
        }
        let Some((x0, y0, x1, y1)) = reach.rect(rect, self.material.max_over(rect) - tol) else {
            return Vec::new();
        };
        let zlow = lo.z;
        let mut cells = Vec::new();
        self.material.for_cells_above(
            (x0, y0, x1, y1),
            zlow + tol,
            |c, r, top| reach.skips_block(c, r, top),
            |y, top| reach.row(y, top),
            |i, j, h, bead| {
                let (x, y) = (centre(i), centre(j));
                if contact.as_ref().is_some_and(|c| !c.above_at(x, y, h - tol)) {
                    return;
                }
                if h - solid.floor_at(x, y) <= tol {
                    return;
                }
                let Some((zi, zo)) = solid.column(x, y) else {
                    return;
                };
                let top = h.min(zo);
                let d = match &contact {
                    Some(c) => c.depth_above(x, y, zi, top),
                    None => top - zi,
                };
                if d > tol {
                    cells.push(SweptCell { x, y, h, bead });
                }
            },
        );
        cells
    }

    /// The cross slope of the bead piece from `p0` to `p1` printed with tool axis `n`, width
    /// `w` ([`super::bead`]): the layer's, read from the material at `±w·h` beside the piece's
    /// middle, bounded by the tool face's.
    fn cross_slope(&self, p0: DVec3, p1: DVec3, n: DVec3, w: f64) -> f64 {
        let Some(h) = bead::across(p1 - p0) else {
            return 0.0;
        };
        let mid = (0.5 * (p0 + p1)).truncate();
        let side = |k: f64| {
            let q = mid + h * (k * w);
            self.material.side_at(q.x, q.y, self.layer)
        };
        let z = 0.5 * (p0.z + p1.z);
        let layer = bead::layer_slope(z, side(1.0), side(-1.0), w, self.layer_height);
        bead::cross_slope(bead::tool_slope(n, p1 - p0, h), layer)
    }

    /// Deposit the bead of a move from `from` to `to` of line width `width` (mm): the tip path
    /// sampled at the pieces the firmware's interpolation gives, each piece a straight bead.
    pub fn deposit(&mut self, from: &[f64], to: &[f64], width: f64) -> Result<(), MachineError> {
        let rect = self.lay(from, to, width)?;
        // a carried stretch survives only if no raised cell now passes its list's test
        // (`super::stretch`: the test is monotone in the cell's top)
        for pi in 0..self.live.len() {
            if let Some((st, _)) = &self.live[pi] {
                let part = &self.parts[pi];
                if !self
                    .cells_near(part, &st.first, st.delta, st.contact, Some(rect))
                    .is_empty()
                {
                    self.live[pi] = None;
                }
            }
        }
        Ok(())
    }

    /// The bead of [`Checker::deposit`] laid into the material: the rectangle (x0, y0, x1, y1)
    /// holding the centre of every cell it may have raised (`Material::deposit` raises cells
    /// whose centres lie within `max(w/2, half a cell diagonal)` of a piece; the pieces' ends
    /// bound the path, and a cell more).
    fn lay(
        &mut self,
        from: &[f64],
        to: &[f64],
        width: f64,
    ) -> Result<(f64, f64, f64, f64), MachineError> {
        self.max_width = self.max_width.max(width);
        // the move's poses as the check sampled them, where they are the same (`super::samples`)
        let a = self.kept_or_solved(from)?;
        let b = self.kept_or_solved(to)?;
        // a straight bead when the pose is fixed; pieces of at most a cell otherwise
        let pieces = if a.n.angle_between(b.n) < 1e-9 {
            1
        } else {
            ((b.p - a.p).length() / CELL_MM).ceil().clamp(1.0, 4096.0) as usize
        };
        let mut prev = a;
        let (mut lo, mut hi) = (a.p.min(b.p), a.p.max(b.p));
        for k in 1..=pieces {
            let t = k as f64 / pieces as f64;
            let next = if k == pieces {
                b
            } else if let Some(p) = self.samples.at(from, to, k, pieces) {
                p
            } else {
                self.pose_between(from, to, t)?
            };
            let n = (prev.n + next.n).normalize_or(next.n);
            let slope = self.cross_slope(prev.p, next.p, n, width);
            self.material
                .deposit(prev.p, next.p, slope, width, self.layer);
            (lo, hi) = (lo.min(next.p), hi.max(next.p));
            prev = next;
        }
        let spread = (0.5 * width).max(CELL_MM) + CELL_MM;
        Ok((lo.x - spread, lo.y - spread, hi.x + spread, hi.y + spread))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::spec::preset;

    /// A small deterministic generator (the tests need no crate for it).
    /// Assert that every cell `part` reaches at `pose` ([`reached_cells`]) is in `listed`;
    /// the number of cells reached. `context` names the case in the failure message.
    fn assert_listed(
        listed: &std::collections::HashSet<(i64, i64)>,
        ck: &Checker,
        part: &Part,
        pose: &Pose,
        context: impl Fn() -> String,
    ) -> usize {
        let reached = reached_cells(ck, part, pose);
        for ((i, j), d) in &reached {
            assert!(
                listed.contains(&(*i, *j)),
                "{}, {}: the cell ({:.1}, {:.1}) is reached {d:.3} mm deep at tip {:?} but not listed",
                context(),
                part.name,
                centre(*i),
                centre(*j),
                pose.p
            );
        }
        reached.len()
    }

    /// Where the tests lay their pad: about the origin for a table that turns the part about
    /// it (Open5x), else about the middle of a 200 mm bed.
    fn pad_centre(name: &str) -> DVec3 {
        if name == "open5x-ab" {
            DVec3::ZERO
        } else {
            DVec3::new(100.0, 100.0, 0.0)
        }
    }

    /// Whether two poses are the same doubles bit for bit (tip, axis, frame).
    fn same_pose(a: &Pose, b: &Pose) -> bool {
        let bits = |q: &Pose| {
            let mut v: Vec<u64> = q.p.to_array().iter().map(|x| x.to_bits()).collect();
            v.extend(q.n.to_array().iter().map(|x| x.to_bits()));
            if let Some(f) = q.frame {
                v.extend(f.to_cols_array().iter().map(|x| x.to_bits()));
            }
            v
        };
        a.frame.is_some() == b.frame.is_some() && bits(a) == bits(b)
    }

    /// The poses kept from the last move (`super::samples`) are the machine's own poses solved
    /// afresh, bit for bit: after each checked move every interior parameter `k/m` (m ≤ 24)
    /// the kept samples answer is compared with [`Checker::pose_between`] at `k as f64 / m as f64`, the
    /// move's ends with the poses of its axes, and a parameter is answered exactly when `k·n`
    /// is a multiple of `m`. Then the walk itself: a checker that reuses them and one that
    /// forgets them before every move and bead give the same material (every cell's top, bit
    /// for bit) and the same findings. Short and long turning moves of the PAX, Open5x A/B and
    /// RTN heads over a pad, digging into it now and then.
    #[test]
    fn poses_reused_from_the_last_move_are_bit_for_bit_the_poses_solved_afresh() {
        let mut rng = Lcg(41);
        let (mut answered, mut ends) = (0, 0);
        for name in ["pax-5axis", "open5x-ab", "rtn-slicer4rtn"] {
            let spec = preset(name).unwrap();
            let mut ck = Checker::new(&spec).unwrap();
            let mut fresh = Checker::new(&spec).unwrap();
            let m = spec.build().unwrap();
            let c = pad_centre(name);
            let at = |p: DVec3, n: DVec3, prev: Option<&[f64]>| m.inverse(p, n, prev).unwrap();
            let lean =
                |t: f64, az: f64| DVec3::new(t.sin() * az.cos(), t.sin() * az.sin(), t.cos());
            let tilts = name != "rtn-slicer4rtn";
            let (mut tilt, mut az) = (0.3f64, rng.range(0.0, std::f64::consts::TAU));
            let mut p = c + DVec3::new(0.0, 0.0, 0.2);
            let mut axes = at(p, if tilts { lean(tilt, az) } else { DVec3::Z }, None);
            for step in 0..160u64 {
                let layer = 1 + (step / 40) as u32;
                let long = step % 7 == 0;
                let d = if long { 4.0 } else { 0.4 };
                let q = c
                    + (p - c + DVec3::new(rng.range(-d, d), rng.range(-d, d), 0.0))
                        .clamp(DVec3::new(-8.0, -8.0, 0.0), DVec3::new(8.0, 8.0, 9.0))
                        .with_z(0.2 * layer as f64 - if step % 11 == 0 { 0.4 } else { 0.0 });
                tilt = (tilt + rng.range(-0.05, 0.05)).clamp(0.0, 0.5);
                az += rng.range(-0.1, 0.1);
                let next = at(
                    q,
                    if tilts { lean(tilt, az) } else { DVec3::Z },
                    Some(&axes),
                );
                let first = step == 0;
                ck.check_move(&axes, &next, step + 1, layer, first).unwrap();
                fresh.samples.forget();
                fresh
                    .check_move(&axes, &next, step + 1, layer, first)
                    .unwrap();
                // the kept poses against the machine's
                let n = ck.samples_kept() - 1;
                for mm in 1..=24usize {
                    for k in 1..mm {
                        match ck.samples.at(&axes, &next, k, mm) {
                            Some(kept) => {
                                let solved =
                                    ck.pose_between(&axes, &next, k as f64 / mm as f64).unwrap();
                                assert!(
                                    same_pose(&kept, &solved),
                                    "{name}, move {step}: the kept pose at {k}/{mm} (of {n} \
                                     samples) {kept:?}, solved afresh {solved:?}"
                                );
                                answered += 1;
                            }
                            None => assert!(
                                !(k * n).is_multiple_of(mm),
                                "{name}, move {step}: {k}/{mm} is sample {} of {n} but not \
                                 answered",
                                k * n / mm
                            ),
                        }
                    }
                }
                for ax in [&axes, &next] {
                    if let Some(kept) = ck.samples.end(ax) {
                        let solved = ck.pose(ax).unwrap();
                        assert!(
                            same_pose(&kept, &solved),
                            "{name}, move {step}: the kept end {kept:?}, solved {solved:?}"
                        );
                        ends += 1;
                    }
                }
                ck.deposit(&axes, &next, 0.45).unwrap();
                fresh.samples.forget();
                fresh.deposit(&axes, &next, 0.45).unwrap();
                (axes, p) = (next, q);
            }
            assert_eq!(
                ck.findings(),
                fresh.findings(),
                "{name}: the findings with and without the kept poses"
            );
            assert!(!ck.findings().is_empty(), "{name}: no finding to compare");
            let (lo, hi) = (cell_of(c.x - 12.0), cell_of(c.x + 12.0));
            let (jlo, jhi) = (cell_of(c.y - 12.0), cell_of(c.y + 12.0));
            for j in jlo..=jhi {
                for i in lo..=hi {
                    let (a, b) = (ck.material.height(i, j), fresh.material.height(i, j));
                    assert!(
                        a.to_bits() == b.to_bits(),
                        "{name}: the cell ({i}, {j}) is {a} with the kept poses, {b} without"
                    );
                }
            }
        }
        assert!(
            answered > 10_000 && ends > 700,
            "{answered} parameters answered from the kept samples, {ends} ends"
        );
    }

    /// The cells of a list, by index.
    fn cell_set(cells: &[SweptCell]) -> std::collections::HashSet<(i64, i64)> {
        cells.iter().map(|c| (cell_of(c.x), cell_of(c.y))).collect()
    }

    use crate::test_rng::Lcg;

    /// Test-only draws of this module's cases.
    trait Draws {
        fn axis(&mut self, tilts: bool) -> DVec3;
    }

    impl Draws for Lcg {
        /// A tool axis: vertical for a 3-axis head (`tilts` false), else tilted up to 30° at
        /// any azimuth.
        fn axis(&mut self, tilts: bool) -> DVec3 {
            if !tilts {
                return DVec3::Z;
            }
            let (t, az) = (
                self.range(0.0, 30f64.to_radians()),
                self.range(0.0, std::f64::consts::TAU),
            );
            DVec3::new(t.sin() * az.cos(), t.sin() * az.sin(), t.cos())
        }
    }

    /// The largest displacement of the part's points between poses `a` and `b`, by brute force
    /// (not [`displacement`]'s bound): a rigid motion moves the points of a convex solid most at
    /// its extreme points (|M q − q| is convex in q), the box's corners or the frustum's two
    /// rim circles (720 points each; the chord error r·(1 − cos 0.25°) ≤ 1e-5·r is added).
    fn brute_displacement(part: &Part, a: &Pose, b: &Pose) -> f64 {
        let sa = part.pose(a.p, a.n, a.frame.as_ref());
        let sb = part.pose(b.p, b.n, b.frame.as_ref());
        let mut best: f64 = 0.0;
        match (sa, sb) {
            (Posed::Box { o, r, min, max }, Posed::Box { o: o2, r: r2, .. }) => {
                for c in 0..8 {
                    let l = DVec3::new(
                        if c & 1 == 0 { min.x } else { max.x },
                        if c & 2 == 0 { min.y } else { max.y },
                        if c & 4 == 0 { min.z } else { max.z },
                    );
                    best = best.max(((o2 + r2 * l) - (o + r * l)).length());
                }
            }
            (
                Posed::Frustum {
                    o,
                    a: ax,
                    s0,
                    s1,
                    r0,
                    k,
                },
                Posed::Frustum { o: o2, a: ax2, .. },
            ) => {
                // the frames: the tool axis and a perpendicular carried by the head frame when
                // known (else the solid is of revolution and any matching perpendicular does)
                let perp = |n: DVec3, f: Option<&DMat3>| match f {
                    Some(m) => (m.x_axis - n * n.dot(m.x_axis)).normalize(),
                    None => n.any_orthonormal_vector(),
                };
                let (u1, u2) = (perp(ax, a.frame.as_ref()), perp(ax2, b.frame.as_ref()));
                let (v1, v2) = (ax.cross(u1), ax2.cross(u2));
                for (s, rad) in [(s0, r0), (s1, r0 + k * (s1 - s0))] {
                    for i in 0..720 {
                        let t = (i as f64 * 0.5).to_radians();
                        let (c, sn) = (t.cos(), t.sin());
                        let q1 = o + ax * s + (u1 * c + v1 * sn) * rad;
                        let q2 = o2 + ax2 * s + (u2 * c + v2 * sn) * rad;
                        best = best.max((q2 - q1).length() + 1e-5 * rad);
                    }
                }
            }
            _ => unreachable!("a part keeps its shape"),
        }
        best
    }

    /// The cells `part` reaches at `pose` against the checker's material now, with their depth:
    /// its own solid's column through each cell centre under its box, the material's top, and
    /// for the nozzle the part above its own contact surface — per cell, without any growth,
    /// floor or block bound (the oracle of the stretch laws).
    fn reached_cells(ck: &Checker, part: &Part, pose: &Pose) -> Vec<((i64, i64), f64)> {
        let solid = part.pose(pose.p, pose.n, pose.frame.as_ref());
        let surface = part
            .tip
            .then(|| ContactSurface::new(pose.p, pose.n, ck.max_width));
        let (lo, hi) = solid.aabb();
        let mut out = Vec::new();
        for j in cell_of(lo.y)..=cell_of(hi.y) {
            for i in cell_of(lo.x)..=cell_of(hi.x) {
                let h = ck.material.height(i, j);
                let (x, y) = (centre(i), centre(j));
                let Some((zi, zo)) = solid.column(x, y) else {
                    continue;
                };
                let top = h.min(zo);
                let d = match &surface {
                    Some(c) => c.depth_above(x, y, zi, top),
                    None => top - zi,
                };
                if d > CONTACT_TOLERANCE_MM {
                    out.push(((i, j), d));
                }
            }
        }
        out
    }

    /// The deepest overlap of one pose with the material ([`Checker::penetrations`]'s search,
    /// its culls raised to the deepest depth found so far, `Reach::raise`) is the greatest depth
    /// of the brute-force per-cell depths (`reached_cells`: every cell under the part's box,
    /// no bound) at one of the cells of that depth, and the very cell the exhaustive check
    /// ([`Checker::exhaustive`], no cull: the first cell of the greatest depth in the same
    /// order) gives. Random poses of the cartesian and PAX heads (tilted ≤ 30°) over a pad
    /// with a ramp beside it rising to 9 mm, into which the heater block and the nozzle's
    /// flank dig at many depths.
    #[test]
    fn a_poses_deepest_overlap_is_the_brute_force_deepest_with_the_bar_raised() {
        let mut rng = Lcg(5);
        let (mut compared, mut box_deep, mut listed_deep) = (0, 0, 0);
        for name in ["cartesian", "pax-5axis"] {
            let spec = preset(name).unwrap();
            let mut ck = Checker::new(&spec).unwrap();
            let m = spec.build().unwrap();
            let c = DVec3::new(100.0, 100.0, 0.0);
            let at = |p: DVec3| m.inverse(p, DVec3::Z, None).unwrap();
            // the pad (3 layers) and the ramp (rows rising 0.15 mm each along +y)
            for layer in 1..=3 {
                ck.layer = layer;
                for row in 0..45 {
                    let y = c.y - 10.0 + 0.45 * row as f64;
                    let z = 0.2 * layer as f64
                        + if row > 22 {
                            0.3 * (row - 22) as f64
                        } else {
                            0.0
                        };
                    let (a, b) = (
                        at(DVec3::new(c.x - 10.0, y, z)),
                        at(DVec3::new(c.x + 10.0, y, z)),
                    );
                    ck.deposit(&a, &b, 0.45).unwrap();
                }
            }
            ck.layer = 10;
            for _ in 0..150 {
                let n = rng.axis(name != "cartesian");
                let p = c + DVec3::new(rng.range(-8.0, 8.0), rng.range(-8.0, 2.0), 0.0);
                let p = DVec3::new(p.x, p.y, rng.range(0.3, 3.0));
                let axes = m.inverse(p, n, None).unwrap();
                let pose = ck.pose(&axes).unwrap();
                for part in &ck.parts {
                    let solid = part.pose(pose.p, pose.n, pose.frame.as_ref());
                    let contact = part
                        .tip
                        .then(|| ContactSurface::new(pose.p, pose.n, ck.max_width));
                    let found = ck.penetrations(&solid, contact.as_ref(), true, None, false);
                    let reached = reached_cells(&ck, part, &pose);
                    let deepest = reached
                        .iter()
                        .map(|(_, d)| *d)
                        .fold(f64::NEG_INFINITY, f64::max);
                    match found.first() {
                        None => assert!(
                            reached.is_empty(),
                            "{name}, {}: none found at {:?}, brute force {deepest:.4} mm",
                            part.name,
                            pose.p
                        ),
                        Some((_, d, at, _)) => {
                            assert!(
                                *d == deepest
                                    && reached
                                        .iter()
                                        .any(|((i, j), e)| *e == deepest && centre(*i) == at[0] && centre(*j) == at[1]),
                                "{name}, {}: {d:.4} mm at {at:?}, brute force {deepest:.4} mm at tip {:?}",
                                part.name,
                                pose.p
                            );
                            box_deep += usize::from(!part.tip && *d > 0.5);
                        }
                    }
                    ck.exhaustive = true;
                    let reference = ck.penetrations(&solid, contact.as_ref(), true, None, false);
                    ck.exhaustive = false;
                    assert_eq!(
                        found, reference,
                        "{name}, {}: at tip {:?}",
                        part.name, pose.p
                    );
                    // the same pose given a list (the path of stretches and translations, where
                    // a cell is first turned away on the pose's one floor): every cell under
                    // the part's box, unculled, in the height field's order
                    let (lo, hi) = solid.aabb();
                    let mut every = Vec::new();
                    ck.material.for_cells_above(
                        (lo.x, lo.y, hi.x, hi.y),
                        f64::NEG_INFINITY,
                        |_, _, _| false,
                        |_, _| Some((f64::NEG_INFINITY, f64::INFINITY)),
                        |i, j, h, bead| {
                            every.push(SweptCell {
                                x: centre(i),
                                y: centre(j),
                                h,
                                bead,
                            })
                        },
                    );
                    let listed =
                        ck.penetrations(&solid, contact.as_ref(), true, Some(&every), false);
                    assert_eq!(
                        listed, reference,
                        "{name}, {}: the list of every cell at tip {:?}",
                        part.name, pose.p
                    );
                    listed_deep += usize::from(part.tip && !listed.is_empty());
                    compared += 1;
                }
            }
        }
        assert!(
            compared > 500 && box_deep > 50 && listed_deep > 20,
            "{compared} compared, {box_deep} deep in a box part, {listed_deep} nozzle findings from a list"
        );
    }

    /// Law of the stretch bound ([`Checker::cells_near`]): every cell that any pose of a stretch
    /// reaches (its own solid's column entering more than the tolerance below the material's top,
    /// above its own contact surface for the nozzle) is listed for the stretch's first pose
    /// grown by the stretch's largest displacement. Random turning moves over a printed pad of
    /// 12 layers on four heads (B head, PAX, RTN, Open5x table); the depth at every cell is
    /// computed per pose from the pose's own solid, without the growth, the floors or the block
    /// bounds.
    #[test]
    fn a_stretch_lists_every_cell_any_of_its_poses_reaches() {
        let mut rng = Lcg(7);
        let mut reached_total = 0;
        for name in [
            "fullcontrol-prusa-b",
            "pax-5axis",
            "rtn-slicer4rtn",
            "open5x-ab",
        ] {
            let spec = preset(name).unwrap();
            let mut ck = Checker::new(&spec).unwrap();
            let m = spec.build().unwrap();
            let centre_xy = pad_centre(name);
            let at = |p: DVec3, n: DVec3, prev: Option<&[f64]>| m.inverse(p, n, prev).unwrap();
            // the pad: 12 layers of lines 0.45 apart, 10 mm square, printed vertically
            let mut beads = Vec::new();
            for layer in 1..=12 {
                let z = 0.2 * layer as f64;
                for row in 0..22 {
                    let y = centre_xy.y - 5.0 + 0.45 * row as f64;
                    let a = at(DVec3::new(centre_xy.x - 5.0, y, z), DVec3::Z, None);
                    let b = at(DVec3::new(centre_xy.x + 5.0, y, z), DVec3::Z, Some(&a));
                    beads.push((layer, a, b));
                }
            }
            for (layer, a, b) in &beads {
                ck.layer = *layer;
                ck.deposit(a, b, 0.45).unwrap();
            }
            ck.layer = 13;
            let mut reached = 0;
            for _ in 0..60 {
                // a short move that turns the tool by up to 6°, the tip at or just above the
                // pad's top, tilted up to 35°
                let tilt = |r: &mut Lcg| {
                    let (t, az) = (
                        r.range(0.0, 35f64.to_radians()),
                        r.range(0.0, std::f64::consts::TAU),
                    );
                    DVec3::new(t.sin() * az.cos(), t.sin() * az.sin(), t.cos())
                };
                let p0 =
                    centre_xy + rng.within(DVec3::new(-6.0, -6.0, 2.2), DVec3::new(6.0, 6.0, 2.8));
                let p1 = p0 + rng.within(DVec3::new(-1.0, -1.0, -0.4), DVec3::new(1.0, 1.0, 0.1));
                let n0 = tilt(&mut rng);
                let n1 = (n0 + DVec3::new(rng.range(-0.05, 0.05), rng.range(-0.05, 0.05), 0.0))
                    .normalize();
                let a0 = at(p0, n0, None);
                let a1 = at(p1, n1, Some(&a0));
                let poses: Vec<Pose> = (0..=24)
                    .map(|k| ck.pose_between(&a0, &a1, k as f64 / 24.0).unwrap())
                    .collect();
                for part in &ck.parts {
                    // the stretch: poses while the brute-force displacement from the first
                    // stays within STRETCH_MM
                    let first = poses[0];
                    let mut delta: f64 = 0.0;
                    let mut stretch = vec![first];
                    for p in &poses[1..] {
                        let d = brute_displacement(part, &first, p);
                        if d > STRETCH_MM {
                            break;
                        }
                        delta = delta.max(d);
                        stretch.push(*p);
                    }
                    let contact = part.tip
                        && stretch
                            .iter()
                            .all(|p| ContactSurface::new(p.p, p.n, ck.max_width).applies());
                    let listed = cell_set(&ck.cells_near(part, &first, delta, contact, None));
                    for pose in &stretch {
                        reached += assert_listed(&listed, &ck, part, pose, || {
                            format!(
                                "{name}: a pose of the stretch from {:?} (δ {delta:.3} mm)",
                                first.p
                            )
                        });
                    }
                }
            }
            reached_total += reached;
        }
        // the moves must reach material, or the law says nothing
        assert!(
            reached_total > 100,
            "only {reached_total} cells reached in all"
        );
    }

    /// Law of the swept cells of a translation ([`Checker::swept_cells`], with its block and
    /// row bounds about the tip's path): every cell a pose of a translating move reaches (its
    /// own solid and contact surface, per cell, without any bound) is in the move's list, and
    /// in that pose's own list ([`Checker::by_pose`], kept in the move's list's order).
    /// Random translations of a vertical (cartesian) and a tilted (PAX, up to 30°) nozzle over
    /// a printed pad, the tip between its top and a layer into it.
    #[test]
    fn a_translation_lists_every_cell_any_of_its_poses_reaches() {
        let mut rng = Lcg(41);
        let (mut reached_total, mut per_pose, mut shorter) = (0, 0, 0);
        for name in ["cartesian", "pax-5axis"] {
            let spec = preset(name).unwrap();
            let mut ck = Checker::new(&spec).unwrap();
            let m = spec.build().unwrap();
            let c = DVec3::new(100.0, 100.0, 0.0);
            let at = |p: DVec3, n: DVec3, prev: Option<&[f64]>| m.inverse(p, n, prev).unwrap();
            // the pad: 3 layers of lines 0.45 apart, 12 mm square, printed vertically
            for layer in 1..=3 {
                for row in 0..27 {
                    let y = c.y - 6.0 + 0.45 * row as f64;
                    let a = at(DVec3::new(c.x - 6.0, y, 0.2 * layer as f64), DVec3::Z, None);
                    let b = at(
                        DVec3::new(c.x + 6.0, y, 0.2 * layer as f64),
                        DVec3::Z,
                        Some(&a),
                    );
                    ck.layer = layer;
                    ck.deposit(&a, &b, 0.45).unwrap();
                }
            }
            ck.layer = 4;
            for _ in 0..80 {
                let n = rng.axis(name != "cartesian");
                let p0 = c + DVec3::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0), 0.0);
                let p0 = DVec3::new(p0.x, p0.y, rng.range(0.2, 0.65));
                let p1 = p0 + DVec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), 0.0);
                let a0 = at(p0, n, None);
                let a1 = at(p1, n, Some(&a0));
                let poses: Vec<Pose> = (0..=16)
                    .map(|k| ck.pose_between(&a0, &a1, k as f64 / 16.0).unwrap())
                    .collect();
                for part in &ck.parts {
                    let Some(list) = ck.swept_cells(part, &poses[0], &poses[16]) else {
                        continue;
                    };
                    let listed = cell_set(&list);
                    for pose in &poses {
                        reached_total += assert_listed(&listed, &ck, part, pose, || {
                            format!("{name}: the move {p0:?} → {p1:?}")
                        });
                    }
                    // each pose's own list (`by_pose`): every cell it reaches, in the
                    // whole list's order
                    let idx: Vec<usize> = (0..poses.len()).collect();
                    let lists = ck
                        .by_pose(part, &poses, &idx, &list)
                        .expect("a translation's tips are in order");
                    for (k, (pose, own)) in poses.iter().zip(&lists).enumerate() {
                        per_pose += assert_listed(&cell_set(own), &ck, part, pose, || {
                            format!("{name}: pose {k} of the move {p0:?} → {p1:?}, its own list")
                        });
                        let order = |c: &SweptCell| {
                            list.iter()
                                .position(|l| l.x == c.x && l.y == c.y)
                                .expect("a pose's cell is in the whole list")
                        };
                        assert!(
                            own.windows(2).all(|w| order(&w[0]) < order(&w[1])),
                            "{name}: pose {k}'s list is not in the whole list's order"
                        );
                        shorter += usize::from(own.len() < list.len());
                    }
                }
            }
        }
        assert!(
            reached_total > 1000 && per_pose > 1000 && shorter > 500,
            "{reached_total} cells reached in all, {per_pose} checked per pose, {shorter} pose lists shorter than the move's"
        );
    }

    /// Law of the carried stretches ([`super::stretch`]): over a walk of short turning moves,
    /// each starting where the last ended, with beads deposited between them (some tall, beside
    /// the head, within the heater block's reach), every cell a part reaches at a pose (its own
    /// solid at that pose against the material of that moment, per cell, without the growth,
    /// the floors or the block bounds) is in the list [`Checker::lists`] gave that pose — the
    /// poses served by a stretch begun in an earlier move and kept over deposits among them.
    /// Three heads leaning 20–35° over a printed pad.
    #[test]
    fn a_stretch_carried_over_moves_and_deposits_lists_every_cell_reached() {
        let mut rng = Lcg(23);
        let (mut carried_poses, mut carried_reached, mut kept_over_deposit) = (0, 0, 0);
        for name in ["pax-5axis", "fullcontrol-prusa-b", "open5x-ab"] {
            let spec = preset(name).unwrap();
            let mut ck = Checker::new(&spec).unwrap();
            let m = spec.build().unwrap();
            let c = pad_centre(name);
            let at = |p: DVec3, n: DVec3, prev: Option<&[f64]>| m.inverse(p, n, prev).unwrap();
            // the pad: 3 layers of lines 0.45 apart, 30 mm square, printed vertically
            for layer in 1..=3 {
                let z = 0.2 * layer as f64;
                for row in 0..67 {
                    let y = c.y - 15.0 + 0.45 * row as f64;
                    let a = at(DVec3::new(c.x - 15.0, y, z), DVec3::Z, None);
                    let b = at(DVec3::new(c.x + 15.0, y, z), DVec3::Z, Some(&a));
                    ck.layer = layer;
                    ck.deposit(&a, &b, 0.45).unwrap();
                }
            }
            ck.layer = 4;
            let lean =
                |t: f64, az: f64| DVec3::new(t.sin() * az.cos(), t.sin() * az.sin(), t.cos());
            let (mut tilt, mut az) = (30f64.to_radians(), rng.range(0.0, std::f64::consts::TAU));
            let mut p = c + DVec3::new(rng.range(-4.0, 4.0), rng.range(-4.0, 4.0), 0.9);
            let mut axes = at(p, lean(tilt, az), None);
            for step in 0..120 {
                // a short move: the tip 0.1–0.6 mm on, the tool turning by up to 2°
                let q = c
                    + (p - c + DVec3::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), 0.0))
                        .clamp(DVec3::new(-8.0, -8.0, 0.7), DVec3::new(8.0, 8.0, 1.2));
                tilt =
                    (tilt + rng.range(-0.02, 0.02)).clamp(20f64.to_radians(), 35f64.to_radians());
                az += rng.range(-0.03, 0.03);
                let next = at(q, lean(tilt, az), Some(&axes));
                let poses: Vec<Pose> = (0..=12)
                    .map(|k| ck.pose_between(&axes, &next, k as f64 / 12.0).unwrap())
                    .collect();
                let checked = vec![vec![true; poses.len()]; ck.parts.len()];
                let reachable = vec![(true, true); ck.parts.len()];
                let carried: Vec<bool> = (0..ck.parts.len())
                    .map(|pi| {
                        ck.live[pi].as_ref().is_some_and(|(st, _)| {
                            st.covers(&poses[0], ck.parts[pi].reach, ck.max_width)
                        })
                    })
                    .collect();
                let mut lists = ck.lists(&poses, &checked, &reachable, false);
                for (pi, part) in ck.parts.iter().enumerate() {
                    for (k, pose) in poses.iter().enumerate() {
                        let listed = cell_set(
                            lists.of[pi][k]
                                .map(|id| lists.cells[id].as_slice())
                                .unwrap_or(&[]),
                        );
                        let from_before = carried[pi] && lists.of[pi][k] == lists.of[pi][0];
                        carried_poses += usize::from(from_before);
                        let n = assert_listed(&listed, &ck, part, pose, || {
                            format!(
                                "{name}, move {step}, pose {k}{}",
                                if from_before {
                                    " (carried from an earlier move)"
                                } else {
                                    ""
                                }
                            )
                        });
                        carried_reached += if from_before { n } else { 0 };
                    }
                }
                ck.carry(&mut lists);
                // a bead where the tip went, and every third move a tall one beside the head
                ck.deposit(&axes, &next, 0.45).unwrap();
                if step % 3 == 0 {
                    let side = lean(1.0, az) * rng.range(6.0, 16.0);
                    let b0 = DVec3::new(q.x + side.x, q.y + side.y, rng.range(1.0, 5.0));
                    // along x or y: cells beside the path, outside its own bounding box, rise
                    let l = rng.range(-1.5, 1.5);
                    let b1 = b0
                        + if step % 2 == 0 {
                            DVec3::new(l, 0.0, 0.0)
                        } else {
                            DVec3::new(0.0, l, 0.0)
                        };
                    let live_before = ck.live.iter().filter(|l| l.is_some()).count();
                    let a0 = at(b0, DVec3::Z, None);
                    let a1 = at(b1, DVec3::Z, Some(&a0));
                    ck.deposit(&a0, &a1, 0.45).unwrap();
                    kept_over_deposit += ck
                        .live
                        .iter()
                        .filter(|l| l.is_some())
                        .count()
                        .min(live_before);
                }
                (p, axes) = (q, next);
            }
        }
        // the carried stretches must serve poses that reach material, or the law says nothing
        assert!(
            carried_poses > 500 && carried_reached > 100 && kept_over_deposit > 20,
            "{carried_poses} poses served by carried stretches, {carried_reached} cells reached there, {kept_over_deposit} stretches kept over a tall bead"
        );
    }

    /// The rectangle [`Checker::deposit`] searches for the carried stretches holds every cell
    /// the bead raised: the material's heights over a wide window compared before and after
    /// random beads (straight, turning, along the axes, short and long, 0.3–1.2 mm wide) on
    /// the PAX head, which tilts them.
    #[test]
    fn a_beads_rectangle_holds_every_cell_it_raised() {
        let mut rng = Lcg(31);
        let spec = preset("pax-5axis").unwrap();
        let mut ck = Checker::new(&spec).unwrap();
        let m = spec.build().unwrap();
        let mut raised_total = 0;
        for k in 0..200 {
            let lean = |r: &mut Lcg| {
                let (t, az) = (r.range(0.0, 0.6), r.range(0.0, std::f64::consts::TAU));
                DVec3::new(t.sin() * az.cos(), t.sin() * az.sin(), t.cos())
            };
            let p0 = DVec3::new(
                rng.range(90.0, 110.0),
                rng.range(90.0, 110.0),
                0.2 * (k / 20 + 1) as f64,
            );
            let d = match k % 3 {
                0 => DVec3::new(rng.range(-3.0, 3.0), 0.0, 0.0),
                1 => DVec3::new(0.0, rng.range(-3.0, 3.0), 0.0),
                _ => DVec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), 0.0),
            };
            let a0 = m.inverse(p0, lean(&mut rng), None).unwrap();
            let a1 = m.inverse(p0 + d, lean(&mut rng), Some(&a0)).unwrap();
            let window = |v: f64| (cell_of(v - 6.0), cell_of(v + 6.0));
            let ((i0, i1), (j0, j1)) = (window(p0.x + 0.5 * d.x), window(p0.y + 0.5 * d.y));
            let heights = |ck: &Checker| -> Vec<f64> {
                (j0..=j1)
                    .flat_map(|j| (i0..=i1).map(move |i| (i, j)))
                    .map(|(i, j)| ck.material.height(i, j))
                    .collect()
            };
            let before = heights(&ck);
            ck.layer = (k / 20 + 1) as u32;
            let (x0, y0, x1, y1) = ck.lay(&a0, &a1, rng.range(0.3, 1.2)).unwrap();
            let after = heights(&ck);
            let cells = (j0..=j1).flat_map(|j| (i0..=i1).map(move |i| (i, j)));
            for ((i, j), (h0, h1)) in cells.zip(before.iter().zip(&after)) {
                if h1 > h0 {
                    raised_total += 1;
                    let (x, y) = (centre(i), centre(j));
                    assert!(
                        x >= x0 && x <= x1 && y >= y0 && y <= y1,
                        "bead {k}: the cell ({x:.2}, {y:.2}) rose from {h0:.3} to {h1:.3} outside ({x0:.2}, {y0:.2})–({x1:.2}, {y1:.2})"
                    );
                }
            }
        }
        assert!(raised_total > 2000, "only {raised_total} cells raised");
    }

    /// Law of the move's skip test ([`grown_box`]): on random moves of five presets (large
    /// turns, small ones, none), 65 poses each, every part's points move from the first pose at
    /// most the bound `|Δtip| + reach·turn_bound` (against the brute force's extreme points,
    /// which over-count by their chord allowance, ≤ 10⁻⁵ of a rim's radius), and its box at
    /// every pose lies inside the grown box.
    #[test]
    fn a_parts_grown_box_holds_it_at_every_pose_of_the_move() {
        let mut rng = Lcg(23);
        for name in [
            "pax-5axis",
            "fullcontrol-prusa-b",
            "rtn-slicer4rtn",
            "open5x-ab",
            "ratrig-vcore3-3z",
        ] {
            let spec = preset(name).unwrap();
            let ck = Checker::new(&spec).unwrap();
            let m = spec.build().unwrap();
            let mut moves = 0;
            for case in 0..30 {
                let p0 = rng.within(DVec3::new(-20.0, -20.0, 1.0), DVec3::new(20.0, 20.0, 20.0));
                let p1 = p0 + rng.within(DVec3::new(-3.0, -3.0, -1.0), DVec3::new(3.0, 3.0, 1.0));
                // large turns, small ones (as between samples) and none
                let n0 = rng.axis(true);
                let n1 = match case % 3 {
                    0 => rng.axis(true),
                    1 => (n0 + rng.axis(true) * 0.01).normalize(),
                    _ => n0,
                };
                let (Ok(a0), Ok(a1)) = (
                    m.inverse(p0, n0, None),
                    m.inverse(p0, n0, None)
                        .and_then(|a0| m.inverse(p1, n1, Some(&a0))),
                ) else {
                    continue;
                };
                moves += 1;
                let poses: Vec<Pose> = (0..=64)
                    .map(|k| ck.pose_between(&a0, &a1, k as f64 / 64.0).unwrap())
                    .collect();
                let q0 = poses[0];
                let away: Vec<(f64, f64)> = poses
                    .iter()
                    .map(|q| ((q.p - q0.p).length(), turn_bound(&q0, q)))
                    .collect();
                for part in &ck.parts {
                    let (lo, hi) = grown_box(part, &q0, &away);
                    for (k, q) in poses.iter().enumerate() {
                        // the bound of the part's points' travel against the brute force's
                        let (d, theta) = away[k];
                        let brute = tests::brute_displacement(part, &q0, q);
                        assert!(
                            brute <= (d + part.reach * theta) * (1.0 + 1e-9) + 1e-5 * part.reach,
                            "{name}, {}, case {case}, pose {k}: the points move {brute:.6} mm, bound {:.6}",
                            part.name,
                            d + part.reach * theta
                        );
                        let (l, h) = part.pose(q.p, q.n, q.frame.as_ref()).aabb();
                        assert!(
                            l.cmpge(lo).all() && h.cmple(hi).all(),
                            "{name}, {}, case {case}, pose {k}: box {l:?}..{h:?} outside the grown {lo:?}..{hi:?}",
                            part.name
                        );
                    }
                }
            }
            assert!(moves >= 20, "{name}: only {moves} of 30 moves reachable");
        }
    }

    /// `turn_bound` is at least the frames' rotation angle measured another way (the angle of
    /// the quaternion of `R_b R_aᵀ`), for turns from 10⁻⁹ rad to π.
    #[test]
    fn the_turn_bound_is_at_least_the_rotation_angle() {
        let mut rng = Lcg(5);
        for k in 0..4000 {
            let axis = rng.axis(true);
            let ra = DMat3::from_axis_angle(rng.axis(true), rng.range(0.0, 3.0));
            let angle = match k % 4 {
                0 => 1e-9 * 10f64.powf(rng.range(0.0, 6.0)),
                1 => rng.range(0.0, 0.01),
                _ => rng.range(0.0, std::f64::consts::PI),
            };
            let rb = DMat3::from_axis_angle(axis, angle) * ra;
            let pose = |r: DMat3| Pose {
                p: DVec3::ZERO,
                n: r.z_axis,
                frame: Some(r),
            };
            let (a, b) = (pose(ra), pose(rb));
            let q = glam::DQuat::from_mat3(&(rb * ra.transpose()));
            let measured = 2.0 * q.xyz().length().atan2(q.w.abs());
            let bound = turn_bound(&a, &b);
            assert!(
                bound >= measured,
                "turn {angle:e}: bound {bound:e} under the measured {measured:e}"
            );
            assert!(
                measured > 0.1 || bound <= measured * (1.0 + 1e-3) + 2e-6,
                "turn {angle:e}: bound {bound:e} far over the measured {measured:e}"
            );
            // without frames: the tool axes' angle
            let (mut a2, mut b2) = (a, b);
            (a2.frame, b2.frame) = (None, None);
            let axes = a.n.cross(b.n).length().atan2(a.n.dot(b.n));
            assert!(turn_bound(&a2, &b2) >= axes, "turn {angle:e}: axes' bound");
        }
    }

    /// Law of the per-part sampling ([`checked_poses`]): between two consecutive poses a part
    /// is checked at, none of its points moves more than [`SAMPLE_STEP_MM`] (measured by brute
    /// force at its extreme points), the move's first and last poses are checked, and a short
    /// part (the nozzle) is checked at fewer poses than the farthest one. Random moves that
    /// turn the PAX and B heads by up to 20°, sampled as `check_move` samples them.
    #[test]
    fn each_part_is_checked_at_poses_its_own_points_move_at_most_a_step_between() {
        let mut rng = Lcg(11);
        for name in ["pax-5axis", "fullcontrol-prusa-b", "rtn-slicer4rtn"] {
            let spec = preset(name).unwrap();
            let ck = Checker::new(&spec).unwrap();
            let m = spec.build().unwrap();
            let (mut nozzle, mut farthest) = (0, 0);
            for _ in 0..40 {
                let tilt = |r: &mut Lcg| {
                    let (t, az) = (
                        r.range(0.0, 30f64.to_radians()),
                        r.range(0.0, std::f64::consts::TAU),
                    );
                    DVec3::new(t.sin() * az.cos(), t.sin() * az.sin(), t.cos())
                };
                let p0 = rng.within(DVec3::new(80.0, 80.0, 1.0), DVec3::new(120.0, 120.0, 20.0));
                let p1 = p0 + rng.within(DVec3::new(-3.0, -3.0, -1.0), DVec3::new(3.0, 3.0, 1.0));
                let a0 = m.inverse(p0, tilt(&mut rng), None).unwrap();
                let a1 = m.inverse(p1, tilt(&mut rng), Some(&a0)).unwrap();
                // check_move's sampling: every head point within the step between neighbours
                let (q0, q1) = (ck.pose(&a0).unwrap(), ck.pose(&a1).unwrap());
                let n = ((ck.displacement(&q0, &q1) / SAMPLE_STEP_MM).ceil() as usize).max(1) * 4;
                let poses: Vec<Pose> = (0..=n)
                    .map(|k| ck.pose_between(&a0, &a1, k as f64 / n as f64).unwrap())
                    .collect();
                let counts: Vec<usize> = ck
                    .parts
                    .iter()
                    .map(|part| {
                        let keep = checked_poses(&poses, part.reach);
                        assert!(
                            keep[0] && keep[n],
                            "{name}, {}: the ends are checked",
                            part.name
                        );
                        let kept: Vec<&Pose> = poses
                            .iter()
                            .zip(&keep)
                            .filter(|(_, &k)| k)
                            .map(|(p, _)| p)
                            .collect();
                        for w in kept.windows(2) {
                            let d = tests::brute_displacement(part, w[0], w[1]);
                            assert!(
                                d <= SAMPLE_STEP_MM + 1e-9,
                                "{name}, {}: {d:.4} mm between two checked poses",
                                part.name
                            );
                        }
                        kept.len()
                    })
                    .collect();
                nozzle += counts[0];
                farthest += counts.iter().copied().max().unwrap();
            }
            assert!(
                nozzle < farthest,
                "{name}: the nozzle checked at {nozzle} poses, the farthest part at {farthest}"
            );
        }
    }
}
