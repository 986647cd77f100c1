//! Forward kinematics of the machine kinds, written for the tests from the seeds and
//! docs/machines.md, sharing nothing with `warpslice::machine` but the machine file's
//! parameters (read as JSON: [`Fk::from_json`], or [`Fk::from_spec`] through `MachineSpec`'s
//! serde form). No crate kinematics function (forward, inverse, realised axis, head position,
//! tessellation) is called here.
//!
//! For every kind (docs/machines.md "A machine file" lists them; `presets/*.json` holds one or
//! two of each):
//! - [`Fk::forward`]: machine axis values (mm, degrees, raw: no `G92` offsets) → nozzle tip `p`
//!   and unit tool axis `n` (tip → nozzle) in the output frame, the part frame of the unwarped
//!   G-code (docs/machines.md "Conventions per machine": "The output frame is the part frame of
//!   the unwarped G-code");
//! - [`Fk::realised`]: the tool axis the machine gives when asked for `(p, n)` (what
//!   docs/machines.md says each kind drops or holds), optionally next to a previous pose;
//! - [`Fk::free`]: where the realised axis is not fixed by `(p, n)` alone (a held axis);
//! - [`Fk::out_of_reach`]: whether `(p, n)` is beyond the limits of the machine file
//!   (tilt, rotary travel, reach, rails), in closed form per kind.
//!
//! Angles in the JSON are degrees; radians inside.

use glam::{DVec2, DVec3};
use serde_json::Value;

/// Below this length (relative to |n|) a projection of the tool axis is zero: the angle it
/// would define is undefined and the machine holds the previous value (docs/machines.md: "a
/// vertical request keeps the previous azimuth", "C held", "B is held").
pub const POLE: f64 = 1e-12;
/// Slack on angle limits, degrees: a toolpath computed exactly at a limit (a 30° cone on a
/// 30° bed) is within it.
pub const LIMIT_SLACK_DEG: f64 = 1e-9;
/// Slack on a length limit (reach, rail travel), mm.
pub const LENGTH_SLACK: f64 = 1e-9;

/// Rodrigues' rotation of `v` about the unit `axis` by `angle` (right-hand rule, radians).
pub fn rotate(v: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    v * c + axis.cross(v) * s + axis * (axis.dot(v) * (1.0 - c))
}

/// Tilt of `n` from +Z, degrees.
pub fn tilt_deg(n: DVec3) -> f64 {
    n.x.hypot(n.y).atan2(n.z).to_degrees()
}

/// The 2-D vector turned 90° counter-clockwise, (−y, x) (seed 001's `(v)_{−y,x}`).
fn perp(v: DVec2) -> DVec2 {
    DVec2::new(-v.y, v.x)
}

/// Wrap radians into (−π, π].
fn wrap_pi(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let mut w = a.rem_euclid(t);
    if w > std::f64::consts::PI {
        w -= t;
    }
    w
}

/// The root of `α cos θ + β sin θ + γ = 0` of smallest |θ| (seed 001 Eqs. 9–11 and 19 pick
/// the root of least rotation; solved here as cos(θ − atan2(β, α)) = −γ/√(α² + β²)).
fn least_root(alpha: f64, beta: f64, gamma: f64) -> Option<f64> {
    let r = alpha.hypot(beta);
    if r == 0.0 {
        return (gamma == 0.0).then_some(0.0);
    }
    let c = -gamma / r;
    if c.abs() > 1.0 + 1e-12 {
        return None;
    }
    let phi = beta.atan2(alpha);
    let d = c.clamp(-1.0, 1.0).acos();
    let (a, b) = (wrap_pi(phi + d), wrap_pi(phi - d));
    Some(if a.abs() <= b.abs() { a } else { b })
}

/// The triple-Z bed's parameters (seed 001 §3 and §4.1; the JSON's `balls_xy`, `ball_z_mm`,
/// `slot_angles_deg`, `max_tilt_deg`, `rail_travel_mm`).
#[derive(Clone, Debug)]
pub struct ThreeZ {
    /// b̂₀ in bed space (with the balls' z), mm.
    b0: DVec3,
    /// l̂ᵢ = b̂ᵢ − b̂₀ (xy; the balls share one z), i = 0, 1, 2 (l̂₀ = 0).
    l: [DVec2; 3],
    /// Rail directions dᵢ = (cos σᵢ, sin σᵢ).
    d: [DVec2; 3],
    /// Rail-plane normals nᵢ = e₃ × dᵢ (xy) (Eq. 3).
    nr: [DVec2; 3],
    /// kᵢ = −nᵢ·b̄ᵢ, b̄ᵢ = l̂ᵢ (Eq. 3).
    k: [f64; 3],
    max_tilt_deg: f64,
    /// Rail travel from the planar position (inward, outward), mm (§4.1: 69, 19).
    rails: Option<[f64; 2]>,
}

/// A bed pose of the triple-Z machine: rotation bed → world and ball 0's slide t along d₀.
#[derive(Clone, Copy, Debug)]
struct BedPose {
    /// The rotation as (its minimal tilt about a horizontal axis, then a turn ψ about e₃):
    /// `R v = R_z(ψ) R_tilt v`.
    tilt_axis: DVec3,
    tilt: f64,
    psi: f64,
    t: f64,
}

impl BedPose {
    fn apply(&self, v: DVec3) -> DVec3 {
        rotate(rotate(v, self.tilt_axis, self.tilt), DVec3::Z, self.psi)
    }
    fn apply_t(&self, v: DVec3) -> DVec3 {
        rotate(rotate(v, DVec3::Z, -self.psi), self.tilt_axis, -self.tilt)
    }
}

/// The minimal rotation taking the unit `from` to the unit `to`: (axis, angle).
fn minimal_rotation(from: DVec3, to: DVec3) -> (DVec3, f64) {
    let w = from.cross(to);
    let s = w.length();
    if s < 1e-15 {
        (DVec3::X, 0.0)
    } else {
        (w / s, s.atan2(from.dot(to)))
    }
}

