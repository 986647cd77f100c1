//! Warps: the transform T from the model frame to the slicing frame, and back.
//!
//! A warp is chosen so that the planes z' = k·h of the warped mesh are the wanted non-planar
//! layers of the real part: layer k is the surface T_z(p) = k·h in the model frame. Each warp
//! lives in one file behind the one small [`Warp`] trait:
//!
//! | warp | T_z(x, y, z) | seed |
//! |---|---|---|
//! | [`curved`] | z + s·c·(x+a)² / (w/2 + \|a\|) | 000 Eq. 1 |
//! | [`tilted`] | z + s·c·\|x+a\| | 000 Eq. 2 |
//! | [`conic`] | z + c·r·tan α, r = \|(x, y) − centre\| | 002 (Slicer4RTN) |
//! | [`belt`] | z + (d·(x, y))·tan α | 002 (`--axis=3`) |
//! | [`cylindrical`] | ρ − R, ρ = distance to a horizontal axis ∥ X | 002 (mandrel) |
//! | [`spherical`] | ρ − R, ρ = distance to a centre | 002 (5-axis) |
//! | [`field`] | z + g(x, y), g typed as an expression of x, y (mm), or a fitted [`spline`] | issue 15 |
//!
//! c = +1 for `outward` (z' = z + g, g ≥ 0 growing away from the centre: layers fall outward and
//! the tool tilts outward), −1 for `inward`. The first four are shears in z: T(x,y,z) = (x, y, z + g(x,y)),
//! so det J = 1 and extruded volume is unchanged. The optional [`base`] blend keeps the first
//! layers flat: z' = z + w(z)·g(x, y). The cylindrical and spherical warps are not shears (their
//! own files implement [`Warp`]; det J ≠ 1, so E is scaled by 1/det J) and refuse `--base`.
//!
//! The tool axis at a model point is the unit layer normal ∇T_z / |∇T_z| (tip → nozzle).

use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

use crate::schema::{Param, ParamDefault, WarpInfo};

pub mod base;
pub mod belt;
pub mod conic;
pub mod curved;
pub mod cylindrical;
pub mod field;
pub mod laws;
pub mod over;
pub mod shear;
pub mod spherical;
pub mod spline;
pub mod thickness;
pub mod tilted;

pub use base::BaseBlend;
pub use shear::{Height, Shear};

/// Every warp, in menu order: what each says of itself (its file's `INFO`). Adding a warp:
/// its file, a [`WarpSpec`] variant, and one line here.
pub const WARPS: &[WarpInfo] = &[
    curved::INFO,
    tilted::INFO,
    conic::INFO,
    belt::INFO,
    cylindrical::INFO,
    spherical::INFO,
    field::INFO,
];

/// Complete a warp spec given as a JSON object (`{"kind": …, …}`, as the CLI and the web page
/// build it): every parameter left out takes its default ([`WarpInfo::params`]), and the
/// defaults derived from another parameter are filled in (the cylindrical axis and the
/// spherical centre sit just under the part, from the radius). Unknown kinds are left alone
/// (serde names them).
pub fn fill_defaults(spec: &mut serde_json::Map<String, serde_json::Value>) {
    use serde_json::Value;
    let Some(kind) = spec.get("kind").and_then(Value::as_str).map(str::to_string) else {
        return;
    };
    let Some(info) = WARPS.iter().find(|w| w.name == kind) else {
        return;
    };
    for p in info.params {
        if spec.contains_key(p.key) {
            continue;
        }
        if let Some(v) = p.default.to_json() {
            spec.insert(p.key.to_string(), v);
        }
    }
    let radius = spec.get("radius").and_then(Value::as_f64);
    match (kind.as_str(), radius) {
        ("cylindrical", Some(r)) if !spec.contains_key("axis") => {
            spec.insert(
                "axis".into(),
                Value::from(cylindrical::default_axis(r).to_vec()),
            );
        }
        ("spherical", Some(r)) if !spec.contains_key("center") => {
            spec.insert(
                "center".into(),
                Value::from(spherical::default_center(r).to_vec()),
            );
        }
        _ => {}
    }
}

