//! The machine origin (seed 004 §5.4.2, Eq. 5.7) and the calibrated machine.
//!
//! ```text
//! A'_dir = R_z(α_{A,z}) A_dir            (the thesis writes A_dir · R_z(α)ᵀ for a row vector)
//! A'_pos = A_pos + [0, −y_bias, z_bias]   (A is an inner diameter: y_bias acts the other way)
//! B'_pos = B_pos + [x_bias, y_bias, z_bias]
//! n  = A'_dir × B_dir
//! t₁ = ((B_dir × n) · (B'_pos − A'_pos)) / (n · n)
//! t₂ = ((A'_dir × n) · (B'_pos − A'_pos)) / (n · n)
//! A''_pos = A'_pos + t₁ A'_dir,   B''_pos = B'_pos + t₂ B_dir
//! A^B_pos = A''_pos − B''_pos
//! θ = asin((A'_dir).y)                    (the A axis' rotation in the Z plane)
//! ```
//! `R_z(α) = [[cos α, −sin α, 0], [sin α, cos α, 0], [0, 0, 1]]` (right hand, +α turns +X toward
//! +Y). A''_pos and B''_pos are the closest points of the two lines; B''_pos is the new origin in
//! the current frame (the shift of the printer's G55 frame) and A^B_pos the A line's point in
//! the new frame. Directions are normalised first (the file rounds them to 7 digits; A'' and
//! B'' do not depend on the directions' lengths, θ does). (Nearly) parallel lines
//! (|A'_dir × B_dir| < [`super::PARALLEL_SINE`]) are refused.
//!
//! ## Repeated series (Table 6.2)
//! Per component: mean ± standard deviation (population, as numpy's default) and the max
//! difference (max − min) over the series. The calibrated machine uses the mean series
//! (positions averaged, directions averaged and normalised).
//!
//! ## The calibrated machine
//! The base machine (an `ab-table` spec, e.g. the `open5x-ab` preset) with
//! `a_pos = A^B_pos`, `a_dir = A'_dir`, `b_pos = 0`, `b_dir = B_dir`: the lines in the new
//! frame, whose origin is B''_pos. Everything else (axis letters, part offset, wobble z_d,
//! limits) is kept from the base.

use glam::DVec3;

use super::{finite, CalibError, Series, PARALLEL_SINE};
use crate::machine::spec::Kinematics;
use crate::machine::MachineSpec;
use crate::num;

/// A measured direction shorter than this is refused (it has no direction).
pub const MIN_DIRECTION_LENGTH: f64 = 1e-9;

/// Corrections applied by Eq. 5.7.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct OriginOptions {
    /// The touch probe's additive biases x_bias, y_bias, z_bias (§5.1.5, §5.1.6), mm.
    pub bias: DVec3,
    /// α_{A,z}: rotation of A_dir about Z found by the A orientation test (§6.2.2), degrees.
    pub a_z_correction_deg: f64,
}

impl Default for OriginOptions {
    fn default() -> Self {
        OriginOptions {
            bias: DVec3::ZERO,
            a_z_correction_deg: 0.0,
        }
    }
}

/// The result of Eq. 5.7 for one series.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Origin {
    /// A'_dir (unit).
    pub a_dir: DVec3,
    /// B_dir (unit).
    pub b_dir: DVec3,
    /// A'_pos, mm.
    pub a_pos: DVec3,
    /// B'_pos, mm.
    pub b_pos: DVec3,
    /// t₁: parameter of A''_pos along the unit A'_dir from A'_pos, mm.
    pub t1: f64,
    /// t₂: parameter of B''_pos along the unit B_dir from B'_pos, mm.
    pub t2: f64,
    /// A''_pos: the A line's point closest to the B line (current frame), mm.
    pub a_closest: DVec3,
    /// B''_pos: the new origin in the current frame, mm.
    pub origin: DVec3,
    /// A^B_pos = A''_pos − B''_pos, mm.
    pub a_from_b: DVec3,
    /// |A^B_pos|: the distance between the lines, mm.
    pub distance: f64,
    /// θ = asin((A'_dir).y), degrees.
    pub theta_deg: f64,
    /// The angle between A'_dir and B_dir, degrees (90 for perpendicular axes).
    pub axes_angle_deg: f64,
}