impl ThreeZ {
    /// The rails: given a bed rotation `R_z(ψ)·R_tilt` known but for ψ, with `tilted(lᵢ)` =
    /// `R_tilt·l̂ᵢ` and `tilted(e₃ × lᵢ)`, solve the two rail constraints of balls 1 and 2
    /// (Eq. 3, ball 0 on its rail by t d₀: Eq. 7) for (t, ψ): the 2-D problem of Eqs. 8–9 /
    /// 20–22, written with ψ turning the tilted ball offsets.
    fn rails_solve(&self, axis: DVec3, tilt: f64) -> Option<BedPose> {
        let (d0, n1, n2) = (self.d[0], self.nr[1], self.nr[2]);
        // (R l)_xy = cos ψ·m + sin ψ·perp(m), m = (R_tilt l)_xy
        let m = |i: usize| rotate(self.l[i].extend(0.0), axis, tilt).truncate();
        let (m1, m2) = (m(1), m(2));
        let (dn1, dn2) = (d0.dot(n1), d0.dot(n2));
        // ball i: nᵢ·(t d₀ + cos ψ mᵢ + sin ψ perp(mᵢ)) + kᵢ = 0, i = 1, 2; t eliminated
        let alpha = dn1 * n2.dot(m2) - dn2 * n1.dot(m1);
        let beta = dn1 * n2.dot(perp(m2)) - dn2 * n1.dot(perp(m1));
        let gamma = dn1 * self.k[2] - dn2 * self.k[1];
        let psi = least_root(alpha, beta, gamma)?;
        if dn1.abs() < 1e-12 {
            return None;
        }
        let (s, c) = psi.sin_cos();
        let t = -(n1.dot(m1 * c + perp(m1) * s) + self.k[1]) / dn1;
        Some(BedPose {
            tilt_axis: axis,
            tilt,
            psi,
            t,
        })
    }

    /// Forward kinematics (seed 001 §3.2 and Eq. 23), solved by another route than the
    /// paper's R₂R₁: the ball heights give `(R l̂ᵢ)_z = z₀ − zᵢ` (Eqs. 1, 15, 17), i.e.
    /// `u·l̂ᵢ = z₀ − zᵢ` for `u = Rᵀe₃` (the world's up in bed space): a 2×2 linear system for
    /// u_xy, u_z > 0. R is then the minimal rotation taking u to e₃ followed by a turn ψ about
    /// e₃, which with ball 0's slide t along d₀ puts balls 1 and 2 on their rail planes
    /// (Eqs. 20–22). Finally (Eq. 23) `p̂ = Rᵀ((x − t d₀ₓ, y − t d₀ᵧ, z₀) − b̂₀) + b̂₀`.
    /// The tool axis is where the vertical nozzle points in bed space: `n̂ = u = Rᵀe₃`
    /// (not Eq. 23's `(R e₃)_{−x,−y,z}`, which equals it only when R has no turn about the
    /// vertical: up to 0.14° off at 30° of tilt on the RatRig preset).
    /// Returns (p̂, n̂, u).
    fn forward(&self, x: f64, y: f64, z: [f64; 3]) -> Result<(DVec3, DVec3, DVec3), String> {
        let (l1, l2) = (self.l[1], self.l[2]);
        let det = l1.perp_dot(l2);
        let (r1, r2) = (z[0] - z[1], z[0] - z[2]);
        let u_xy = DVec2::new(r1 * l2.y - r2 * l1.y, l1.x * r2 - l2.x * r1) / det;
        let uz2 = 1.0 - u_xy.length_squared();
        if uz2.is_nan() || uz2 <= 0.0 {
            return Err(format!(
                "three-z: the Z axes {z:?} admit no bed pose (|u_xy| = {})",
                u_xy.length()
            ));
        }
        let u = u_xy.extend(uz2.sqrt());
        let (axis, tilt) = minimal_rotation(u, DVec3::Z);
        let pose = self
            .rails_solve(axis, tilt)
            .ok_or_else(|| format!("three-z: the Z axes {z:?} put no ball on its rail"))?;
        let b0w = self.d[0] * pose.t;
        let p = pose.apply_t(DVec3::new(x - b0w.x, y - b0w.y, z[0]) - self.b0) + self.b0;
        Ok((p, u, u))
    }

    /// The bed pose realising tool axis `n`: the vertical nozzle is `n` in bed space, so
    /// `Rᵀe₃ = n` and R is the minimal rotation taking n to e₃ followed by a turn ψ about e₃,
    /// ψ and ball 0's slide from the rails ([`ThreeZ::rails_solve`]).
    fn pose_of(&self, n: DVec3) -> Option<BedPose> {
        let (axis, tilt) = minimal_rotation(n.normalize(), DVec3::Z);
        self.rails_solve(axis, tilt)
    }

    /// The machine axes (x, y, z₀, z₁, z₂) putting the tip at bed point `p` with tool axis `n`:
    /// Eq. 23 read backwards, `(x − t d₀ₓ, y − t d₀ᵧ, z₀) = R(p̂ − b̂₀) + b̂₀` and
    /// `zᵢ = z₀ − (R l̂ᵢ)_z` (Eqs. 1, 15), R of [`ThreeZ::pose_of`].
    fn axes_of(&self, p: DVec3, n: DVec3) -> Option<[f64; 5]> {
        let pose = self.pose_of(n)?;
        let r = |v: DVec3| pose.apply(v);
        let q = r(p - self.b0) + self.b0;
        let b0w = self.d[0] * pose.t;
        let z = |i: usize| q.z - r(self.l[i].extend(0.0)).z;
        Some([q.x + b0w.x, q.y + b0w.y, q.z, z(1), z(2)])
    }