/// `--strength s` of the curved and tilted warps (seed 000).
pub(crate) const STRENGTH: Param = Param::number("strength", "--strength", "Strength")
    .range(Some(0.0), None, (false, false))
    .step(0.05)
    .default(ParamDefault::Number(0.3))
    .help("s of seed 000 Eqs. 1–2: the layers' rise per mm of x (dimensionless)");
/// `--direction` (outward: c = +1).
pub(crate) const DIRECTION: Param = Param::number("direction", "--direction", "Direction")
    .choices(&["outward", "inward"])
    .default(ParamDefault::Text("outward"))
    .help(
        "outward: layers fall away from the centre and the tool tilts outward; inward: the reverse",
    );
/// `--offset a` of the curved and tilted warps (mm).
pub(crate) const OFFSET: Param = Param::number("offset", "--offset", "Offset")
    .unit("mm")
    .step(1.0)
    .default(ParamDefault::Number(0.0))
    .help("a: moves the vertex or crease to x = −a");
/// `--angle α` of the conic and belt warps (degrees).
pub(crate) const ANGLE: Param = Param::number("angle", "--angle", "Angle")
    .unit("deg")
    .range(Some(0.0), Some(90.0), (true, true))
    .step(1.0)
    .default(ParamDefault::Number(30.0))
    .help("α: the layers' slope from horizontal (0 < α < 90)");
/// `--radius R` of the cylindrical and spherical warps (mm).
pub(crate) const RADIUS: Param = Param::number("radius", "--radius", "Radius")
    .unit("mm")
    .range(Some(0.0), None, (true, false))
    .step(1.0)
    .default(ParamDefault::Number(10.0))
    .help("R: the radius of the first layer (mandrel or inner sphere)");

/// A transform T from the model frame to the slicing frame (both mm).
pub trait Warp: Send + Sync + std::fmt::Debug {
    /// T(p): model frame → slicing frame.
    fn forward(&self, p: DVec3) -> DVec3;
    /// T⁻¹(q): slicing frame → model frame.
    fn inverse(&self, q: DVec3) -> DVec3;
    /// The Jacobian ∂T/∂p at a model-frame point (columns ∂T/∂x, ∂T/∂y, ∂T/∂z).
    fn jacobian(&self, p: DVec3) -> DMat3;

    /// det J at a model-frame point: the ratio of warped to model volume. Unwarped extrusion is
    /// E_out = E_in / det J.
    fn jacobian_det(&self, p: DVec3) -> f64 {
        self.jacobian(p).determinant()
    }
    /// The unit tool axis at a model-frame point: ∇T_z / |∇T_z| (the third row of J).
    fn tool_axis(&self, p: DVec3) -> DVec3 {
        let j = self.jacobian(p);
        let g = DVec3::new(j.x_axis.z, j.y_axis.z, j.z_axis.z);
        let len = g.length();
        if len > 0.0 {
            g / len
        } else {
            DVec3::Z
        }
    }
}

/// `outward` (c = +1) or `inward` (c = −1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// c = +1: z' = z + g with g ≥ 0 growing away from the centre; layers fall outward.
    #[default]
    Outward,
    /// c = −1: layers rise away from the centre and the tool tilts inward.
    Inward,
}

impl Direction {
    /// c of seed 000: +1 outward, −1 inward.
    pub fn sign(self) -> f64 {
        match self {
            Direction::Outward => 1.0,
            Direction::Inward => -1.0,
        }
    }
}

impl std::str::FromStr for Direction {
    type Err = WarpError;
    fn from_str(s: &str) -> Result<Self, WarpError> {
        match s {
            "outward" => Ok(Direction::Outward),
            "inward" => Ok(Direction::Inward),
            _ => Err(WarpError::BadParameter {
                name: "direction",
                value: s.to_string(),
                allowed: "outward or inward".into(),
            }),
        }
    }
}

