//! The print head and the bed as simple solids, for the collision check ([`crate::collision`]).
//!
//! ## The head, in the tool frame
//! The **tool frame** has its origin at the nozzle tip, its z axis along the tool axis `n`
//! (tip → nozzle body) and its x axis where the machine turns it ([`super::Machine::head_frame`]:
//! for the B head R_y(B)·e_x, for rotating heads R_z(φ)·R_y(tilt)·e_x). Every part turns with
//! the tool (the B head, RTN and PAX rotary axes carry the whole hotend; on table machines the
//! head is fixed and the part turns, which in the part frame is the same). Parts:
//! - `cone`: the nozzle, a frustum of revolution about the tool axis from `from_mm` to
//!   `from_mm + length_mm`, radius `tip_radius_mm + (z − from_mm)·tan(half_angle)`;
//! - `cylinder`: radius `radius_mm` about the tool axis, `from_mm ≤ z ≤ to_mm` (heat sink);
//! - `box`: an axis-aligned box of the tool frame, `min ≤ (x, y, z) ≤ max` (heater block).
//!
//! A machine whose head twist about `n` is not known ([`super::Machine::head_frame`] gives
//! `None`) checks each box as the cylinder about the tool axis that contains it: more findings,
//! never fewer.
//!
//! ## Default head (E3D-V6 class, seed 000's MK3S+ nozzle)
//! Nozzle: tip flat Ø 1 mm, 40° half-angle, 4.5 mm from the tip to the heater block (the V6
//! nozzle's hex, 7 mm across flats, fits inside the cone at 4.5 mm). Heater block 20 × 16 ×
//! 11.5 mm with the nozzle 6 mm from its −x end (the cartridge towards +x), from 4.5 to 16 mm.
//! Heat sink Ø 22.3 mm from 18 to 44 mm. With the tip on the bed, the block's +x edge touches the
//! bed at tilt atan(4.5/14) = 17.8°: seed 000 §4.3.1 found 18° for the B head by trying.
//! The RTN presets (kind `rtn`, seed 002) take a long nozzle below the same block: 15 mm,
//! 15° half-angle, so that at the fixed 45° tilt the block stays above the tip's plane (seed
//! 002's own RTN had its block "touching the bed (same height as nozzle)").
//!
//! ## The bed, in the output (part) frame
//! The part sits on the bed, so in the output frame the bed does not move, whatever the machine
//! turns: `plate` (a rectangle `min`..`max` in x, y with its top at `top_mm`), `disc` (centre,
//! radius, top) or `none`. The default per kind: the MK3S+ plate 250 × 210 mm for the B head;
//! the RatRig 300 × 293 mm (seed 001 §4.1) for the triple-Z bed; a disc about the output origin
//! for the turning tables (Open5x: radius 60 mm, a documented guess; polar: 150 mm, its reach);
//! a 300 mm plate about the origin otherwise; none for the lathe (the mandrel is not a plate).

use serde::{Deserialize, Serialize};

use super::MachineError;

/// One named solid of the head (JSON `{"shape": "cone", "name": "nozzle", ...}`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "kebab-case", deny_unknown_fields)]
#[non_exhaustive]
pub enum HeadPart {
    /// A frustum of revolution about the tool axis (the nozzle).
    Cone {
        /// The name a finding gives (`nozzle`, `heater-block`, …).
        name: String,
        /// Radius at `from_mm` (the nozzle's flat tip), mm.
        tip_radius_mm: f64,
        /// Half-angle of the cone, degrees, in [0, 89].
        half_angle_deg: f64,
        /// Length along the tool axis, mm.
        length_mm: f64,
        /// Where it starts above the tip, mm (0: at the tip).
        #[serde(default)]
        from_mm: f64,
    },
    /// A cylinder about the tool axis.
    Cylinder {
        /// The name a finding gives.
        name: String,
        /// Radius, mm.
        radius_mm: f64,
        /// Lower end above the tip, mm.
        from_mm: f64,
        /// Upper end above the tip, mm.
        to_mm: f64,
    },
    /// An axis-aligned box of the tool frame, mm.
    Box {
        /// The name a finding gives.
        name: String,
        /// Lowest corner (x, y, z), mm.
        min: [f64; 3],
        /// Highest corner (x, y, z), mm.
        max: [f64; 3],
    },
}

impl HeadPart {
    /// The part's name.
    pub fn name(&self) -> &str {
        match self {
            HeadPart::Cone { name, .. }
            | HeadPart::Cylinder { name, .. }
            | HeadPart::Box { name, .. } => name,
        }
    }
}

/// The head: named solids in the tool frame (JSON `"head": {"parts": [...]}`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeadSpec {
    /// The parts, checked in this order.
    pub parts: Vec<HeadPart>,
}