    /// Whether the bed pose realising tool axis `n` ([`ThreeZ::pose_of`]) is beyond the tilt limit or slides a ball
    /// beyond its rail's travel (§4.1: from the planar position, inward towards the balls'
    /// centroid and outward).
    fn out_of_reach(&self, n: DVec3) -> Option<String> {
        let t = tilt_deg(n);
        if t > self.max_tilt_deg + LIMIT_SLACK_DEG {
            return Some(format!(
                "the bed would tilt {t:.4}°, beyond max_tilt_deg {}",
                self.max_tilt_deg
            ));
        }
        let [inward, outward] = self.rails?;
        let Some(pose) = self.pose_of(n) else {
            return Some("no bed pose puts the balls on their rails".into());
        };
        let (d0, t) = (self.d[0], pose.t);
        let world = |i: usize| pose.apply(self.l[i].extend(0.0)).truncate();
        let centroid = (self.l[0] + self.l[1] + self.l[2]) / 3.0;
        for i in 0..3 {
            let now = d0 * t + world(i);
            let into = if self.d[i].dot(centroid - self.l[i]) >= 0.0 {
                self.d[i]
            } else {
                -self.d[i]
            };
            let slide = into.dot(now - self.l[i]);
            if slide > inward + LENGTH_SLACK || -slide > outward + LENGTH_SLACK {
                return Some(format!(
                    "ball {i} would slide {slide:.3} mm inward, beyond the rail travel [-{outward}, {inward}] mm"
                ));
            }
        }
        None
    }
}

/// One machine's kinematics, from its machine file.
#[derive(Clone, Debug)]
pub enum Fk {
    /// `cartesian`: X Y Z = tip, nozzle vertical.
    Cartesian { max_tilt_deg: Option<f64> },
    /// `b-head` (FullControl's Prusa B head).
    BHead {
        r: f64,
        /// (b₀ degrees, z_clip mm) of the collision clip.
        clip: Option<(f64, f64)>,
        b_limit_deg: f64,
    },
    /// `rtn` (Slicer4RTN, RotBot).
    Rtn {
        tilt: f64,
        /// c + rot_offset (docs/machines.md: R = φ + c + rot_offset), degrees.
        offset_deg: f64,
        /// (e_parallel, e_perpendicular), mm.
        e: DVec2,
        /// `revolution: single`: the range `[lo, hi]` of R, degrees (`rotation_range_deg`,
        /// docs/machines.md: default [−170, 170], seed 002); `None`: unlimited.
        range: Option<[f64; 2]>,
    },
    /// `pax` (5-axis head).
    Pax {
        l: f64,
        /// c + rot_offset (docs/machines.md: A = φ + c + rot_offset), degrees.
        offset_deg: f64,
        max_tilt_deg: f64,
    },
    /// `ab-table` (Open5x).
    AbTable {
        a_pos: DVec3,
        a_dir: DVec3,
        b_pos: DVec3,
        b_dir: DVec3,
        part_offset: DVec3,
        z_d: f64,
        hold: f64,
        a_limit_deg: f64,
    },
    /// `three-z` (RatRig V-Core 3 triple Z).
    ThreeZ(ThreeZ),
    /// `r-theta` (polar).
    RTheta {
        l: f64,
        max_tilt_deg: f64,
        max_radius: f64,
    },
    /// `lathe-a` (mandrel about X).
    Lathe { c: DVec3, with_y: bool },
}

fn field<'a>(v: &'a Value, k: &str) -> Result<&'a Value, String> {
    v.get(k).ok_or_else(|| format!("machine JSON: no '{k}'"))
}

fn number(v: &Value, k: &str) -> Result<f64, String> {
    field(v, k)?
        .as_f64()
        .ok_or_else(|| format!("machine JSON: '{k}' is not a number"))
}

/// A number, `null` (or absent) meaning `none`.
/// docs/machines.md "rtn-slicer4rtn / rotbot": the constant c of R = φ + c + rot_offset by
/// `rot_convention`: `slicer4rtn` (the default) 180° — Slicer4RTN 0.6.0 writes atan2 of the
/// point about the cone centre + 180° + `--rot-offset` —, `rotbot` 0° — RotBot's Transform
/// scripts write U = atan2(y, x) of the point on an outward cone.
fn rotation_base_deg(v: &Value) -> Result<f64, String> {
    match v.get("rot_convention") {
        None | Some(Value::Null) => Ok(180.0),
        Some(c) => match c.as_str() {
            Some("slicer4rtn") => Ok(180.0),
            Some("rotbot") => Ok(0.0),
            _ => Err(format!("machine JSON: 'rot_convention' {c}")),
        },
    }
}

fn number_or(v: &Value, k: &str, none: f64) -> Result<f64, String> {
    match v.get(k) {
        None | Some(Value::Null) => Ok(none),
        Some(_) => number(v, k),
    }
}

fn numbers(v: &Value, k: &str) -> Result<Vec<f64>, String> {
    field(v, k)?
        .as_array()
        .ok_or_else(|| format!("machine JSON: '{k}' is not an array"))?
        .iter()
        .map(|x| {
            x.as_f64()
                .ok_or_else(|| format!("machine JSON: '{k}' holds a non-number"))
        })
        .collect()
}

fn vec3(v: &Value, k: &str) -> Result<DVec3, String> {
    match numbers(v, k)?[..] {
        [x, y, z] => Ok(DVec3::new(x, y, z)),
        _ => Err(format!("machine JSON: '{k}' is not 3 numbers")),
    }
}

impl Fk {
    /// The kinematics of a machine spec, from its JSON form (the public data of the spec,
    /// serialised: every parameter, defaults filled in).
    pub fn from_spec(spec: &warpslice::machine::MachineSpec) -> Result<Fk, String> {
        Fk::from_json(&serde_json::to_value(spec).map_err(|e| e.to_string())?)
    }

