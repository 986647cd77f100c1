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
//! [`MAX_SAMPLES`]; the report counts moves that hit it). So a bead of a line width (≥ 0.4 mm)
//! cannot pass between two samples of a head part.
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
use super::material::{cell_of, centre, Material, CELL_MM};
use super::solid::Posed;
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

/// One sampled pose.
#[derive(Clone, Copy, Debug)]
struct Pose {
    p: DVec3,
    n: DVec3,
    frame: Option<DMat3>,
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

    /// Take the findings.
    pub fn take_findings(&mut self) -> Vec<CollisionFinding> {
        std::mem::take(&mut self.findings)
    }

    fn pose(&self, axes: &[f64]) -> Result<Pose, MachineError> {
        let (p, n) = self.machine.forward(axes)?;
        Ok(Pose {
            p,
            n,
            frame: self.machine.head_frame(axes),
        })
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

    /// Upper bound of the displacement of any head point between two poses, mm.
    fn displacement(&self, a: &Pose, b: &Pose) -> f64 {
        let theta = match (&a.frame, &b.frame) {
            (Some(ra), Some(rb)) => {
                let r = *rb * ra.transpose();
                let c = ((r.x_axis.x + r.y_axis.y + r.z_axis.z - 1.0) * 0.5).clamp(-1.0, 1.0);
                num::acos(c)
            }
            _ => a.n.angle_between(b.n),
        };
        (b.p - a.p).length() + self.reach * theta
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
        let p0 = self.pose(from)?;
        let p1 = self.pose(to)?;
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
                .all(|w| self.displacement(&w[0], &w[1]) <= SAMPLE_STEP_MM);
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
        let start = usize::from(!include_start);
        let poses = &poses[start..];
        // per part, over the whole move: can it reach the material or the bed at all? (the
        // union of its boxes against the material's block maxima and the bed's top)
        let tol = CONTACT_TOLERANCE_MM;
        let reachable: Vec<(bool, bool)> = self
            .parts
            .iter()
            .map(|part| {
                let (mut lo, mut hi) =
                    (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
                for pose in poses {
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
        // a translation (the pose fixed): the cells each frustum part can reach over the
        // whole move, found once
        let fixed = !self.exhaustive && p0.n.angle_between(p1.n) < 1e-12 && p0.frame == p1.frame;
        let swept: Vec<Option<Vec<SweptCell>>> = self
            .parts
            .iter()
            .zip(&reachable)
            .map(|(part, &(mat, _))| {
                (fixed && mat)
                    .then(|| self.swept_cells(part, &p0, &p1))
                    .flatten()
            })
            .collect();
        let mut found: Vec<CollisionFinding> = Vec::new();
        for pose in poses {
            self.stats.samples += 1;
            for ((part, &(mut mat, bed)), cells) in self.parts.iter().zip(&reachable).zip(&swept) {
                if cells.as_ref().is_some_and(|c| c.is_empty()) {
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
                    self.penetrations(&solid, contact.as_ref(), mat, cells.as_deref(), bed)
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
        Ok(())
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
            // the depth is at most h − z_in (the contact surface only takes from it)
            let floor = match contact {
                _ if self.exhaustive => f64::NEG_INFINITY,
                Some(c) => solid.floor_at(x, y).max(c.floor_at(x, y)),
                None => solid.floor_at(x, y),
            };
            if h - floor <= tol {
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
            for c in cells {
                consider(c.h, c.x, c.y, c.bead, contact, &mut best);
            }
        } else if material {
            // only the columns near the tip can reach the highest material under the solid
            let (mut x0, mut y0, mut x1, mut y1) = (lo.x, lo.y, hi.x, hi.y);
            let m = self.material.max_over((x0, y0, x1, y1)) - tol;
            let r = match (
                solid.radius_below(m),
                contact.and_then(|c| c.radius_below(m)),
            ) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            if let (Some(r), Posed::Frustum { o, .. }, false) = (r, solid, self.exhaustive) {
                (x0, y0) = (x0.max(o.x - r), y0.max(o.y - r));
                (x1, y1) = (x1.min(o.x + r), y1.min(o.y + r));
            }
            // the block's region between the solid's lowest point and its top
            let zlow = lo.z;
            let above = if self.exhaustive {
                f64::NEG_INFINITY
            } else {
                lo.z + tol
            };
            self.material.for_cells_above(
                (x0, y0, x1, y1),
                above,
                |c, r, top| {
                    let c = DVec3::new(c.x, c.y, 0.5 * (zlow + top));
                    !self.exhaustive && solid.distance(c) > r.hypot(0.5 * (top - zlow))
                },
                |i, j, h, bead| consider(h, centre(i), centre(j), bead, contact, &mut best),
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

    /// The material cells a frustum part can reach while it translates from pose `a` to `b`
    /// (same tool axis and frame): `None` for other parts. The part's floor
    /// ([`Posed::floor_at`], and the contact surface's for the tip part,
    /// [`ContactSurface::floor_at`]) depends on the horizontal distance D from the tip only, and
    /// grows with D; over the move a cell is at least `D_min` (its distance from the tip's
    /// path) from the tip, and the tip at least as high as its lower end: the floor of the
    /// part at that lowest tip, placed at the path's point nearest the cell, bounds every
    /// sampled pose's floor from below, so a cell under it cannot be reached; a whole block is
    /// skipped when its highest top is under that floor at the block's least distance from the
    /// path (the floor grows with the distance).
    fn swept_cells(&self, part: &Part, a: &Pose, b: &Pose) -> Option<Vec<SweptCell>> {
        let tol = CONTACT_TOLERANCE_MM;
        let low_z = a.p.z.min(b.p.z);
        let at = |xy: glam::DVec2| DVec3::new(xy.x, xy.y, low_z);
        let sa = part.pose(a.p, a.n, a.frame.as_ref());
        if !matches!(sa, Posed::Frustum { .. }) {
            return None;
        }
        let sb = part.pose(b.p, b.n, b.frame.as_ref());
        let (la, ha) = sa.aabb();
        let (lb, hb) = sb.aabb();
        let (lo, hi) = (la.min(lb), ha.max(hb));
        let base = part.pose(at(a.p.truncate()), a.n, a.frame.as_ref());
        let m = self.material.max_over((lo.x, lo.y, hi.x, hi.y)) - tol;
        let contact = |tip: DVec3| {
            part.tip
                .then(|| ContactSurface::new(tip, a.n, self.max_width))
        };
        let r = match (
            base.radius_below(m),
            contact(at(a.p.truncate())).and_then(|c| c.radius_below(m)),
        ) {
            (Some(x), Some(y)) => Some(x.min(y)),
            (x, y) => x.or(y),
        };
        let (mut x0, mut y0, mut x1, mut y1) = (lo.x, lo.y, hi.x, hi.y);
        if let Some(r) = r {
            x0 = x0.max(a.p.x.min(b.p.x) - r);
            y0 = y0.max(a.p.y.min(b.p.y) - r);
            x1 = x1.min(a.p.x.max(b.p.x) + r);
            y1 = y1.min(a.p.y.max(b.p.y) + r);
        }
        let (pa, d) = (a.p.truncate(), (b.p - a.p).truncate());
        let l2 = d.length_squared();
        // the floor at horizontal distance D from the lowest tip (it depends on D only and
        // grows with it): at a cell's distance from the path it bounds the part's floor there
        // at every pose, at a block's least distance the floor of every cell of the block
        let low_tip = DVec3::new(0.0, 0.0, low_z);
        let low_solid = part.pose(low_tip, a.n, a.frame.as_ref());
        let low_contact = contact(low_tip);
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
        self.max_width = self.max_width.max(width);
        let a = self.pose(from)?;
        let b = self.pose(to)?;
        // a straight bead when the pose is fixed; pieces of at most a cell otherwise
        let pieces = if a.n.angle_between(b.n) < 1e-9 {
            1
        } else {
            ((b.p - a.p).length() / CELL_MM).ceil().clamp(1.0, 4096.0) as usize
        };
        let mut prev = a;
        for k in 1..=pieces {
            let t = k as f64 / pieces as f64;
            let next = if k == pieces {
                b
            } else {
                self.pose_between(from, to, t)?
            };
            let n = (prev.n + next.n).normalize_or(next.n);
            let slope = self.cross_slope(prev.p, next.p, n, width);
            self.material
                .deposit(prev.p, next.p, slope, width, self.layer);
            prev = next;
        }
        Ok(())
    }
}
