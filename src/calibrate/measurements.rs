//! The measurement file `ab_values.out` (seed 004 §4.3.1, listing 4.1).
//!
//! ```text
//! <heading line>
//! a_axis {0,-0.1650009,-0.2140012}
//! a_z_in_y 0.0030937
//! a_axis_dir {0.9994476,0.0332315,-0.0004059}
//! b_axis {-0.1399994,0.0900002,-10}
//! b_axis_dir {0.0010010,0.0059996,0.9999815}
//! ```
//! Space separated: the component, then a vector `{x,y,z}` or a number. `a_axis` is A_pos
//! (Eq. 5.3), `a_axis_dir` A_dir (Eq. 5.4), `b_axis` B_pos (Eq. 5.5), `b_axis_dir` B_dir
//! (Eq. 5.6), all in the printer's current frame (mm); `a_z_in_y` is the slope m_zy of Eq. 5.4
//! (how level the A axis is homed; reported, not used by Eq. 5.7).
//!
//! Accepted around that: blank lines; comment lines starting with `;`, `#` or `//`; one heading
//! line (the first non-blank line when it is not a component line); the listing's line-number
//! prefix `12 | ` (so a pasted listing reads). Repeated series: a component that the current
//! series already has starts a new series. Every series needs `a_axis`, `a_axis_dir`,
//! `b_axis`, `b_axis_dir`; `a_z_in_y` is optional. Anything else is an error naming the line.

use glam::DVec3;

use super::CalibError;

/// One measurement series (printer's current frame, mm; directions as measured).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Series {
    /// 1-based line number of the series' first component line.
    pub line: usize,
    /// A_pos (`a_axis`).
    pub a_pos: DVec3,
    /// A_dir (`a_axis_dir`).
    pub a_dir: DVec3,
    /// B_pos (`b_axis`).
    pub b_pos: DVec3,
    /// B_dir (`b_axis_dir`).
    pub b_dir: DVec3,
    /// m_zy (`a_z_in_y`), if measured.
    pub a_z_in_y: Option<f64>,
}

#[derive(Default)]
struct Partial {
    line: usize,
    a_pos: Option<DVec3>,
    a_dir: Option<DVec3>,
    b_pos: Option<DVec3>,
    b_dir: Option<DVec3>,
    a_z_in_y: Option<f64>,
}

impl Partial {
    fn is_empty(&self) -> bool {
        self.a_pos.is_none()
            && self.a_dir.is_none()
            && self.b_pos.is_none()
            && self.b_dir.is_none()
            && self.a_z_in_y.is_none()
    }
    fn finish(self) -> Result<Series, CalibError> {
        let miss = |m| CalibError::IncompleteSeries {
            line: self.line,
            missing: m,
        };
        Ok(Series {
            line: self.line,
            a_pos: self.a_pos.ok_or_else(|| miss("a_axis"))?,
            a_dir: self.a_dir.ok_or_else(|| miss("a_axis_dir"))?,
            b_pos: self.b_pos.ok_or_else(|| miss("b_axis"))?,
            b_dir: self.b_dir.ok_or_else(|| miss("b_axis_dir"))?,
            a_z_in_y: self.a_z_in_y,
        })
    }
}

const KEYS: [&str; 5] = ["a_axis", "a_z_in_y", "a_axis_dir", "b_axis", "b_axis_dir"];

/// Strip the listing's `12 | ` prefix, if any.
fn strip_listing_number(s: &str) -> &str {
    let digits = s.bytes().take_while(|b| b.is_ascii_digit()).count();
    if digits > 0 {
        let rest = s[digits..].trim_start();
        if let Some(r) = rest.strip_prefix('|') {
            return r.trim_start();
        }
    }
    s
}

fn number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok().filter(|v| v.is_finite())
}

fn vector(s: &str) -> Result<DVec3, String> {
    let inner = s
        .trim()
        .strip_prefix('{')
        .and_then(|r| r.strip_suffix('}'))
        .ok_or_else(|| format!("'{s}' is not a vector {{x,y,z}}"))?;
    let parts: Vec<&str> = inner.split(',').collect();
    if parts.len() != 3 {
        return Err(format!(
            "the vector has {} components, expected 3 ({{x,y,z}})",
            parts.len()
        ));
    }
    let mut v = [0.0; 3];
    for (k, p) in parts.iter().enumerate() {
        v[k] = number(p)
            .ok_or_else(|| format!("component {} '{}' is not a number", k + 1, p.trim()))?;
    }
    Ok(DVec3::from_array(v))
}

/// Parse an `ab_values.out` text into its series (at least one).
pub fn parse_measurements(text: &str) -> Result<Vec<Series>, CalibError> {
    let mut out = Vec::new();
    let mut cur = Partial::default();
    let mut seen_content = false;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let s = strip_listing_number(raw.trim());
        if s.is_empty() || s.starts_with(';') || s.starts_with('#') || s.starts_with("//") {
            continue;
        }
        let (key, value) = match s.find(char::is_whitespace) {
            Some(p) => (&s[..p], s[p..].trim()),
            None => (s, ""),
        };
        let first = !seen_content;
        seen_content = true;
        if !KEYS.contains(&key) {
            if first && !value.starts_with('{') && number(value).is_none() {
                continue; // the heading line
            }
            return Err(CalibError::BadLine {
                line,
                text: raw.to_string(),
                message: format!("unknown component '{key}'"),
            });
        }
        let bad = |message: String| CalibError::BadLine {
            line,
            text: raw.to_string(),
            message,
        };
        if value.is_empty() {
            return Err(bad(format!("'{key}' has no value")));
        }
        let already = match key {
            "a_axis" => cur.a_pos.is_some(),
            "a_axis_dir" => cur.a_dir.is_some(),
            "b_axis" => cur.b_pos.is_some(),
            "b_axis_dir" => cur.b_dir.is_some(),
            _ => cur.a_z_in_y.is_some(),
        };
        if already {
            let done = std::mem::take(&mut cur);
            out.push(done.finish()?);
        }
        if cur.is_empty() {
            cur.line = line;
        }
        match key {
            "a_z_in_y" => {
                cur.a_z_in_y =
                    Some(number(value).ok_or_else(|| bad(format!("'{value}' is not a number")))?)
            }
            _ => {
                let v = vector(value).map_err(bad)?;
                match key {
                    "a_axis" => cur.a_pos = Some(v),
                    "a_axis_dir" => cur.a_dir = Some(v),
                    "b_axis" => cur.b_pos = Some(v),
                    _ => cur.b_dir = Some(v),
                }
            }
        }
    }
    if !cur.is_empty() {
        out.push(cur.finish()?);
    }
    if out.is_empty() {
        return Err(CalibError::NoSeries);
    }
    Ok(out)
}

/// Write series in the listing 4.1 format (full precision; for synthetic files and round
/// trips). The heading is written first.
pub fn write_measurements(series: &[Series], heading: &str) -> String {
    let v = |d: DVec3| format!("{{{:?},{:?},{:?}}}", d.x, d.y, d.z);
    let mut s = format!("{heading}\n");
    for x in series {
        s.push_str(&format!("a_axis {}\n", v(x.a_pos)));
        if let Some(m) = x.a_z_in_y {
            s.push_str(&format!("a_z_in_y {m:?}\n"));
        }
        s.push_str(&format!("a_axis_dir {}\n", v(x.a_dir)));
        s.push_str(&format!("b_axis {}\n", v(x.b_pos)));
        s.push_str(&format!("b_axis_dir {}\n", v(x.b_dir)));
    }
    s
}