    /// The kinematics of a machine file (`presets/*.json`: every parameter present).
    pub fn from_json(v: &Value) -> Result<Fk, String> {
        let kind = field(v, "kind")?.as_str().ok_or("machine JSON: 'kind'")?;
        Ok(match kind {
            "cartesian" => Fk::Cartesian {
                max_tilt_deg: v.get("max_tilt_deg").and_then(Value::as_f64),
            },
            "b-head" => Fk::BHead {
                r: number(v, "pivot_to_tip_mm")?,
                clip: field(v, "clip")?
                    .as_bool()
                    .ok_or("machine JSON: 'clip'")?
                    .then(|| Ok::<_, String>((number(v, "clip_b0_deg")?, number(v, "clip_z_mm")?)))
                    .transpose()?,
                b_limit_deg: number(v, "b_limit_deg")?,
            },
            "rtn" => Fk::Rtn {
                tilt: number(v, "tilt_deg")?.to_radians(),
                offset_deg: rotation_base_deg(v)? + number(v, "rot_offset_deg")?,
                e: DVec2::new(
                    number(v, "e_parallel_mm")?,
                    number(v, "e_perpendicular_mm")?,
                ),
                range: match v.get("revolution").and_then(Value::as_str) {
                    Some("unlimited") => None,
                    _ => Some(match v.get("rotation_range_deg") {
                        None | Some(Value::Null) => [-170.0, 170.0],
                        Some(_) => match numbers(v, "rotation_range_deg")?[..] {
                            [lo, hi] => [lo, hi],
                            _ => {
                                return Err(
                                    "machine JSON: 'rotation_range_deg' is not 2 numbers".into()
                                )
                            }
                        },
                    }),
                },
            },
            "pax" => Fk::Pax {
                l: number(v, "pivot_to_tip_mm")?,
                offset_deg: rotation_base_deg(v)? + number(v, "rot_offset_deg")?,
                max_tilt_deg: number(v, "max_tilt_deg")?,
            },
            "ab-table" => {
                let (a_dir, b_dir) = (vec3(v, "a_dir")?.normalize(), vec3(v, "b_dir")?.normalize());
                let (a_pos, b_pos) = (vec3(v, "a_pos")?, vec3(v, "b_pos")?);
                // seed 004 §4.1.1: the origin is the point of the B line closest to the A line
                // (B_pos + s b with the joining segment ⟂ a and b)
                let r = b_pos - a_pos;
                let ab = a_dir.dot(b_dir);
                let s = (ab * r.dot(a_dir) - r.dot(b_dir)) / (1.0 - ab * ab);
                let origin = b_pos + b_dir * s;
                Fk::AbTable {
                    a_pos: a_pos - origin,
                    a_dir,
                    b_pos: b_pos - origin,
                    b_dir,
                    part_offset: vec3(v, "part_offset")?,
                    z_d: number(v, "z_wobble_mm")?,
                    hold: number(v, "pole_hold_deg")?.to_radians(),
                    a_limit_deg: number(v, "a_limit_deg")?,
                }
            }
            "three-z" => {
                let balls = field(v, "balls_xy")?
                    .as_array()
                    .ok_or("machine JSON: 'balls_xy'")?
                    .iter()
                    .map(|b| match b.as_array().map(|a| a.as_slice()) {
                        Some([x, y]) => Ok(DVec2::new(
                            x.as_f64().ok_or("balls_xy")?,
                            y.as_f64().ok_or("balls_xy")?,
                        )),
                        _ => Err("machine JSON: 'balls_xy' holds a non-pair".to_string()),
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                let slots = numbers(v, "slot_angles_deg")?;
                if balls.len() != 3 || slots.len() != 3 {
                    return Err("machine JSON: three balls and three slots".into());
                }
                let d: [DVec2; 3] = std::array::from_fn(|i| {
                    let s = slots[i].to_radians();
                    DVec2::new(s.cos(), s.sin())
                });
                let l: [DVec2; 3] = std::array::from_fn(|i| balls[i] - balls[0]);
                let nr = d.map(perp);
                let rails = match v.get("rail_travel_mm") {
                    None | Some(Value::Null) => None,
                    Some(_) => match numbers(v, "rail_travel_mm")?[..] {
                        [i, o] => Some([i, o]),
                        _ => return Err("machine JSON: 'rail_travel_mm' is not 2 numbers".into()),
                    },
                };
                Fk::ThreeZ(ThreeZ {
                    b0: balls[0].extend(number(v, "ball_z_mm")?),
                    l,
                    d,
                    nr,
                    k: std::array::from_fn(|i| -nr[i].dot(l[i])),
                    max_tilt_deg: number(v, "max_tilt_deg")?,
                    rails,
                })
            }
            "r-theta" => Fk::RTheta {
                l: number(v, "pivot_to_tip_mm")?,
                max_tilt_deg: number(v, "max_tilt_deg")?,
                max_radius: number_or(v, "max_radius_mm", f64::INFINITY)?,
            },
            "lathe-a" => Fk::Lathe {
                c: DVec3::new(0.0, number(v, "axis_y_mm")?, number(v, "axis_z_mm")?),
                with_y: v.get("with_y").and_then(Value::as_bool).unwrap_or(false),
            },
            other => return Err(format!("machine JSON: unknown kind '{other}'")),
        })
    }

    /// Number of axes.
    pub fn axes(&self) -> usize {
        match self {
            Fk::Cartesian { .. } => 3,
            Fk::BHead { .. } | Fk::Rtn { .. } | Fk::RTheta { .. } => 4,
            Fk::Pax { .. } | Fk::AbTable { .. } | Fk::ThreeZ(_) => 5,
            Fk::Lathe { with_y, .. } => 3 + usize::from(*with_y),
        }
    }

    /// Seed 004 Eq. 5.1: the A axis' Z wobble (linear in A, ±z_d at ±90°).
    fn z_wobble(z_d: f64, a_deg: f64) -> f64 {
        z_d.max(-z_d)
            .min(z_d.min(-z_d).max(2.0 * z_d * a_deg / 180.0))
    }

    /// Forward kinematics: axes (machine order, mm and degrees) → (tip, unit tool axis) in the
    /// output frame.
    pub fn forward(&self, x: &[f64]) -> Result<(DVec3, DVec3), String> {
        if x.len() != self.axes() || x.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "{} finite axis values expected, got {x:?}",
                self.axes()
            ));
        }
        Ok(match self {
            // docs/machines.md "cartesian — X Y Z = tip."
            Fk::Cartesian { .. } => (DVec3::new(x[0], x[1], x[2]), DVec3::Z),
            // docs/machines.md "fullcontrol-prusa-b": n = (sin B, 0, cos B) (B > 0 leans the
            // nozzle body towards +X), X = p_x + r sin B, Z = p_z + r cos B − r, Y = p_y:
            // seed 000 Eqs. 5–6 (x + r cos b, z − (r − r sin b)) with the seed's b measured
            // from the horizontal, b = 90° − B.
            Fk::BHead { r, .. } => {
                let (s, c) = x[3].to_radians().sin_cos();
                (
                    DVec3::new(x[0] - r * s, x[1], x[2] - r * c + r),
                    DVec3::new(s, 0.0, c),
                )
            }
            // docs/machines.md "rtn-slicer4rtn / rotbot": fixed tilt α, rotation R = φ + c +
            // rot_offset with φ the azimuth of the tool axis and c by rot_convention (180° for
            // Slicer4RTN: seed 002 "rot-offset" −90°, 0° in front, counter-clockwise increasing,
            // ±180° with the nozzle opening looking forward; 0° for RotBot), so
            // n = (sin α cos φ, sin α sin φ, cos α) with φ = R − c − rot_offset; the RotBot
            // misalignment "turns with U": the tip is off the rotation axis by e_parallel along
            // the azimuth and e_perpendicular 90° counter-clockwise from it.
            Fk::Rtn {
                tilt,
                offset_deg,
                e,
                ..
            } => {
                let phi = (x[3] - offset_deg).to_radians();
                let (s, c) = phi.sin_cos();
                let off = DVec3::new(e.x * c - e.y * s, e.x * s + e.y * c, 0.0);
                (
                    DVec3::new(x[0], x[1], x[2]) + off,
                    DVec3::new(tilt.sin() * c, tilt.sin() * s, tilt.cos()),
                )
            }
            // docs/machines.md "pax-5axis": n = (sin B cos φ, sin B sin φ, cos B),
            // φ = A − c − rot_offset (c by rot_convention, as the rtn); pivot-to-tip L with the
            // machine position the tip at B = 0 (as the B head): pivot = p + L n = (X, Y, Z) + L e_z.
            Fk::Pax { l, offset_deg, .. } => {
                let phi = (x[3] - offset_deg).to_radians();
                let b = x[4].to_radians();
                let n = DVec3::new(b.sin() * phi.cos(), b.sin() * phi.sin(), b.cos());
                (DVec3::new(x[0], x[1], x[2]) + DVec3::Z * *l - n * *l, n)
            }
            // docs/machines.md "open5x-ab" and seed 004 §4.1: the nozzle is vertical; A turns
            // the table about the line (A_pos, A_dir), B the bed about (B_pos, B_dir) carried
            // by A, right-hand, so a part point p is at q = T_A(A) T_B(B) (p + part_offset)
            // (T_L(θ) x = L_pos + R(L_dir, θ)(x − L_pos)) and X Y Z = q plus the Z wobble of
            // Eq. 5.1 on Z. Inverted: p = T_B(−B) T_A(−A) q − part_offset,
            // n = R(B_dir, −B) R(A_dir, −A) e_z.
            Fk::AbTable {
                a_pos,
                a_dir,
                b_pos,
                b_dir,
                part_offset,
                z_d,
                ..
            } => {
                let (a, b) = (x[3].to_radians(), x[4].to_radians());
                let q = DVec3::new(x[0], x[1], x[2] - Fk::z_wobble(*z_d, x[3]));
                let y = *a_pos + rotate(q - *a_pos, *a_dir, -a);
                let p = *b_pos + rotate(y - *b_pos, *b_dir, -b) - *part_offset;
                (p, rotate(rotate(DVec3::Z, *a_dir, -a), *b_dir, -b))
            }
            // seed 001 §3.2, Eq. 23 (see ThreeZ::forward).
            Fk::ThreeZ(t) => {
                let (p, n, _) = t.forward(x[0], x[1], [x[2], x[3], x[4]])?;
                (p, n)
            }
            // docs/machines.md "core-r-theta": the bed turns by C (right-hand) about the
            // vertical through the origin, so the tip in the machine frame is q = R_z(C) p; the
            // head is on the machine's x axis (X = r) and tilts by B in its XZ plane with
            // pivot-to-tip L as the B head: q = (X − L sin B, 0, Z − L cos B + L), tool axis
            // (sin B, 0, cos B) in the machine frame. Output: p = R_z(−C) q, n = R_z(−C)(…).
            Fk::RTheta { l, .. } => {
                let (s, c) = x[3].to_radians().sin_cos();
                let cc = -x[1].to_radians();
                let q = DVec3::new(x[0] - l * s, 0.0, x[2] - l * c + l);
                (
                    rotate(q, DVec3::Z, cc),
                    rotate(DVec3::new(s, 0.0, c), DVec3::Z, cc),
                )
            }
            // docs/machines.md "lathe-a": the mandrel is the line y = axis_y, z = axis_z along
            // X; A turns the part (right-hand about +X) so q = c + R_x(A)(p − c) is the tip in
            // the machine frame, the nozzle vertical (X Z A: q = (X, axis_y, Z)). Inverted:
            // p = c + R_x(−A)(q − c), n = R_x(−A) e_z = (0, sin A, cos A).
            Fk::Lathe { c, with_y } => {
                let (q, a) = if *with_y {
                    (DVec3::new(x[0], x[1], x[2]), x[3])
                } else {
                    (DVec3::new(x[0], c.y, x[1]), x[2])
                };
                let a = a.to_radians();
                (
                    *c + rotate(q - *c, DVec3::X, -a),
                    DVec3::new(0.0, a.sin(), a.cos()),
                )
            }
        })
    }

    /// Whether the realised tool axis at `(p, n)` is not fixed by `(p, n)` alone: the machine
    /// holds an axis from the previous pose (docs/machines.md: the B head with no XZ part,
    /// "a vertical request keeps the previous azimuth" of the RTN, the A/B table "near the pole
    /// (tool within 0.5° of the B axis) B is held", "the centre is singular (C held)" of the
    /// polar machine and a tool axis along its tangent, the mandrel with the tip on its axis and
    /// n ∥ X).
    pub fn free(&self, p: DVec3, n: DVec3) -> bool {
        let n = n.normalize();
        match self {
            Fk::Cartesian { .. } | Fk::Pax { .. } | Fk::ThreeZ(_) => false,
            Fk::BHead { .. } => n.x.hypot(n.z) < POLE,
            // or, with one revolution, a rotation midway in the shadow (hi, lo + 360°): the
            // previous R picks the end
            Fk::Rtn {
                offset_deg, range, ..
            } => {
                n.x.hypot(n.y) < POLE
                    || range.is_some_and(|[lo, hi]| {
                        let k = (offset_deg + n.y.atan2(n.x).to_degrees() - lo).rem_euclid(360.0);
                        let mid = (hi - lo + 360.0) / 2.0;
                        k > hi - lo && (k - mid).abs() <= 1e-9
                    })
            }
            Fk::AbTable { b_dir, hold, .. } => n.cross(*b_dir).length() < hold.sin(),
            Fk::RTheta { .. } => {
                let rho = p.x.hypot(p.y);
                rho < POLE || {
                    let r = DVec3::new(p.x / rho, p.y / rho, 0.0);
                    n.dot(r).hypot(n.z) < POLE
                }
            }
            Fk::Lathe { c, with_y } => {
                let v = p - *c;
                n.y.hypot(n.z) < POLE && (*with_y || v.y.hypot(v.z) < POLE)
            }
        }
    }

    /// The tool axis the machine realises when asked for `n` at `p` (`prev`: the axes of the
    /// previous pose, for what the machine holds).
    pub fn realised(&self, p: DVec3, n: DVec3, prev: Option<&[f64]>) -> DVec3 {
        let n = n.normalize();
        let prev_axis = |i: usize| prev.and_then(|a| a.get(i).copied());
        match self {
            Fk::Cartesian { .. } => DVec3::Z,
            // docs/machines.md: "The Y component of the requested axis is dropped", then the
            // collision clip |B| ≤ b₀ + (90° − b₀)·min(z/z_clip, 1) of seed 000 §4.3.1 at the
            // tip height.
            Fk::BHead { clip, .. } => {
                let mut b = if n.x.hypot(n.z) < POLE {
                    prev_axis(3).unwrap_or(0.0)
                } else {
                    n.x.atan2(n.z).to_degrees()
                };
                if let Some((b0, zc)) = clip {
                    let lim = b0 + (90.0 - b0) * (p.z / zc).min(1.0);
                    b = b.min(lim).max(-lim);
                }
                let (s, c) = b.to_radians().sin_cos();
                DVec3::new(s, 0.0, c)
            }
            // docs/machines.md: "Only the azimuth of a requested axis is realised (a vertical
            // request keeps the previous azimuth)".
            // With one revolution R stays in [lo, hi]: a rotation in the shadow between hi and
            // lo + 360° stops at the nearer end (the firmware's clamp to its M208 limits), at
            // equal distance the end nearer the previous R (lo without one).
            Fk::Rtn {
                tilt,
                offset_deg,
                range,
                ..
            } => {
                let phi = if n.x.hypot(n.y) < POLE {
                    prev_axis(3).map_or(0.0, |r| (r - offset_deg).to_radians())
                } else {
                    let az = n.y.atan2(n.x);
                    match range {
                        Some([lo, hi]) => {
                            let r = *offset_deg + az.to_degrees();
                            // r modulo 360° measured from lo
                            let k = (r - lo).rem_euclid(360.0);
                            let r = if k <= hi - lo + LIMIT_SLACK_DEG {
                                lo + k
                            } else {
                                let (to_hi, to_lo) = (lo + k - hi, lo + 360.0 - (lo + k));
                                if (to_hi - to_lo).abs() > LIMIT_SLACK_DEG {
                                    if to_hi < to_lo {
                                        *hi
                                    } else {
                                        *lo
                                    }
                                } else {
                                    match prev_axis(3) {
                                        Some(pr) if (pr - hi).abs() < (pr - lo).abs() => *hi,
                                        _ => *lo,
                                    }
                                }
                            };
                            (r - offset_deg).to_radians()
                        }
                        None => az,
                    }
                };
                DVec3::new(tilt.sin() * phi.cos(), tilt.sin() * phi.sin(), tilt.cos())
            }
            Fk::Pax { .. } | Fk::ThreeZ(_) => n,
            // docs/machines.md: B held near the pole (with a previous pose); A then brings the
            // tool axis as near vertical as it goes: maximise (R_A(A) m)_z, m = R_B(B) n,
            // A = atan2((a × m⊥)_z, (m⊥)_z) (m⊥: m's part perpendicular to a).
            Fk::AbTable {
                a_dir, b_dir, hold, ..
            } => match prev_axis(4) {
                Some(b) if n.cross(*b_dir).length() < hold.sin() => {
                    let b = b.to_radians();
                    let m = rotate(n, *b_dir, b);
                    let mp = m - *a_dir * a_dir.dot(m);
                    let a = a_dir.cross(mp).z.atan2(mp.z);
                    rotate(rotate(DVec3::Z, *a_dir, -a), *b_dir, -b)
                }
                _ => n,
            },
            // docs/machines.md "core-r-theta": the head tilts in its XZ plane, i.e. the plane
            // of the radius through the tip and the vertical: n's tangential part is dropped
            // (at the centre the radius is that of the previous C).
            Fk::RTheta { .. } => {
                let rho = p.x.hypot(p.y);
                let r = if rho >= POLE {
                    DVec3::new(p.x / rho, p.y / rho, 0.0)
                } else {
                    let c = -prev_axis(1).unwrap_or(0.0).to_radians();
                    DVec3::new(c.cos(), c.sin(), 0.0)
                };
                let m = r * n.dot(r) + DVec3::Z * n.z;
                if m.length() < POLE {
                    let b = prev_axis(3).unwrap_or(0.0).to_radians();
                    r * b.sin() + DVec3::Z * b.cos()
                } else {
                    m.normalize()
                }
            }
            // docs/machines.md "lathe-a": "the realised tool axis is radial" (X Z A: from the
            // mandrel axis to the tip; on the axis, or with a Y axis, n's YZ part).
            Fk::Lathe { c, with_y } => {
                let v = p - *c;
                let radial = DVec3::new(0.0, v.y, v.z);
                let yz = DVec3::new(0.0, n.y, n.z);
                if !*with_y && radial.length() >= POLE {
                    radial.normalize()
                } else if yz.length() >= POLE {
                    yz.normalize()
                } else {
                    let a = prev_axis(self.axes() - 1).unwrap_or(0.0).to_radians();
                    DVec3::new(0.0, a.sin(), a.cos())
                }
            }
        }
    }

    /// Why `(p, n)` is beyond the machine file's limits, or `None` when it is within them:
    /// `cartesian` `max_tilt_deg`; `b-head` |B| (after the clip) beyond `b_limit_deg`; `rtn`
    /// none (the rotation wraps); `pax` tilt beyond `max_tilt_deg`; `ab-table` the A that makes
    /// n vertical beyond `a_limit_deg` (every branch); `three-z` tilt beyond `max_tilt_deg` or
    /// a ball beyond `rail_travel_mm`; `r-theta` |B| beyond `max_tilt_deg` or |X| =
    /// |r + L sin B| beyond `max_radius_mm`; `lathe-a` none.
    pub fn out_of_reach(&self, p: DVec3, n: DVec3) -> Option<String> {
        let n = n.normalize();
        let t = tilt_deg(n);
        match self {
            Fk::Cartesian {
                max_tilt_deg: Some(m),
            } if t > m + LIMIT_SLACK_DEG => Some(format!("tilt {t:.4}° beyond max_tilt_deg {m}")),
            Fk::Cartesian { .. } | Fk::Rtn { .. } | Fk::Lathe { .. } => None,
            Fk::BHead { b_limit_deg, .. } => {
                let r = self.realised(p, n, None);
                let b = r.x.atan2(r.z).to_degrees();
                (b.abs() > b_limit_deg + LIMIT_SLACK_DEG)
                    .then(|| format!("B = {b:.4}° beyond b_limit_deg {b_limit_deg}"))
            }
            Fk::Pax { max_tilt_deg, .. } => (t > max_tilt_deg + LIMIT_SLACK_DEG)
                .then(|| format!("tilt {t:.4}° beyond max_tilt_deg {max_tilt_deg}")),
            Fk::AbTable {
                a_dir,
                b_dir,
                a_limit_deg,
                ..
            } => {
                // no exact pose: the machine takes the nearest one
                let [v1, v2] = ab_table_branches(*a_dir, *b_dir, n)?;
                let a_of = |v: DVec3| turn_about(*a_dir, v, DVec3::Z).to_degrees();
                let a = a_of(v1).abs().min(a_of(v2).abs());
                (a > a_limit_deg + LIMIT_SLACK_DEG)
                    .then(|| format!("A = {a:.4}° beyond a_limit_deg {a_limit_deg}"))
            }
            Fk::ThreeZ(tz) => tz.out_of_reach(n),
            Fk::RTheta {
                l,
                max_tilt_deg,
                max_radius,
            } => {
                let rho = p.x.hypot(p.y);
                if rho < POLE {
                    return (t > max_tilt_deg + LIMIT_SLACK_DEG)
                        .then(|| format!("tilt {t:.4}° beyond max_tilt_deg {max_tilt_deg}"));
                }
                let r = DVec3::new(p.x / rho, p.y / rho, 0.0);
                let b = n.dot(r).atan2(n.z);
                let x = rho + l * b.sin();
                if b.to_degrees().abs() > max_tilt_deg + LIMIT_SLACK_DEG {
                    Some(format!(
                        "B = {:.4}° beyond max_tilt_deg {max_tilt_deg}",
                        b.to_degrees()
                    ))
                } else if x.abs() > max_radius + LENGTH_SLACK {
                    Some(format!(
                        "|X| = {:.4} mm beyond max_radius_mm {max_radius}",
                        x.abs()
                    ))
                } else {
                    None
                }
            }
        }
    }
}

