//! What calibration errors do (seed 004 Fig. 3.1, Fig. 6.12, Fig. 6.16): the G-code is made by
//! the machine we **believe** in, the table moves as the **true** machine does.
//!
//! For each tool pose (tip p, tool axis n, part frame): `axes = believed.inverse(p, n, prev)`,
//! `(p_real, n_real) = true.forward(axes)`; the error is `|p_real − p|` (mm) and
//! `∠(n_real, n)` (degrees). Both machines must describe the same printer frame:
//!
//! ## Frames of two A/B tables
//! An `ab-table` spec gives its lines in some frame F; [`crate::machine::abtable::AbTable`]
//! moves its origin to the closest approach of its lines (B'', Eq. 5.7), so its axis values are
//! `X Y Z = F − B''`. The G-code frame is the believed machine's; the part sits where the
//! believed machine put it (it printed the base object). So the true machine is built with
//! `part_offset_true = part_offset_believed + B''_believed − B''_true`, and G-code XYZ `g` is
//! `g + B''_believed − B''_true` in the true machine's axes. Other kinds need no shift.
//!
//! ## Fig. 3.1 check
//! A believed along +X, truly turned 2° about Z, both through the origin; the point (0, 20, 0)
//! turned 90° about A (n = +Y ⇒ A = 90°, B = 0): believed (0, 0, 20), true
//! `20·(sin 2° cos 2°, sin² 2°, cos 2°)`; they are 0.698 mm apart (the figure's own geometry
//! shows about 1 mm).

use glam::DVec3;

use super::origin::closest_approach;
use super::svg::{self, Curve, Panel};
use super::{finite, CalibError};
use crate::machine::angles::rotate;
use crate::machine::spec::Kinematics;
use crate::machine::{Machine, MachineSpec};
use crate::num;

/// One tool pose of a toolpath (part frame): tip and tool axis.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Pose {
    /// Nozzle tip (part frame), mm.
    pub p: DVec3,
    /// Tool axis: unit vector from the tip into the nozzle (part frame).
    pub n: DVec3,
}

/// How the true machine differs from the believed one (an `ab-table`); lines in the spec's
/// frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Deviation {
    /// Added to the A line's point, mm.
    pub a_offset: DVec3,
    /// The A direction turned about +Z, degrees (Fig. 3.1: 2°).
    pub a_rot_z_deg: f64,
    /// The A direction turned about +Y, degrees.
    pub a_rot_y_deg: f64,
    /// Added to the B line's point, mm (Fig. 6.16: (0, −0.2, 0)).
    pub b_offset: DVec3,
    /// The B direction turned about +X, degrees.
    pub b_rot_x_deg: f64,
    /// The B direction turned about +Y, degrees.
    pub b_rot_y_deg: f64,
    /// Added to the wobble amplitude z_d, mm.
    pub z_wobble_mm: f64,
}

/// The true machine: `believed` (an `ab-table` spec) with `dev` applied.
pub fn deviate(believed: &MachineSpec, dev: &Deviation) -> Result<MachineSpec, CalibError> {
    let v = [
        dev.a_offset.to_array(),
        dev.b_offset.to_array(),
        [dev.a_rot_z_deg, dev.a_rot_y_deg, dev.b_rot_x_deg],
        [dev.b_rot_y_deg, dev.z_wobble_mm, 0.0],
    ]
    .concat();
    finite("deviation", &v)?;
    let mut t = believed.clone();
    match &mut t.kinematics {
        Kinematics::AbTable(p) => {
            p.a_pos += dev.a_offset;
            p.a_dir = rotate(
                rotate(p.a_dir, DVec3::Z, num::rad(dev.a_rot_z_deg)),
                DVec3::Y,
                num::rad(dev.a_rot_y_deg),
            );
            p.b_pos += dev.b_offset;
            p.b_dir = rotate(
                rotate(p.b_dir, DVec3::X, num::rad(dev.b_rot_x_deg)),
                DVec3::Y,
                num::rad(dev.b_rot_y_deg),
            );
            p.z_wobble_mm += dev.z_wobble_mm;
        }
        _ => return Err(not_ab(believed)),
    }
    t.name = format!("{} (true)", believed.name);
    Ok(t)
}

