//! Batch kinematics over CSV text (for `warpslice kinematics inverse|forward`).
//!
//! - [`inverse_csv`]: each line `px,py,pz,nx,ny,nz` (mm, unit tool axis tip → nozzle) → one
//!   line of axis values in the machine's order. Lines are a path: each uses the previous
//!   line's axes to pick the branch (continuous rotary axes).
//! - [`forward_csv`]: each line of axis values → `px,py,pz,nx,ny,nz`.
//!
//! Values are written raw (no `G92` offsets) with Rust's shortest round-trip formatting, which
//! parses back to the identical f64 (≤ 17 significant digits). Blank lines and lines starting
//! with `#` are skipped; any other invalid line is a [`MachineError::BadCsv`] with its 1-based
//! number, or the machine's own error (unreachable, limit) prefixed by the line number.

use glam::DVec3;

use super::{Machine, MachineError};

fn parse_line(
    line: &str,
    lineno: usize,
    expected: usize,
) -> Result<Option<Vec<f64>>, MachineError> {
    let t = line.trim();
    if t.is_empty() || t.starts_with('#') {
        return Ok(None);
    }
    let mut v = Vec::with_capacity(expected);
    for (i, field) in t.split(',').enumerate() {
        let f = field.trim();
        match f.parse::<f64>() {
            Ok(x) if x.is_finite() => v.push(x),
            _ => {
                return Err(MachineError::BadCsv {
                    line: lineno,
                    message: format!("field {} '{f}' is not a finite number", i + 1),
                })
            }
        }
    }
    if v.len() != expected {
        return Err(MachineError::BadCsv {
            line: lineno,
            message: format!(
                "expected {expected} comma-separated numbers, got {}",
                v.len()
            ),
        });
    }
    Ok(Some(v))
}

fn join(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{v}"))
        .collect::<Vec<_>>()
        .join(",")
}

fn at_line(lineno: usize, e: MachineError) -> MachineError {
    match e {
        MachineError::BadCsv { .. } => e,
        other => MachineError::BadCsv {
            line: lineno,
            message: other.to_string(),
        },
    }
}

/// Inverse kinematics of every CSV line; output one line per input point (with `\n`).
pub fn inverse_csv(machine: &dyn Machine, input: &str) -> Result<String, MachineError> {
    let mut out = String::new();
    let mut prev: Option<Vec<f64>> = None;
    for (i, line) in input.lines().enumerate() {
        let Some(v) = parse_line(line, i + 1, 6)? else {
            continue;
        };
        let p = DVec3::new(v[0], v[1], v[2]);
        let n = DVec3::new(v[3], v[4], v[5]);
        if (n.length() - 1.0).abs() > super::UNIT_SLACK {
            return Err(MachineError::BadCsv {
                line: i + 1,
                message: format!(
                    "tool axis ({}, {}, {}) is not a unit vector (length {})",
                    n.x,
                    n.y,
                    n.z,
                    n.length()
                ),
            });
        }
        let axes = machine
            .inverse(p, n, prev.as_deref())
            .map_err(|e| at_line(i + 1, e))?;
        out.push_str(&join(&axes));
        out.push('\n');
        prev = Some(axes);
    }
    Ok(out)
}

/// Forward kinematics of every CSV line of axis values; output `px,py,pz,nx,ny,nz` lines.
pub fn forward_csv(machine: &dyn Machine, input: &str) -> Result<String, MachineError> {
    let count = machine.limits().len();
    let mut out = String::new();
    for (i, line) in input.lines().enumerate() {
        let Some(v) = parse_line(line, i + 1, count)? else {
            continue;
        };
        let (p, n) = machine.forward(&v).map_err(|e| at_line(i + 1, e))?;
        out.push_str(&join(&[p.x, p.y, p.z, n.x, n.y, n.z]));
        out.push('\n');
    }
    Ok(out)
}