/// The bed in the output frame (JSON `"bed": {"shape": ...}`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "kebab-case", deny_unknown_fields)]
#[non_exhaustive]
pub enum BedSpec {
    /// A rectangular plate.
    Plate {
        /// Lowest corner (x, y), mm.
        min: [f64; 2],
        /// Highest corner (x, y), mm.
        max: [f64; 2],
        /// Height of its top surface, mm.
        #[serde(default)]
        top_mm: f64,
    },
    /// A round plate.
    Disc {
        /// Centre (x, y), mm.
        center: [f64; 2],
        /// Radius, mm.
        radius_mm: f64,
        /// Height of its top surface, mm.
        #[serde(default)]
        top_mm: f64,
    },
    /// No bed is checked.
    None,
}

/// Nozzle of the default head: radius of the flat tip, mm (Ø 1 mm for a 0.4 mm nozzle).
pub const V6_TIP_RADIUS_MM: f64 = 0.5;
/// Nozzle cone half-angle, degrees (contains the 7 mm hex at 4.5 mm).
pub const V6_NOZZLE_HALF_ANGLE_DEG: f64 = 40.0;
/// Tip to heater block, mm (E3D V6).
pub const V6_NOZZLE_LENGTH_MM: f64 = 4.5;
/// The rotating tilted nozzle's long nozzle, tip to heater block, mm: at the fixed 45° tilt the
/// block's far edge (14 mm from the nozzle) is then 0.7 mm above the tip, where seed 002's
/// Micro Swiss RTN had its block "touching the bed (same height as nozzle)".
pub const RTN_NOZZLE_LENGTH_MM: f64 = 15.0;
/// The long nozzle's tip radius, mm: its 0.4 mm opening (a flat tip tilted 45° over a planar
/// layer would dip r·sin 45° below the tip).
pub const RTN_TIP_RADIUS_MM: f64 = 0.2;
/// The long nozzle's half-angle, degrees (Ø 8.5 mm at the block).
pub const RTN_NOZZLE_HALF_ANGLE_DEG: f64 = 15.0;

impl HeadSpec {
    /// The E3D-V6-class head with the nozzle protruding `nozzle_mm` below the heater block (see
    /// the module documentation).
    pub fn v6(nozzle_mm: f64, half_angle_deg: f64, tip_radius_mm: f64) -> HeadSpec {
        let b = nozzle_mm;
        HeadSpec {
            parts: vec![
                HeadPart::Cone {
                    name: "nozzle".into(),
                    tip_radius_mm,
                    half_angle_deg,
                    length_mm: b,
                    from_mm: 0.0,
                },
                HeadPart::Box {
                    name: "heater-block".into(),
                    min: [-6.0, -8.0, b],
                    max: [14.0, 8.0, b + 11.5],
                },
                HeadPart::Cylinder {
                    name: "heat-sink".into(),
                    radius_mm: 11.15,
                    from_mm: b + 13.5,
                    to_mm: b + 39.5,
                },
            ],
        }
    }

    /// The default head of a machine kind (see the module documentation).
    pub fn default_for(kind: &str) -> HeadSpec {
        match kind {
            "rtn" => HeadSpec::v6(
                RTN_NOZZLE_LENGTH_MM,
                RTN_NOZZLE_HALF_ANGLE_DEG,
                RTN_TIP_RADIUS_MM,
            ),
            _ => HeadSpec::v6(
                V6_NOZZLE_LENGTH_MM,
                V6_NOZZLE_HALF_ANGLE_DEG,
                V6_TIP_RADIUS_MM,
            ),
        }
    }