/// A warp and its parameters, as the CLI, the job file and the web app give them.
/// Lengths in mm, angles in degrees.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
#[non_exhaustive]
pub enum WarpSpec {
    /// Seed 000 Eq. 1. `width` is the model's width in x (filled in from the mesh when 0).
    Curved {
        /// s: the layers' rise factor (dimensionless, ≥ 0).
        strength: f64,
        /// c: outward (domes) or inward (bowls).
        direction: Direction,
        /// a, mm: moves the parabola's vertex to x = −a (model frame).
        offset: f64,
        /// w, mm: the model's width in x (0: taken from the model-frame bounding box).
        #[serde(default)]
        width: f64,
    },
    /// Seed 000 Eq. 2.
    Tilted {
        /// s = tan of the layer tilt (dimensionless, ≥ 0).
        strength: f64,
        /// c: outward (a ridge, layers falling away from the crease) or inward (a valley).
        direction: Direction,
        /// a, mm: moves the crease to x = −a (model frame).
        offset: f64,
    },
    /// Seed 002: conic layers about the vertical axis through `center`.
    Conic {
        /// α: the cone's slope from horizontal, degrees (0 < α < 90).
        angle: f64,
        /// c: outward (layers fall away from the axis) or inward (they rise away from it).
        direction: Direction,
        /// (x, y) of the cone's vertical axis, model frame, mm.
        center: [f64; 2],
    },
    /// Seed 002 tilted slices: planes falling toward the unit vector `toward`.
    Belt {
        /// α: the planes' slope from horizontal, degrees (0 < α < 90).
        angle: f64,
        /// Direction (dx, dy) the planes fall toward (normalised; must be non-zero).
        toward: [f64; 2],
    },
    /// Seed 002 mandrel: coaxial cylinders about the axis ∥ X through (y, z) = `axis`, the first
    /// of radius `radius` (mm).
    Cylindrical {
        /// R: radius of the first layer (the mandrel), mm.
        radius: f64,
        /// (y, z) of the cylinders' axis (parallel to X), model frame, mm.
        axis: [f64; 2],
    },
    /// Seed 002 5-axis: concentric spheres about `center`, the first of radius `radius` (mm).
    Spherical {
        /// R: radius of the first layer (the inner sphere), mm.
        radius: f64,
        /// (x, y, z) of the spheres' centre, model frame, mm.
        center: [f64; 3],
    },
    /// Issue 15: T_z = z + g(x, y) with g typed by the user ([`field`]) or fitted by
    /// `suggest` (a bicubic B-spline, [`spline`]): exactly one of the two.
    Field {
        /// g(x, y) in mm, x and y in mm in the model frame (e.g. `2*sin(x/5)`); empty with `grid`.
        #[serde(default, skip_serializing_if = "String::is_empty")]
        expr: String,
        /// The B-spline's text form (`x0,y0,dx,dy,nx,ny:c00,c10,…`, [`spline`]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        grid: Option<String>,
        /// A family warp the field is added to (g = g_family + g_field, [`over`]): how
        /// `suggest` stores a fit that starts at the best family warp.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        over: Option<String>,
    },
}