fn not_ab(m: &MachineSpec) -> CalibError {
    CalibError::BadInput {
        what: format!("machine {}", m.name),
        message: "is not an A/B table (kind 'ab-table')".to_string(),
    }
}

/// B'' of an `ab-table` spec (its origin in the spec's frame); zero for other kinds.
pub fn spec_origin(spec: &MachineSpec) -> Result<DVec3, CalibError> {
    match &spec.kinematics {
        Kinematics::AbTable(p) => {
            let (a, b) = (p.a_dir.normalize_or_zero(), p.b_dir.normalize_or_zero());
            let (_, t2) = closest_approach(p.a_pos, a, p.b_pos, b)?;
            Ok(p.b_pos + b * t2)
        }
        _ => Ok(DVec3::ZERO),
    }
}

/// A believed and a true machine sharing the believed machine's G-code frame.
#[derive(Debug)]
pub struct Pair {
    /// The machine the G-code is made for (its inverse kinematics write the axes).
    pub believed: Box<dyn Machine>,
    /// The machine as it really moves (its forward kinematics place the tip).
    pub truth: Box<dyn Machine>,
    /// Added to the believed G-code XYZ to get the true machine's XYZ, mm.
    pub shift: DVec3,
}

impl Pair {
    /// Build both (see the module doc for the frames).
    pub fn new(believed: &MachineSpec, truth: &MachineSpec) -> Result<Pair, CalibError> {
        let ob = spec_origin(believed)?;
        let ot = spec_origin(truth)?;
        let mut t = truth.clone();
        if let (Kinematics::AbTable(pb), Kinematics::AbTable(pt)) =
            (&believed.kinematics, &mut t.kinematics)
        {
            pt.part_offset = pb.part_offset + ob - ot;
        }
        let b = believed.build()?;
        let tr = t.build()?;
        if b.limits().len() != tr.limits().len() {
            return Err(CalibError::BadInput {
                what: "true machine".to_string(),
                message: format!(
                    "has {} axes, the believed machine {}",
                    tr.limits().len(),
                    b.limits().len()
                ),
            });
        }
        Ok(Pair {
            believed: b,
            truth: tr,
            shift: ob - ot,
        })
    }

    /// Where the true machine puts the tip for the believed machine's axes:
    /// `(p_real, n_real)`.
    pub fn land(&self, axes: &[f64]) -> Result<(DVec3, DVec3), CalibError> {
        let mut a = axes.to_vec();
        for k in 0..3.min(a.len()) {
            a[k] += self.shift[k];
        }
        Ok(self.truth.forward(&a)?)
    }
}

/// One simulated point.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Landed {
    /// Intended tip, mm.
    pub p: DVec3,
    /// Where it really lands, mm.
    pub real: DVec3,
    /// |real − p|, mm.
    pub error_mm: f64,
    /// Angle between the real and the intended tool axis, degrees.
    pub axis_error_deg: f64,
}

/// The simulation's result.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimReport {
    /// Every simulated point, in toolpath order.
    pub points: Vec<Landed>,
    /// Largest tip error |real − p| over the points, mm.
    pub max_error_mm: f64,
    /// Mean tip error over the points (0 when there are none), mm.
    pub mean_error_mm: f64,
    /// Largest angle between the real and the intended tool axis, degrees.
    pub max_axis_error_deg: f64,
}

impl SimReport {
    fn of(points: Vec<Landed>) -> SimReport {
        let n = points.len().max(1) as f64;
        SimReport {
            max_error_mm: points.iter().map(|l| l.error_mm).fold(0.0, f64::max),
            mean_error_mm: points.iter().map(|l| l.error_mm).sum::<f64>() / n,
            max_axis_error_deg: points.iter().map(|l| l.axis_error_deg).fold(0.0, f64::max),
            points,
        }
    }