impl Fk {
    /// The linear axes that put the tip at `p` with the realised tool axis for `n` (no
    /// previous pose), as `(axis index, value)` in machine order, read backwards from the
    /// forward kinematics above (docs/machines.md per kind); `None` where the pose is not fixed
    /// by `(p, n)` alone ([`Fk::free`]) or the kind has no closed form here.
    pub fn linear_axes(&self, p: DVec3, n: DVec3) -> Option<Vec<(usize, f64)>> {
        let n = n.normalize();
        if self.free(p, n) {
            return None;
        }
        let r = self.realised(p, n, None);
        let xyz = |q: DVec3| Some(vec![(0, q.x), (1, q.y), (2, q.z)]);
        match self {
            Fk::Cartesian { .. } => xyz(p),
            // X = p_x + r sin B, Y = p_y, Z = p_z + r cos B − r
            Fk::BHead { r: l, .. } => {
                let b = r.x.atan2(r.z);
                xyz(DVec3::new(p.x + l * b.sin(), p.y, p.z + l * b.cos() - l))
            }
            // (X, Y) = p_xy − R_z(φ)(e_par, e_perp), Z = p_z
            Fk::Rtn { e, .. } => {
                let (s, c) = r.y.atan2(r.x).sin_cos();
                xyz(DVec3::new(
                    p.x - (e.x * c - e.y * s),
                    p.y - (e.x * s + e.y * c),
                    p.z,
                ))
            }
            // (X, Y, Z) = p + L n − L e_z
            Fk::Pax { l, .. } => xyz(p + r * *l - DVec3::Z * *l),
            // v = R_A(−A) e_z with v·a = e_z·a, v·b = n·b (the |A| smallest branch, as
            // out_of_reach), B turns n into v about b; then q = T_A(A) T_B(B)(p + offset) and
            // Z gets the wobble back.
            Fk::AbTable {
                a_pos,
                a_dir,
                b_pos,
                b_dir,
                part_offset,
                z_d,
                ..
            } => {
                let [v1, v2] = ab_table_branches(*a_dir, *b_dir, r)?;
                // A: the turn about a taking v to e_z; of the two branches the larger A (the
                // A/B table's choice without a previous pose, src/machine/abtable.rs's
                // documentation)
                let (a1, a2) = (
                    turn_about(*a_dir, v1, DVec3::Z),
                    turn_about(*a_dir, v2, DVec3::Z),
                );
                let (v, a) = if a1 >= a2 { (v1, a1) } else { (v2, a2) };
                let b = turn_about(*b_dir, r, v);
                let y = *b_pos + rotate(p + *part_offset - *b_pos, *b_dir, b);
                let q = *a_pos + rotate(y - *a_pos, *a_dir, a);
                xyz(q + DVec3::Z * Fk::z_wobble(*z_d, a.to_degrees()))
            }
            Fk::ThreeZ(t) => {
                let x = t.axes_of(p, n)?;
                Some(x.iter().copied().enumerate().collect())
            }
            // X = ρ + L sin B, Z = p_z + L cos B − L (B the tilt in the radial plane)
            Fk::RTheta { l, .. } => {
                let rho = p.x.hypot(p.y);
                let radial = DVec3::new(p.x / rho, p.y / rho, 0.0);
                let b = r.dot(radial).atan2(r.z);
                Some(vec![(0, rho + l * b.sin()), (2, p.z + l * b.cos() - l)])
            }
            // q = c + R_x(A)(p − c) with n = (0, sin A, cos A)
            Fk::Lathe { c, with_y } => {
                let a = r.y.atan2(r.z);
                let q = *c + rotate(p - *c, DVec3::X, a);
                Some(if *with_y {
                    vec![(0, q.x), (1, q.y), (2, q.z)]
                } else {
                    vec![(0, q.x), (1, q.z)]
                })
            }
        }
    }
}