/// Closest approach of the lines `p1 + t₁ d1` and `p2 + t₂ d2` (the formulas of Eq. 5.7):
/// `(t₁, t₂)`. Errors when the lines are (nearly) parallel.
pub fn closest_approach(
    p1: DVec3,
    d1: DVec3,
    p2: DVec3,
    d2: DVec3,
) -> Result<(f64, f64), CalibError> {
    let n = d1.cross(d2);
    let sine = n.length() / (d1.length() * d2.length());
    if !(sine >= PARALLEL_SINE) {
        return Err(CalibError::ParallelAxes { sine });
    }
    let nn = n.dot(n);
    let r = p2 - p1;
    Ok((d2.cross(n).dot(r) / nn, d1.cross(n).dot(r) / nn))
}

fn unit(what: &str, v: DVec3) -> Result<DVec3, CalibError> {
    finite(what, &v.to_array())?;
    let l = v.length();
    if !(l > MIN_DIRECTION_LENGTH) {
        return Err(CalibError::BadInput {
            what: what.to_string(),
            message: format!("the direction ({}, {}, {}) has zero length", v.x, v.y, v.z),
        });
    }
    Ok(v / l)
}

/// Eq. 5.7 for one series.
pub fn machine_origin(s: &Series, opts: &OriginOptions) -> Result<Origin, CalibError> {
    finite("a_axis", &s.a_pos.to_array())?;
    finite("b_axis", &s.b_pos.to_array())?;
    finite("bias", &opts.bias.to_array())?;
    finite("A-axis z correction", &[opts.a_z_correction_deg])?;
    let a_dir0 = unit("a_axis_dir", s.a_dir)?;
    let b_dir = unit("b_axis_dir", s.b_dir)?;
    let a_dir = crate::machine::angles::rot_z(a_dir0, num::rad(opts.a_z_correction_deg));
    let bias = opts.bias;
    let a_pos = s.a_pos + DVec3::new(0.0, -bias.y, bias.z);
    let b_pos = s.b_pos + bias;
    let (t1, t2) = closest_approach(a_pos, a_dir, b_pos, b_dir)?;
    let a_closest = a_pos + a_dir * t1;
    let origin = b_pos + b_dir * t2;
    let a_from_b = a_closest - origin;
    Ok(Origin {
        a_dir,
        b_dir,
        a_pos,
        b_pos,
        t1,
        t2,
        a_closest,
        origin,
        a_from_b,
        distance: a_from_b.length(),
        theta_deg: num::deg(num::asin(a_dir.y.clamp(-1.0, 1.0))),
        axes_angle_deg: num::deg(num::angle_between(a_dir, b_dir)),
    })
}

/// mean ± standard deviation (population) and max difference of one component.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stat {
    /// Arithmetic mean of the values.
    pub mean: f64,
    /// Population standard deviation (divides by n, as numpy's default).
    pub std: f64,
    /// Max difference over the values (max − min).
    pub max_diff: f64,
}

impl Stat {
    /// Of the values (none → zeros).
    pub fn of(v: &[f64]) -> Stat {
        if v.is_empty() {
            return Stat::default();
        }
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                (l.min(x), h.max(x))
            });
        Stat {
            mean,
            std: var.sqrt(),
            max_diff: hi - lo,
        }
    }
    fn text(&self) -> String {
        format!("{:.6} ± {:.6} ({:.6})", self.mean, self.std, self.max_diff)
    }
}

/// Per-component statistics of a vector quantity.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct VecStat {
    /// Statistics of the x components.
    pub x: Stat,
    /// Statistics of the y components.
    pub y: Stat,
    /// Statistics of the z components.
    pub z: Stat,
}

impl VecStat {
    /// Of the vectors.
    pub fn of(v: &[DVec3]) -> VecStat {
        let c = |k: usize| Stat::of(&v.iter().map(|p| p[k]).collect::<Vec<_>>());
        VecStat {
            x: c(0),
            y: c(1),
            z: c(2),
        }
    }
}