    /// The human-readable summary and one line per point.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "points: {}, tip error max {:.4} mm, mean {:.4} mm; tool axis error max {:.4}°\n",
            self.points.len(),
            self.max_error_mm,
            self.mean_error_mm,
            self.max_axis_error_deg
        );
        s.push_str("x,y,z,real_x,real_y,real_z,error_mm,axis_error_deg\n");
        for l in &self.points {
            s.push_str(&format!(
                "{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}\n",
                l.p.x, l.p.y, l.p.z, l.real.x, l.real.y, l.real.z, l.error_mm, l.axis_error_deg
            ));
        }
        s
    }
}

/// Simulate a toolpath: believed inverse (each pose seeded by the previous axes), true forward.
pub fn simulate(pair: &Pair, poses: &[Pose]) -> Result<SimReport, CalibError> {
    let mut prev: Option<Vec<f64>> = None;
    let mut out = Vec::with_capacity(poses.len());
    for q in poses {
        let axes = pair.believed.inverse(q.p, q.n, prev.as_deref())?;
        let (real, nr) = pair.land(&axes)?;
        let n = q.n.normalize_or_zero();
        out.push(Landed {
            p: q.p,
            real,
            error_mm: (real - q.p).length(),
            axis_error_deg: num::deg(num::angle_between(nr, n)),
        });
        prev = Some(axes);
    }
    Ok(SimReport::of(out))
}

/// Simulate given believed axes and the tips they are meant to give.
pub fn simulate_axes(
    pair: &Pair,
    axes: &[Vec<f64>],
    tips: &[DVec3],
) -> Result<SimReport, CalibError> {
    let mut out = Vec::with_capacity(axes.len());
    for (a, &p) in axes.iter().zip(tips) {
        let (real, nr) = pair.land(a)?;
        let (_, nb) = pair.believed.forward(a)?;
        out.push(Landed {
            p,
            real,
            error_mm: (real - p).length(),
            axis_error_deg: num::deg(num::angle_between(nr, nb)),
        });
    }
    Ok(SimReport::of(out))
}

/// The plane a path is best seen in: drop the coordinate with the least extent. Returns the two
/// kept indices.
fn view(points: &[DVec3]) -> [usize; 2] {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in points {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let e = hi - lo;
    if e.x <= e.y && e.x <= e.z {
        [1, 2]
    } else if e.y <= e.z {
        [0, 2]
    } else {
        [0, 1]
    }
}

/// SVG: left the intended (green) and real (red) path with the error exaggerated `exaggerate`
/// times (Fig. 6.12, 6.16), in the plane where both paths spread most (the coordinate with the
/// least extent is dropped); right the tip error along the path.
pub fn svg(report: &SimReport, title: &str, exaggerate: f64) -> String {
    let ps: Vec<DVec3> = report.points.iter().map(|l| l.p).collect();
    let k = if exaggerate.is_finite() && exaggerate > 0.0 {
        exaggerate
    } else {
        1.0
    };
    let both: Vec<DVec3> = report
        .points
        .iter()
        .flat_map(|l| [l.p, l.p + (l.real - l.p) * k])
        .collect();
    let [i, j] = view(&both);
    let names = ["X", "Y", "Z"];
    let intended: Vec<[f64; 2]> = ps.iter().map(|p| [p[i], p[j]]).collect();
    let real: Vec<[f64; 2]> = report
        .points
        .iter()
        .map(|l| {
            let q = l.p + (l.real - l.p) * k;
            [q[i], q[j]]
        })
        .collect();
    let mut s = 0.0;
    let mut err = Vec::with_capacity(ps.len());
    for (m, l) in report.points.iter().enumerate() {
        if m > 0 {
            s += (l.p - report.points[m - 1].p).length();
        }
        err.push([s, l.error_mm]);
    }
    svg::render(&[
        Panel {
            title: format!("{title}: path (error ×{k})"),
            x_label: format!("{} (mm)", names[i]),
            y_label: format!("{} (mm)", names[j]),
            curves: vec![
                Curve {
                    points: intended,
                    color: "green".into(),
                    label: "intended".into(),
                },
                Curve {
                    points: real,
                    color: "red".into(),
                    label: "real".into(),
                },
            ],
            equal: true,
        },
        Panel {
            title: format!(
                "tip error (max {:.3} mm, mean {:.3} mm)",
                report.max_error_mm, report.mean_error_mm
            ),
            x_label: "path length (mm)".into(),
            y_label: "error (mm)".into(),
            curves: vec![Curve {
                points: err,
                color: "red".into(),
                label: "|real − intended|".into(),
            }],
            equal: false,
        },
    ])
}

/// Parse a toolpath CSV: `x,y,z,nx,ny,nz` per line (mm; blank lines and lines starting with `#`
/// skipped; a first line that is not numbers is a header).
pub fn parse_poses(text: &str) -> Result<Vec<Pose>, CalibError> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let v: Result<Vec<f64>, _> = t.split(',').map(|s| s.trim().parse::<f64>()).collect();
        match v {
            Ok(v) if v.len() == 6 && v.iter().all(|x| x.is_finite()) => out.push(Pose {
                p: DVec3::new(v[0], v[1], v[2]),
                n: DVec3::new(v[3], v[4], v[5]),
            }),
            Err(_) if out.is_empty() && i == 0 => continue,
            _ => {
                return Err(CalibError::BadInput {
                    what: format!("toolpath line {}", i + 1),
                    message: format!("'{t}' is not six numbers x,y,z,nx,ny,nz"),
                })
            }
        }
    }
    Ok(out)
}