impl WarpSpec {
    /// The CLI / UI name of the warp.
    pub fn name(&self) -> &'static str {
        match self {
            WarpSpec::Curved { .. } => "curved",
            WarpSpec::Tilted { .. } => "tilted",
            WarpSpec::Conic { .. } => "conic",
            WarpSpec::Belt { .. } => "belt",
            WarpSpec::Cylindrical { .. } => "cylindrical",
            WarpSpec::Spherical { .. } => "spherical",
            WarpSpec::Field { .. } => "field",
        }
    }

    /// Fill in what depends on the model (the curved warp's width) from the model-frame bbox.
    pub fn resolve(&mut self, model_bbox: &crate::mesh::Aabb) {
        if let WarpSpec::Curved { width, .. } = self {
            if *width <= 0.0 {
                *width = model_bbox.size().x;
            }
        }
    }

    /// Check the parameters; names the bad one and its allowed range.
    pub fn validate(&self) -> Result<(), WarpError> {
        fn positive_radius(v: f64) -> Result<(), WarpError> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(WarpError::BadParameter {
                    name: "radius",
                    value: v.to_string(),
                    allowed: "a radius > 0 mm".into(),
                })
            }
        }
        fn finite(name: &'static str, v: f64) -> Result<(), WarpError> {
            if v.is_finite() {
                Ok(())
            } else {
                Err(WarpError::BadParameter {
                    name,
                    value: v.to_string(),
                    allowed: "a finite number".into(),
                })
            }
        }
        match *self {
            WarpSpec::Curved {
                strength,
                offset,
                width,
                ..
            } => {
                finite("strength", strength)?;
                finite("offset", offset)?;
                finite("width", width)?;
                if strength < 0.0 {
                    return Err(WarpError::BadParameter {
                        name: "strength",
                        value: strength.to_string(),
                        allowed: "≥ 0 (use --direction inward for concave layers)".into(),
                    });
                }
                if width / 2.0 + offset.abs() <= 0.0 {
                    return Err(WarpError::BadParameter {
                        name: "width",
                        value: width.to_string(),
                        allowed: "> 0 (a model with no extent in x cannot take the curved warp)"
                            .into(),
                    });
                }
            }
            WarpSpec::Tilted {
                strength, offset, ..
            } => {
                finite("strength", strength)?;
                finite("offset", offset)?;
                if strength < 0.0 {
                    return Err(WarpError::BadParameter {
                        name: "strength",
                        value: strength.to_string(),
                        allowed: "≥ 0 (use --direction inward for concave layers)".into(),
                    });
                }
            }
            WarpSpec::Conic { angle, center, .. } => {
                finite("center", center[0])?;
                finite("center", center[1])?;
                if !(angle > 0.0 && angle < 90.0) {
                    return Err(WarpError::BadParameter {
                        name: "angle",
                        value: angle.to_string(),
                        allowed: "0 < angle < 90 degrees".into(),
                    });
                }
            }
            WarpSpec::Belt { angle, toward } => {
                if !(angle > 0.0 && angle < 90.0) {
                    return Err(WarpError::BadParameter {
                        name: "angle",
                        value: angle.to_string(),
                        allowed: "0 < angle < 90 degrees".into(),
                    });
                }
                let l = (toward[0] * toward[0] + toward[1] * toward[1]).sqrt();
                if !(l.is_finite() && l > 0.0) {
                    return Err(WarpError::BadParameter {
                        name: "toward",
                        value: format!("{},{}", toward[0], toward[1]),
                        allowed: "a non-zero direction dx,dy".into(),
                    });
                }
            }
            WarpSpec::Cylindrical { radius, axis } => {
                finite("axis", axis[0])?;
                finite("axis", axis[1])?;
                positive_radius(radius)?;
            }
            WarpSpec::Spherical { radius, center } => {
                for c in center {
                    finite("center", c)?;
                }
                positive_radius(radius)?;
            }
            WarpSpec::Field {
                ref expr,
                ref grid,
                ref over,
            } => {
                if let Some(text) = over {
                    over::parse(text)?;
                }
                match grid {
                    None => {
                        field::Expression::parse(expr)?;
                    }
                    Some(_) if !expr.is_empty() => {
                        return Err(WarpError::BadParameter {
                            name: "grid",
                            value: "with --expr".into(),
                            allowed: "either --expr or --grid, not both".into(),
                        })
                    }
                    Some(text) => {
                        spline::Spline::parse(text)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// Whether this warp is a shear in z (has a height function g(x, y) and takes `--base`).
    pub fn is_shear(&self) -> bool {
        !matches!(
            self,
            WarpSpec::Cylindrical { .. } | WarpSpec::Spherical { .. }
        )
    }

    /// The height function g(x, y) of a shear warp (`None` for the cylindrical and spherical
    /// warps, which are not shears, and for a field whose expression does not parse:
    /// [`WarpSpec::validate`] names why).
    pub fn height(&self) -> Option<Box<dyn Height>> {
        Some(match *self {
            WarpSpec::Curved {
                strength,
                direction,
                offset,
                width,
            } => Box::new(curved::Curved::new(strength, direction, offset, width)),
            WarpSpec::Tilted {
                strength,
                direction,
                offset,
            } => Box::new(tilted::Tilted::new(strength, direction, offset)),
            WarpSpec::Conic {
                angle,
                direction,
                center,
            } => Box::new(conic::Conic::new(angle, direction, center)),
            WarpSpec::Belt { angle, toward } => Box::new(belt::Belt::new(angle, toward)),
            WarpSpec::Field {
                ref expr,
                ref grid,
                ref over,
            } => {
                let field: Box<dyn Height> = match grid {
                    Some(text) => Box::new(spline::Spline::parse(text).ok()?),
                    None => Box::new(field::Expression::parse(expr).ok()?),
                };
                match over {
                    Some(text) => Box::new(over::Sum {
                        family: over::parse(text).ok()?.height()?,
                        field,
                    }),
                    None => field,
                }
            }
            WarpSpec::Cylindrical { .. } | WarpSpec::Spherical { .. } => return None,
        })
    }

    /// The largest value of this warp's strength parameter (strength, or angle in degrees) for
    /// which a height function scaled to reach `max_negative_g` at the current value would reach
    /// `limit_g` instead. Used to name the limit in refusals.
    pub fn strength_for_limit(
        &self,
        current_max_negative_g: f64,
        limit_g: f64,
    ) -> (&'static str, f64) {
        let ratio = if current_max_negative_g > 0.0 {
            limit_g / current_max_negative_g
        } else {
            f64::INFINITY
        };
        match *self {
            WarpSpec::Curved { strength, .. } | WarpSpec::Tilted { strength, .. } => {
                ("strength", strength * ratio)
            }
            WarpSpec::Conic { angle, .. } | WarpSpec::Belt { angle, .. } => (
                "angle",
                crate::num::deg(crate::num::atan(
                    crate::num::tan(crate::num::rad(angle)) * ratio,
                )),
            ),
            // not shears: no base blend, no limit
            WarpSpec::Cylindrical { radius, .. } | WarpSpec::Spherical { radius, .. } => {
                ("radius", radius)
            }
            // g scaled by `ratio` keeps the layers from folding
            WarpSpec::Field { .. } => ("scale of the expression", ratio),
        }
    }
}

/// Why a warp cannot be built or used.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum WarpError {
    /// A parameter outside its range.
    BadParameter {
        /// The parameter's name (e.g. `strength`, `angle`, `base`).
        name: &'static str,
        /// The value given, as text.
        value: String,
        /// The allowed range (e.g. `0 < angle < 90 degrees`).
        allowed: String,
    },
    /// ∂z'/∂z ≤ 0 somewhere in the model's bounding box: layers would fold over.
    NotMonotonic {
        /// The warp's name (e.g. `belt`).
        warp: &'static str,
        /// The parameter to lower: `strength` or `angle`.
        parameter: &'static str,
        /// The parameter's largest value that keeps the layers from folding (its own unit).
        largest_allowed: f64,
        /// The `--base` blend [z0, z1], mm.
        base: [f64; 2],
        /// Model-frame (x, y) where g is most negative (where folding starts), mm.
        worst_point: [f64; 2],
    },
    /// The inverse did not converge (a point outside the warp's domain).
    InverseFailed {
        /// The slicing-frame point that could not be mapped back, mm.
        point: [f64; 3],
    },
    /// `--base` given for a warp that is not a shear in z.
    BaseNotSupported {
        /// The warp's name (`cylindrical` or `spherical`).
        warp: &'static str,
    },
    /// The field's `--expr` does not parse.
    ExpressionUnparsable {
        /// The expression as given.
        expr: String,
        /// The parser's message.
        message: String,
    },
    /// The field's `--expr` uses a name that is neither x nor y.
    ExpressionUnknownVariable {
        /// The expression as given.
        expr: String,
        /// The unknown name.
        name: String,
    },
    /// g or ∇g is not a finite number somewhere over the model's footprint.
    FieldNotFinite {
        /// The expression (or `grid`).
        expr: String,
        /// `g`, `∂g/∂x` or `∂g/∂y`.
        what: &'static str,
        /// Model-frame (x, y) where it is not finite, mm.
        at: [f64; 2],
        /// The value there.
        value: f64,
    },
    /// |∇g| beyond tan [`field::MAX_FIELD_TILT_DEG`] somewhere over the model's footprint.
    FieldTooSteep {
        /// The expression (or `grid`).
        expr: String,
        /// Model-frame (x, y) of the first such point found, mm.
        at: [f64; 2],
        /// |∇g| there (dimensionless).
        slope: f64,
        /// The largest allowed |∇g|.
        limit: f64,
    },
}

impl std::fmt::Display for WarpError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WarpError::BadParameter { name, value, allowed } => {
                write!(f, "warp parameter {name} = {value} is not allowed: {allowed}")
            }
            WarpError::NotMonotonic { warp, parameter, largest_allowed, base, worst_point } => write!(
                f,
                "the {warp} warp with --base {},{} folds the layers over near x = {:.2}, y = {:.2} (∂z'/∂z ≤ 0): \
                 the largest allowed {parameter} for this model and base is {:.3}; lower it or widen the base blend (larger z1 − z0)",
                base[0], base[1], worst_point[0], worst_point[1], largest_allowed
            ),
            WarpError::BaseNotSupported { warp } => write!(
                f,
                "the {warp} warp does not take --base (its layers are not heights over the bed); remove --base"
            ),
            WarpError::ExpressionUnparsable { expr, message } => write!(
                f,
                "--expr \"{expr}\" is not an expression of x and y: {message}; write it like 2*sin(x/5)*cos(y/7) \
                 (operators + - * / ^, functions sin cos tan exp ln sqrt abs min max …)"
            ),
            WarpError::ExpressionUnknownVariable { expr, name } => write!(
                f,
                "--expr \"{expr}\" uses {name}, but a field is g(x, y): use only x and y (mm, model frame)"
            ),
            WarpError::FieldNotFinite { expr, what, at, value } => write!(
                f,
                "the field \"{expr}\" has {what} = {value} at x = {:.2}, y = {:.2} (model frame, mm): \
                 it must be finite over the model's footprint; avoid division by zero, ln or sqrt of negatives there",
                at[0], at[1]
            ),
            WarpError::FieldTooSteep { expr, at, slope, limit } => write!(
                f,
                "the field \"{expr}\" is too steep at x = {:.2}, y = {:.2} (model frame, mm): |∇g| = {slope:.3} > {limit:.3} \
                 (layers steeper than {}°); scale the expression down",
                at[0], at[1], field::MAX_FIELD_TILT_DEG
            ),
            WarpError::InverseFailed { point } => write!(
                f,
                "cannot invert the warp at ({:.4}, {:.4}, {:.4}): the point lies outside the warped model's domain",
                point[0], point[1], point[2]
            ),
        }
    }
}