/// Table 6.2 over repeated series (raw measurements), plus the spread of the results.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SeriesStats {
    /// A_pos (`a_axis`) of each series as measured (printer's current frame), mm.
    pub a_pos: VecStat,
    /// B_pos (`b_axis`) of each series as measured (printer's current frame), mm.
    pub b_pos: VecStat,
    /// A_dir (`a_axis_dir`) of each series, normalised to unit length.
    pub a_dir: VecStat,
    /// B_dir (`b_axis_dir`) of each series, normalised to unit length.
    pub b_dir: VecStat,
    /// A^B_pos of each series.
    pub a_from_b: VecStat,
    /// B''_pos of each series.
    pub origin: VecStat,
    /// θ of each series, degrees.
    pub theta_deg: Stat,
}

/// What `calibrate origin` found.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OriginReport {
    /// Number of series read.
    pub series: usize,
    /// Eq. 5.7 on the mean series (what the machine JSON holds).
    pub result: Origin,
    /// Eq. 5.7 per series.
    pub per_series: Vec<Origin>,
    /// Table 6.2 statistics (with 2 or more series).
    pub stats: Option<SeriesStats>,
    /// The mean A-axis levelness slope m_zy (`a_z_in_y`), if measured.
    pub a_z_in_y: Option<f64>,
    /// The options used.
    pub options: OriginOptions,
}

fn v3(v: DVec3) -> String {
    format!("({:.6}, {:.6}, {:.6})", v.x, v.y, v.z)
}

impl OriginReport {
    /// The RepRapFirmware line that moves the G55 frame (the B-axis frame, seed 004 §4.3.2's
    /// `update_g55`) to the computed origin: the measurements are relative to the G55 frame in
    /// force, so the new offset is the old one plus B''_pos (machine = program + offset):
    /// `G10 L2 P2 X{move.axes[0].workplaceOffsets[1] + x} …`: `G10 L2 P2` sets coordinate
    /// system 2 (G55; P1 is G54) and RepRapFirmware adds the offset (machine = user + offset;
    /// `M206` is `G10 L2 P1` negated); `workplaceOffsets[1]` is G55's entry (index 0 is G54, as
    /// Duet Web Control reads `workplaceOffsets[move.workplaceNumber]`). Sources in
    /// docs/machines.md "Firmware facts and their sources". The expressions need a
    /// RepRapFirmware 3 with object-model expressions in G-code parameters: 3.3 or later is
    /// what the line says, the exact first version was not confirmed. Run it once per
    /// measurement cycle.
    pub fn g55_line(&self) -> String {
        let o = self.result.origin;
        let axis = |i: usize, v: f64| {
            format!(
                "{}{{move.axes[{i}].workplaceOffsets[1] + {v:.6}}}",
                ["X", "Y", "Z"][i]
            )
        };
        format!(
            "G10 L2 P2 {} {} {}   ; set G55 to the new origin (RepRapFirmware 3.3+ with expressions: the G55 offsets in force plus B''_pos; run once per measurement cycle)",
            axis(0, o.x),
            axis(1, o.y),
            axis(2, o.z)
        )
    }

    /// The human-readable report (what the CLI prints).
    pub fn to_text(&self) -> String {
        let r = &self.result;
        let mut s = String::new();
        s.push_str(&format!(
            "series: {}{}\n",
            self.series,
            if self.series > 1 {
                " (the machine uses their mean)"
            } else {
                ""
            }
        ));
        s.push_str(&format!(
            "corrections: bias {} mm, A z-rotation α_A,z = {}°\n",
            v3(self.options.bias),
            self.options.a_z_correction_deg
        ));
        s.push_str(&format!(
            "A'_dir = {}, B_dir = {} (angle between the axes {:.4}°)\n",
            v3(r.a_dir),
            v3(r.b_dir),
            r.axes_angle_deg
        ));
        s.push_str(&format!(
            "new origin B''_pos (current frame; shift the G55 frame by it) = {} mm\n",
            v3(r.origin)
        ));
        s.push_str(&format!("{}\n", self.g55_line()));
        s.push_str(&format!(
            "A^B_pos (A axis from the B axis) = {} mm, distance between the axes {:.6} mm\n",
            v3(r.a_from_b),
            r.distance
        ));
        s.push_str(&format!(
            "A axis rotation in the Z plane θ = asin(A'_dir.y) = {:.6}° ({:.7} rad)\n",
            r.theta_deg,
            num::rad(r.theta_deg)
        ));
        if let Some(m) = self.a_z_in_y {
            s.push_str(&format!(
                "A levelness a_z_in_y = {m:.7} ({:.4}°)\n",
                num::deg(num::atan(m))
            ));
        }
        if let Some(st) = &self.stats {
            s.push_str("component: mean ± std (max difference)\n");
            let rows: [(&str, &VecStat); 6] = [
                ("A axis position", &st.a_pos),
                ("B axis position", &st.b_pos),
                ("A axis direction", &st.a_dir),
                ("B axis direction", &st.b_dir),
                ("A^B_pos", &st.a_from_b),
                ("B''_pos", &st.origin),
            ];
            for (name, v) in rows {
                s.push_str(&format!(
                    "  {name}: X {}  Y {}  Z {}\n",
                    v.x.text(),
                    v.y.text(),
                    v.z.text()
                ));
            }
            s.push_str(&format!("  θ (degrees): {}\n", st.theta_deg.text()));
        }
        s
    }
}

