//! A field on top of a family warp (issue 15 item 3a): g = g_family + g_field, so that the
//! fitted field can start **exactly** at the best warp of the seed families (its correction
//! all zero) and only improve on it — a B-spline alone rounds a cone's apex off and can leave
//! more overhang than the cone it copies.
//!
//! **As text** (the job's `over` and the `--over` flag; no spaces and no shell metacharacters,
//! so a suggestion's flags stay one shell word each): the family's name, then its parameters as
//! `name=value`, separated by `:`; a value is a number, a word, or numbers joined by `,`:
//! `conic:angle=30:direction=outward:center=1.5,-2`, `belt:angle=20:toward=1,0`,
//! `curved:strength=0.1:direction=inward:offset=0:width=40`,
//! `tilted:strength=0.3:direction=outward:offset=-2`. The names are the job file's (the
//! serde names of [`WarpSpec`]); only the four shear families are allowed.
//!
//! ∇(g_family + g_field) = ∇g_family + ∇g_field: at a family's kink (the cone's apex, the
//! tilted warp's crease) the sum's gradient is the family's mean of one-sided gradients plus
//! the field's, the same rule as the family warp alone.

use glam::DVec2;
use serde_json::{Map, Value};

use super::{Height, WarpError, WarpSpec};

/// The families a field may lie over.
pub const OVER_FAMILIES: [&str; 4] = ["curved", "tilted", "conic", "belt"];

/// g = `family` + `field`.
#[derive(Debug)]
pub struct Sum {
    /// The family warp's height.
    pub family: Box<dyn Height>,
    /// The field's height (a B-spline or an expression).
    pub field: Box<dyn Height>,
}

impl Height for Sum {
    fn into_shear(self: Box<Self>, blend: Option<super::BaseBlend>) -> Box<dyn super::Warp> {
        Box::new(super::Shear::new(self, blend))
    }

    fn g(&self, x: f64, y: f64) -> f64 {
        self.family.g(x, y) + self.field.g(x, y)
    }
    fn grad(&self, x: f64, y: f64) -> DVec2 {
        self.family.grad(x, y) + self.field.grad(x, y)
    }
}

/// The text form of a (resolved) family warp; `None` for a warp that is not one of
/// [`OVER_FAMILIES`].
pub fn to_text(spec: &WarpSpec) -> Option<String> {
    if !OVER_FAMILIES.contains(&spec.name()) {
        return None;
    }
    let Ok(Value::Object(map)) = serde_json::to_value(spec) else {
        return None;
    };
    let f = crate::num::fmt_shortest;
    let mut s = spec.name().to_string();
    for (k, v) in map.iter().filter(|(k, _)| k.as_str() != "kind") {
        let value = match v {
            Value::Number(n) => f(n.as_f64()?),
            Value::String(t) => t.clone(),
            Value::Array(a) => a
                .iter()
                .map(|x| x.as_f64().map(f))
                .collect::<Option<Vec<_>>>()?
                .join(","),
            _ => return None,
        };
        s.push_str(&format!(":{k}={value}"));
    }
    Some(s)
}

/// Read the text form (the module documentation); names what is wrong.
pub fn parse(text: &str) -> Result<WarpSpec, WarpError> {
    let bad = |why: String| WarpError::BadParameter {
        name: "over",
        value: text.to_string(),
        allowed: format!(
            "a family warp as kind:name=value:… with kind one of {} (e.g. \
             conic:angle=30:direction=outward:center=0,0): {why}",
            OVER_FAMILIES.join(", ")
        ),
    };
    let mut parts = text.split(':');
    let kind = parts.next().unwrap_or_default();
    if !OVER_FAMILIES.contains(&kind) {
        return Err(bad(format!("'{kind}' is not one of them")));
    }
    let mut map = Map::new();
    map.insert("kind".into(), Value::from(kind));
    for part in parts {
        let (k, v) = part
            .split_once('=')
            .ok_or_else(|| bad(format!("'{part}' is not name=value")))?;
        let number = |t: &str| t.parse::<f64>().ok().filter(|x| x.is_finite());
        let value = if v.contains(',') {
            let list = v
                .split(',')
                .map(|t| number(t).map(Value::from))
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| bad(format!("'{v}' is not a list of finite numbers")))?;
            Value::Array(list)
        } else if let Some(x) = number(v) {
            Value::from(x)
        } else {
            Value::from(v)
        };
        if map.insert(k.to_string(), value).is_some() {
            return Err(bad(format!("'{k}' given twice")));
        }
    }
    let spec: WarpSpec =
        serde_json::from_value(Value::Object(map)).map_err(|e| bad(e.to_string()))?;
    spec.validate()?;
    Ok(spec)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::warp::Direction;

    #[test]
    fn every_family_round_trips_through_its_text() {
        for spec in [
            WarpSpec::Conic {
                angle: 27.5,
                direction: Direction::Inward,
                center: [1.25, -3.0],
            },
            WarpSpec::Belt {
                angle: 20.0,
                toward: [0.6, -0.8],
            },
            WarpSpec::Curved {
                strength: 0.1,
                direction: Direction::Outward,
                offset: -2.0,
                width: 40.0,
            },
            WarpSpec::Tilted {
                strength: 0.3,
                direction: Direction::Inward,
                offset: 0.0,
            },
        ] {
            let text = to_text(&spec).unwrap();
            assert!(!text.contains(' '), "{text}");
            assert_eq!(parse(&text).unwrap(), spec, "{text}");
        }
    }

    #[test]
    fn bad_text_is_named() {
        for bad in [
            "spherical:radius=3:center=0,0,0",
            "conic:angle",
            "conic:angle=30:angle=20:direction=outward:center=0,0",
            "conic:angle=95:direction=outward:center=0,0",
            "belt:angle=20:toward=a,b",
            "conic:angle=30:colour=red:direction=outward:center=0,0",
        ] {
            let e = parse(bad).unwrap_err();
            assert!(
                e.to_string().contains("over") || e.to_string().contains("angle"),
                "{bad}: {e}"
            );
        }
        assert!(to_text(&WarpSpec::Spherical {
            radius: 1.0,
            center: [0.0; 3]
        })
        .is_none());
    }
}