impl std::error::Error for WarpError {}

crate::error_codes!(WarpError, ERROR_CODES, "warp" {
    BadParameter => "warp.bad-parameter", "a warp parameter outside its range";
    NotMonotonic => "warp.not-monotonic", "the base blend would fold the layers over";
    InverseFailed => "warp.inverse-failed", "a point outside the warp's domain";
    BaseNotSupported => "warp.base-not-supported", "--base given for a warp that is not a shear";
    ExpressionUnparsable => "warp.expression-unparsable", "the field's --expr does not parse";
    ExpressionUnknownVariable => "warp.expression-unknown-variable", "the field's --expr uses a name other than x and y";
    FieldNotFinite => "warp.field-not-finite", "the field's g or ∇g is not finite over the model's footprint";
    FieldTooSteep => "warp.field-too-steep", "the field's |∇g| passes the steepest allowed layer";
} wraps {});

/// Everything that defines a warp: the spec and the optional flat base `[z0, z1]` (mm).
/// Unknown keys are refused (here and in the spec: a misspelt `"angel"` is an error, not the
/// default angle).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WarpParams {
    /// The warp kind and its parameters.
    pub spec: WarpSpec,
    /// Optional flat base [z0, z1], mm (model frame): flat below z0, fully warped above z1.
    #[serde(default)]
    pub base: Option<[f64; 2]>,
}