/// A machine file's kinematics ([`Fk`]) with the travel of its linear axes (the JSON's
/// `travel`, by the letters of `axis_names`; docs/machines.md: an axis not listed is
/// unlimited).
#[derive(Clone, Debug)]
pub struct Limits {
    /// The kinematics.
    pub fk: Fk,
    /// Per axis (machine order): its letter and `[min, max]` when limited.
    travel: Vec<(String, Option<[f64; 2]>)>,
}

impl Limits {
    /// From a machine file's JSON (every parameter present, `axis_names` included).
    pub fn from_json(v: &Value) -> Result<Limits, String> {
        let fk = Fk::from_json(v)?;
        let names: Vec<String> = field(v, "axis_names")?
            .as_array()
            .ok_or("machine JSON: 'axis_names'")?
            .iter()
            .map(|s| s.as_str().map(str::to_string).ok_or("axis_names"))
            .collect::<Result<_, _>>()?;
        let travel = names
            .into_iter()
            .map(|name| {
                let t = match v.get("travel").and_then(|t| t.get(&name)) {
                    None | Some(Value::Null) => None,
                    Some(pair) => match pair.as_array().map(|a| a.as_slice()) {
                        Some([lo, hi]) => {
                            Some([lo.as_f64().ok_or("travel")?, hi.as_f64().ok_or("travel")?])
                        }
                        _ => return Err(format!("machine JSON: travel of {name}")),
                    },
                };
                Ok((name, t))
            })
            .collect::<Result<_, String>>()?;
        Ok(Limits { fk, travel })
    }