    /// Refuse unusable sizes (negative, non-finite, inverted boxes, cones of 90° or more).
    pub fn validate(&self, machine: &str) -> Result<(), MachineError> {
        let bad = |name: &str, what: String| MachineError::BadSpec {
            machine: machine.to_string(),
            message: format!("head part '{name}': {what}"),
        };
        if self.parts.is_empty() {
            return Err(MachineError::BadSpec {
                machine: machine.to_string(),
                message: "head has no parts (give at least the nozzle)".into(),
            });
        }
        for p in &self.parts {
            let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
            match p {
                HeadPart::Cone {
                    tip_radius_mm: r,
                    half_angle_deg: a,
                    length_mm: l,
                    from_mm: f,
                    ..
                } => {
                    if !finite(&[*r, *a, *l, *f]) || *r < 0.0 || *l <= 0.0 || *f < 0.0 {
                        return Err(bad(p.name(), format!("tip_radius_mm = {r}, length_mm = {l}, from_mm = {f}: radius and from_mm must be ≥ 0, length_mm > 0")));
                    }
                    if !(0.0..=89.0).contains(a) {
                        return Err(bad(
                            p.name(),
                            format!("half_angle_deg = {a} must be in [0, 89]"),
                        ));
                    }
                }
                HeadPart::Cylinder {
                    radius_mm: r,
                    from_mm: a,
                    to_mm: b,
                    ..
                } => {
                    if !finite(&[*r, *a, *b]) || *r <= 0.0 || *b <= *a {
                        return Err(bad(p.name(), format!("radius_mm = {r}, from_mm = {a}, to_mm = {b}: radius must be > 0 and to_mm > from_mm")));
                    }
                }
                HeadPart::Box { min, max, .. } => {
                    if !finite(min) || !finite(max) || (0..3).any(|i| max[i] <= min[i]) {
                        return Err(bad(
                            p.name(),
                            format!("box min {min:?} max {max:?}: every max must exceed its min"),
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

impl BedSpec {
    /// The default bed of a machine kind (see the module documentation).
    pub fn default_for(kind: &str) -> BedSpec {
        match kind {
            "b-head" => BedSpec::Plate {
                min: [0.0, 0.0],
                max: [250.0, 210.0],
                top_mm: 0.0,
            },
            "three-z" => BedSpec::Plate {
                min: [0.0, 0.0],
                max: [300.0, 293.0],
                top_mm: 0.0,
            },
            "ab-table" => BedSpec::Disc {
                center: [0.0, 0.0],
                radius_mm: 60.0,
                top_mm: 0.0,
            },
            "r-theta" => BedSpec::Disc {
                center: [0.0, 0.0],
                radius_mm: 150.0,
                top_mm: 0.0,
            },
            "lathe-a" => BedSpec::None,
            _ => BedSpec::Plate {
                min: [-150.0, -150.0],
                max: [300.0, 300.0],
                top_mm: 0.0,
            },
        }
    }

    /// Refuse unusable sizes.
    pub fn validate(&self, machine: &str) -> Result<(), MachineError> {
        let ok = match self {
            BedSpec::Plate { min, max, top_mm } => {
                [min[0], min[1], max[0], max[1], *top_mm]
                    .iter()
                    .all(|v| v.is_finite())
                    && max[0] > min[0]
                    && max[1] > min[1]
            }
            BedSpec::Disc {
                center,
                radius_mm,
                top_mm,
            } => {
                [center[0], center[1], *radius_mm, *top_mm]
                    .iter()
                    .all(|v| v.is_finite())
                    && *radius_mm > 0.0
            }
            BedSpec::None => true,
        };
        if ok {
            Ok(())
        } else {
            Err(MachineError::BadSpec {
                machine: machine.to_string(),
                message: format!("bed {self:?}: sizes must be finite, max > min, radius > 0"),
            })
        }
    }

    /// Whether (x, y) is over the bed.
    pub fn covers(&self, x: f64, y: f64) -> bool {
        match self {
            BedSpec::Plate { min, max, .. } => {
                x >= min[0] && x <= max[0] && y >= min[1] && y <= max[1]
            }
            BedSpec::Disc {
                center, radius_mm, ..
            } => (x - center[0]).hypot(y - center[1]) <= *radius_mm,
            BedSpec::None => false,
        }
    }

    /// Height of the bed's top, mm (−∞ for no bed).
    pub fn top(&self) -> f64 {
        match self {
            BedSpec::Plate { top_mm, .. } | BedSpec::Disc { top_mm, .. } => *top_mm,
            BedSpec::None => f64::NEG_INFINITY,
        }
    }
}

/// The tool frame of a head turned by φ about +Z after tilting by `t` about +Y (radians):
/// `R_z(φ)·R_y(t)`, columns x = (cos t cos φ, cos t sin φ, −sin t), y = (−sin φ, cos φ, 0),
/// z = (sin t cos φ, sin t sin φ, cos t) = the tool axis.
pub fn turned_frame(phi: f64, t: f64) -> glam::DMat3 {
    use crate::num::{cos, sin};
    let (sp, cp, st, ct) = (sin(phi), cos(phi), sin(t), cos(t));
    glam::DMat3::from_cols(
        glam::DVec3::new(ct * cp, ct * sp, -st),
        glam::DVec3::new(-sp, cp, 0.0),
        glam::DVec3::new(st * cp, st * sp, ct),
    )
}

/// Below this length of `∂p/∂X` made orthogonal to the tool axis (per mm of X), X runs along
/// the tool axis and gives no head twist: [`fixed_head_frame`] says `None` (unit-free ratio).
pub const FIXED_FRAME_DEGENERATE: f64 = 1e-6;

/// The tool frame of a head that does not turn about its tool axis in the machine: the part
/// turns instead (A/B table, triple-Z tilting bed, polar table), or the head tilts only about
/// the machine's Y (the polar machine's B). The head's x axis is then the machine's +X made
/// orthogonal to the tool axis; in the part (output) frame, +X is the way the tip moves
/// relative to the part as X grows, `∂p/∂X`, exact because the tip is affine in the linear
/// axes at a fixed pose ([`super::Machine::linear_at_fixed_pose`], machine law 3; X is a
/// G-code coordinate of the tip relative to the bed whichever of the two moves). With
/// `n = forward(axes).1`:
///
/// `x = normalize(d − (d·n) n)`, `d = p(axes + e_X) − p(axes)`, `y = n × x`, `z = n`.
///
/// For the A/B table (seed 004) this is `R⁻¹·e_x` with `R` the table's rotation; for the polar
/// machine `R_z(−C)·R_y(B)·e_x`. `None` where X runs along the tool axis (a 90° tilt) or the
/// forward kinematics fails.
pub fn fixed_head_frame(machine: &dyn super::Machine, axes: &[f64]) -> Option<glam::DMat3> {
    let (p, n) = machine.forward(axes).ok()?;
    fixed_head_frame_at(machine, axes, p, n)
}

/// [`super::Machine::pose`] of a machine whose head frame is [`fixed_head_frame`]: the forward
/// kinematics once for the tip, the tool axis and the frame (the frame's own needs the tip
/// and axis at `axes` and the tip at `axes + e_X`: two forward calls, not three).
pub fn fixed_head_pose(
    machine: &dyn super::Machine,
    axes: &[f64],
) -> Result<(glam::DVec3, glam::DVec3, Option<glam::DMat3>), super::MachineError> {
    let (p, n) = machine.forward(axes)?;
    Ok((p, n, fixed_head_frame_at(machine, axes, p, n)))
}

/// [`fixed_head_frame`] at axes whose forward kinematics `(p, n)` the caller has.
fn fixed_head_frame_at(
    machine: &dyn super::Machine,
    axes: &[f64],
    p: glam::DVec3,
    n: glam::DVec3,
) -> Option<glam::DMat3> {
    let mut moved = axes.to_vec();
    *moved.first_mut()? += 1.0;
    let (q, _) = machine.forward(&moved).ok()?;
    let d = q - p;
    let x = d - d.dot(n) * n;
    if x.length() < FIXED_FRAME_DEGENERATE * d.length().max(1.0) {
        return None;
    }
    let x = x.normalize();
    Some(glam::DMat3::from_cols(x, n.cross(x), n))
}

/// The head's clearance profile for lifts ([`crate::emit::clearance`]): one piece per part, in
/// the tool frame. A cone's radius and its reach towards the tilt's descent are both
/// `tip_radius + (s − from)·tan(half_angle)`; a cylinder's are its radius; a box's radius is its
/// farthest corner from the tool axis, and its reach towards the descent is `max(|x_min|,
/// |x_max|)` when `tilt_frame` (the head tilts in the vertical plane of its tool axis, its x
/// axis along the descent or against it: `R_z(φ)·R_y(t)`, the B head, RTN and PAX heads, the
/// 3-axis head), else that same farthest corner (a head the part turns under, whose twist about
/// the tool axis the profile does not know).
pub fn clearance_profile(head: &HeadSpec, tilt_frame: bool) -> crate::emit::clearance::HeadProfile {
    use crate::emit::clearance::{HeadProfile, ProfilePiece};
    let pieces = head
        .parts
        .iter()
        .filter_map(|part| match part {
            HeadPart::Cone {
                name,
                tip_radius_mm,
                half_angle_deg,
                length_mm,
                from_mm,
            } => {
                let r1 =
                    tip_radius_mm + length_mm * crate::num::tan(crate::num::rad(*half_angle_deg));
                Some(ProfilePiece {
                    name: name.clone(),
                    from_mm: *from_mm,
                    to_mm: from_mm + length_mm,
                    radius_mm: [*tip_radius_mm, r1],
                    drop_mm: [*tip_radius_mm, r1],
                })
            }
            HeadPart::Cylinder {
                name,
                radius_mm,
                from_mm,
                to_mm,
            } => Some(ProfilePiece {
                name: name.clone(),
                from_mm: *from_mm,
                to_mm: *to_mm,
                radius_mm: [*radius_mm; 2],
                drop_mm: [*radius_mm; 2],
            }),
            HeadPart::Box { name, min, max } => {
                let corner = [min[0], max[0]]
                    .iter()
                    .flat_map(|x| [min[1], max[1]].map(|y| x.hypot(y)))
                    .fold(0.0, f64::max);
                let drop = if tilt_frame {
                    min[0].abs().max(max[0].abs())
                } else {
                    corner
                };
                Some(ProfilePiece {
                    name: name.clone(),
                    from_mm: min[2],
                    to_mm: max[2],
                    radius_mm: [corner; 2],
                    drop_mm: [drop; 2],
                })
            }
            #[allow(unreachable_patterns)]
            _ => None,
        })
        .collect();
    HeadProfile {
        pieces,
        ..HeadProfile::default()
    }
}