impl WarpParams {
    /// Build the warp for a model whose model-frame bounding box is `model_bbox` (resolves the
    /// spec, validates it and checks monotonicity of the base blend over the bbox).
    pub fn build(&mut self, model_bbox: &crate::mesh::Aabb) -> Result<Box<dyn Warp>, WarpError> {
        self.spec.resolve(model_bbox);
        self.spec.validate()?;
        if !self.spec.is_shear() {
            if self.base.is_some() {
                return Err(WarpError::BaseNotSupported {
                    warp: self.spec.name(),
                });
            }
            return Ok(match self.spec {
                WarpSpec::Cylindrical { radius, axis } => {
                    Box::new(cylindrical::Cylindrical::new(radius, axis))
                }
                WarpSpec::Spherical { radius, center } => {
                    Box::new(spherical::Spherical::new(radius, center))
                }
                _ => {
                    return Err(WarpError::BaseNotSupported {
                        warp: self.spec.name(),
                    })
                }
            });
        }
        let blend = match self.base {
            None => None,
            Some([z0, z1]) => {
                if !(z0.is_finite() && z1.is_finite() && z0 >= 0.0 && z1 > z0) {
                    return Err(WarpError::BadParameter {
                        name: "base",
                        value: format!("{z0},{z1}"),
                        allowed: "z0,z1 with 0 ≤ z0 < z1 (mm)".into(),
                    });
                }
                Some(BaseBlend::new(z0, z1))
            }
        };
        let Some(height) = self.spec.height() else {
            return Err(WarpError::BaseNotSupported {
                warp: self.spec.name(),
            });
        };
        if let WarpSpec::Field { expr, grid, .. } = &self.spec {
            let name = if grid.is_some() { "grid" } else { expr };
            field::check_over(height.as_ref(), model_bbox, name)?;
        }
        if let Some(b) = blend {
            // ∂z'/∂z = 1 + w'(z)·g(x,y) ≥ 1 − w'_max·max(−g): check g over the bbox.
            let (min_g, at) = height.min_over(model_bbox);
            let need = -min_g * b.max_slope();
            if need >= 1.0 {
                let limit_g = 1.0 / b.max_slope() * (1.0 - MONOTONIC_MARGIN);
                let (parameter, largest) = self.spec.strength_for_limit(-min_g, limit_g);
                return Err(WarpError::NotMonotonic {
                    warp: self.spec.name(),
                    parameter,
                    largest_allowed: largest,
                    base: [b.z0, b.z1],
                    worst_point: at,
                });
            }
        }
        Ok(height.into_shear(blend))
    }
}

/// Safety margin on ∂z'/∂z when naming the largest allowed strength: the named value keeps
/// ∂z'/∂z ≥ this fraction (a margin of 1 %, so the named value itself is accepted).
pub const MONOTONIC_MARGIN: f64 = 0.01;
