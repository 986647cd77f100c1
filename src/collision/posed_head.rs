//! The head at one pose, for drawing (the web preview draws the head's solids at the move its
//! slider or a clicked finding selects): each part of the machine's head
//! ([`crate::machine::head`]) placed by the collision check's own code
//! ([`super::Checker::posed_head`]: the machine's forward kinematics and head frame), so what
//! the page draws is what the check tests — no copy of the head's sizes outside the core.
//!
//! Geometry, output (part) frame, mm:
//! - a frustum (the nozzle's cone, a cylinder, or a box of a head whose twist about the tool
//!   axis is unknown, taken as the cylinder that contains it): the centres of its end discs,
//!   `base = o + s0·a`, `top = o + s1·a` (`o` the tip, `a` the tool axis), and their radii
//!   `r0`, `r1 = r0 + k (s1 − s0)`;
//! - a box: its centre `o + R·(min + max)/2`, its axes (the columns of `R`, the head frame)
//!   and half-sizes `(max − min)/2`.

use glam::DVec3;
use serde::Serialize;

use super::solid::Posed;
use super::Checker;
use crate::machine::{MachineError, MachineSpec};

/// One posed part as the page draws it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HeadSolid {
    /// The part's name (the one a finding gives).
    pub name: String,
    /// Its geometry (see the module documentation).
    #[serde(flatten)]
    pub geometry: SolidGeometry,
}

/// A posed solid's geometry (see the module documentation).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[non_exhaustive]
pub enum SolidGeometry {
    /// A frustum of revolution: end disc centres and radii.
    Frustum {
        /// Centre of the end disc at `s0` (the nozzle's: the tip itself).
        base: [f64; 3],
        /// Centre of the end disc at `s1`.
        top: [f64; 3],
        /// Radius at `base`.
        base_radius: f64,
        /// Radius at `top`.
        top_radius: f64,
    },
    /// An oriented box.
    Box {
        /// Centre.
        center: [f64; 3],
        /// Its x, y and z axes (unit, output frame).
        axes: [[f64; 3]; 3],
        /// Half-sizes along those axes.
        half: [f64; 3],
    },
}

/// The head at one pose: the tip, the tool axis and every part, in the head's order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HeadAt {
    /// The tip (output frame), mm.
    pub tip: [f64; 3],
    /// The unit tool axis (tip → nozzle).
    pub axis: [f64; 3],
    /// The parts.
    pub parts: Vec<HeadSolid>,
}

impl SolidGeometry {
    /// The geometry of a posed solid.
    pub fn of(solid: &Posed) -> SolidGeometry {
        match *solid {
            Posed::Frustum {
                o,
                a,
                s0,
                s1,
                r0,
                k,
            } => SolidGeometry::Frustum {
                base: (o + a * s0).to_array(),
                top: (o + a * s1).to_array(),
                base_radius: r0,
                top_radius: r0 + k * (s1 - s0),
            },
            Posed::Box { o, r, min, max } => SolidGeometry::Box {
                center: (o + r * ((min + max) * 0.5)).to_array(),
                axes: [
                    r.x_axis.to_array(),
                    r.y_axis.to_array(),
                    r.z_axis.to_array(),
                ],
                half: ((max - min) * 0.5).to_array(),
            },
        }
    }
}

/// The head of `spec` at the axis values `axes` (machine order; linear mm, rotary degrees).
/// Errors: the machine's (a wrong axis count, an unreachable pose), and the lathe's
/// `machine.collision-unsupported` (its head is not checked, so not drawn).
pub fn head_at(spec: &MachineSpec, axes: &[f64]) -> Result<HeadAt, MachineError> {
    let checker = Checker::new(spec)?;
    let (tip, axis): (DVec3, DVec3) = checker.machine().forward(axes)?;
    let parts = checker
        .posed_head(axes)?
        .into_iter()
        .map(|(name, solid)| HeadSolid {
            name,
            geometry: SolidGeometry::of(&solid),
        })
        .collect();
    Ok(HeadAt {
        tip: tip.to_array(),
        axis: axis.to_array(),
        parts,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::preset;

    /// The B head (seed 000): tip `(X − r sin B, Y, Z − r cos B + r)`, axis `(sin B, 0, cos B)`
    /// (docs/machines.md), written here; the nozzle's base disc is the tip, its top 4.5 mm up
    /// the axis (the default head's nozzle length), the heater block's x axis the head's
    /// `R_y(B)·e_x = (cos B, 0, −sin B)`.
    #[test]
    fn b_head_parts_are_posed_at_the_tip_along_the_tool_axis() {
        let spec = preset("fullcontrol-prusa-b").unwrap();
        let (x, y, z, b) = (120.0, 80.0, 30.0, 40f64);
        let h = head_at(&spec, &[x, y, z, b]).unwrap();
        let (s, c) = b.to_radians().sin_cos();
        let tip = DVec3::new(x - 46.0 * s, y, z - 46.0 * c + 46.0);
        let n = DVec3::new(s, 0.0, c);
        assert!((DVec3::from_array(h.tip) - tip).length() < 1e-9, "{h:?}");
        let names: Vec<&str> = h.parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["nozzle", "heater-block", "heat-sink"]);
        match &h.parts[0].geometry {
            SolidGeometry::Frustum { base, top, .. } => {
                assert!((DVec3::from_array(*base) - tip).length() < 1e-9);
                assert!((DVec3::from_array(*top) - (tip + n * 4.5)).length() < 1e-9);
            }
            g => panic!("nozzle {g:?}"),
        }
        match &h.parts[1].geometry {
            SolidGeometry::Box { axes, half, .. } => {
                assert!((DVec3::from_array(axes[0]) - DVec3::new(c, 0.0, -s)).length() < 1e-9);
                assert!((DVec3::from_array(*half) - DVec3::new(10.0, 8.0, 5.75)).length() < 1e-9);
            }
            g => panic!("block {g:?}"),
        }
    }

    #[test]
    fn a_wrong_axis_count_and_the_lathe_are_named_errors() {
        let spec = preset("fullcontrol-prusa-b").unwrap();
        let e = head_at(&spec, &[1.0, 2.0]).unwrap_err();
        assert_eq!(crate::error::Coded::code(&e), "machine.wrong-axis-count");
        let e = head_at(&preset("lathe-a").unwrap(), &[0.0, 0.0, 0.0]).unwrap_err();
        assert_eq!(
            crate::error::Coded::code(&e),
            "machine.collision-unsupported"
        );
    }
}