/// The mean series: positions averaged, directions averaged (each normalised first) and
/// normalised, m_zy averaged over the series that have it.
pub fn mean_series(series: &[Series]) -> Result<Series, CalibError> {
    let first = series.first().ok_or(CalibError::NoSeries)?;
    let n = series.len() as f64;
    let mut m = Series {
        line: first.line,
        a_pos: DVec3::ZERO,
        a_dir: DVec3::ZERO,
        b_pos: DVec3::ZERO,
        b_dir: DVec3::ZERO,
        a_z_in_y: None,
    };
    let mut zy = Vec::new();
    for s in series {
        m.a_pos += s.a_pos / n;
        m.b_pos += s.b_pos / n;
        m.a_dir += unit("a_axis_dir", s.a_dir)? / n;
        m.b_dir += unit("b_axis_dir", s.b_dir)? / n;
        zy.extend(s.a_z_in_y);
    }
    if !zy.is_empty() {
        m.a_z_in_y = Some(zy.iter().sum::<f64>() / zy.len() as f64);
    }
    Ok(m)
}

/// Calibrate: Eq. 5.7 per series and on the mean series, statistics, and the calibrated
/// machine built from `base` (must be an `ab-table` spec).
pub fn calibrate_origin(
    series: &[Series],
    opts: &OriginOptions,
    base: &MachineSpec,
) -> Result<(OriginReport, MachineSpec), CalibError> {
    let per_series = series
        .iter()
        .map(|s| machine_origin(s, opts))
        .collect::<Result<Vec<_>, _>>()?;
    let mean = mean_series(series)?;
    let result = machine_origin(&mean, opts)?;
    let stats = (series.len() > 1).then(|| {
        let col =
            |f: &dyn Fn(&Series) -> DVec3| VecStat::of(&series.iter().map(f).collect::<Vec<_>>());
        SeriesStats {
            a_pos: col(&|s| s.a_pos),
            b_pos: col(&|s| s.b_pos),
            a_dir: col(&|s| s.a_dir.normalize_or_zero()),
            b_dir: col(&|s| s.b_dir.normalize_or_zero()),
            a_from_b: VecStat::of(&per_series.iter().map(|o| o.a_from_b).collect::<Vec<_>>()),
            origin: VecStat::of(&per_series.iter().map(|o| o.origin).collect::<Vec<_>>()),
            theta_deg: Stat::of(&per_series.iter().map(|o| o.theta_deg).collect::<Vec<_>>()),
        }
    });
    let mut spec = base.clone();
    match &mut spec.kinematics {
        Kinematics::AbTable(p) => {
            p.a_pos = result.a_from_b;
            p.a_dir = result.a_dir;
            p.b_pos = DVec3::ZERO;
            p.b_dir = result.b_dir;
        }
        _ => {
            return Err(CalibError::BadInput {
                what: format!("base machine {}", base.name),
                message: "is not an A/B table (kind 'ab-table'); use the open5x-ab preset or an ab-table JSON".to_string(),
            })
        }
    }
    // The spec must build (its own checks on the lines).
    spec.build()?;
    let report = OriginReport {
        series: series.len(),
        result,
        per_series,
        stats,
        a_z_in_y: mean.a_z_in_y,
        options: *opts,
    };
    Ok((report, spec))
}