    /// From a spec, through its JSON form.
    pub fn from_spec(spec: &warpslice::machine::MachineSpec) -> Result<Limits, String> {
        let mut v = serde_json::to_value(spec).map_err(|e| e.to_string())?;
        if v.get("axis_names").is_none_or(Value::is_null) {
            let names = spec.axis_names().map_err(|e| e.to_string())?;
            v["axis_names"] = serde_json::json!(names);
        }
        Limits::from_json(&v)
    }

    /// Why `(p, n)` is beyond the machine file's limits: [`Fk::out_of_reach`] (tilt, rotary
    /// range, rails, radius), or a linear axis of [`Fk::linear_axes`] outside its travel.
    pub fn out_of_reach(&self, p: DVec3, n: DVec3) -> Option<String> {
        self.fk.out_of_reach(p, n).or_else(|| {
            self.fk.linear_axes(p, n)?.into_iter().find_map(|(i, x)| {
                let (name, t) = &self.travel[i];
                let [lo, hi] = (*t)?;
                (x < lo - LENGTH_SLACK || x > hi + LENGTH_SLACK)
                    .then(|| format!("axis {name} = {x:.4} outside its travel [{lo}, {hi}]"))
            })
        })
    }
}

/// The A/B table's two tool-axis branches for the part-frame axis `n`: the vectors v with
/// R_B(B) n = v = R_A(−A) e_z, i.e. v·b = n·b, v·a = e_z·a, |v| = 1 (v = base ± z (a × b));
/// `None` when no exact pose exists.
fn ab_table_branches(a_dir: DVec3, b_dir: DVec3, n: DVec3) -> Option<[DVec3; 2]> {
    let (ca, cb, ab) = (a_dir.z, n.dot(b_dir), a_dir.dot(b_dir));
    let det = 1.0 - ab * ab;
    let base = a_dir * ((ca - ab * cb) / det) + b_dir * ((cb - ab * ca) / det);
    let w = a_dir.cross(b_dir);
    let z2 = (1.0 - base.length_squared()) / w.length_squared();
    if z2 < -1e-12 {
        return None;
    }
    let z = z2.max(0.0).sqrt();
    Some([base + w * z, base - w * z])
}

/// The signed angle (radians) of the turn about the unit `axis` taking `from` to `to`, both
/// projected on the plane normal to the axis.
fn turn_about(axis: DVec3, from: DVec3, to: DVec3) -> f64 {
    let f = from - axis * axis.dot(from);
    let t = to - axis * axis.dot(to);
    axis.dot(f.cross(t)).atan2(f.dot(t))
}