/// Fig. 3.1 as numbers: a point at `radius` on +Y turned `angle_deg` about an A axis believed
/// along +X but truly turned `a_rot_z_deg` about Z (both through the origin) → the distance
/// between where the believed and the true machine put it, mm. Goes through the machines
/// (believed inverse, true forward).
pub fn fig_3_1(radius: f64, a_rot_z_deg: f64) -> Result<f64, CalibError> {
    let believed = crate::machine::preset("open5x-ab")?;
    let truth = deviate(
        &believed,
        &Deviation {
            a_rot_z_deg,
            ..Deviation::default()
        },
    )?;
    let pair = Pair::new(&believed, &truth)?;
    let r = simulate(
        &pair,
        &[Pose {
            p: DVec3::new(0.0, radius, 0.0),
            n: DVec3::Y,
        }],
    )?;
    Ok(r.max_error_mm)
}

/// What to simulate: the poses of a toolpath (CSV text `x,y,z,nx,ny,nz`, see [`parse_poses`]),
/// or the path of one of the §6.2 test prints made by the believed machine.
#[derive(Clone, Copy, Debug)]
pub enum SimInput<'a> {
    /// A toolpath as CSV text, and its name for the figure's title.
    Toolpath {
        /// The CSV text.
        csv: &'a str,
        /// Its name (a file path).
        name: &'a str,
    },
    /// A test print (§6.2).
    TestPrint(super::patterns::TestKind),
}

/// The whole simulation as the CLI and the web page run it: the true machine is `truth`, or
/// the believed one with `deviation` ([`deviate`]); returns the report and the figure's title.
pub fn run(
    believed: &MachineSpec,
    truth: Option<&MachineSpec>,
    deviation: &Deviation,
    input: SimInput<'_>,
) -> Result<(SimReport, String), CalibError> {
    let t = match truth {
        Some(t) => t.clone(),
        None => deviate(believed, deviation)?,
    };
    let pair = Pair::new(believed, &t)?;
    match input {
        SimInput::Toolpath { csv, name } => {
            let poses = parse_poses(csv)?;
            Ok((simulate(&pair, &poses)?, name.to_string()))
        }
        SimInput::TestPrint(kind) => {
            let tp = super::patterns::test_print(
                believed,
                kind,
                &super::patterns::PrintOptions::default(),
            )?;
            let (axes, tips): (Vec<Vec<f64>>, Vec<DVec3>) = tp
                .moves
                .iter()
                .filter_map(|m| m.tip.map(|p| (m.axes.clone(), p)))
                .unzip();
            Ok((
                simulate_axes(&pair, &axes, &tips)?,
                format!("{} test", kind.name()),
            ))
        }
    }
}
