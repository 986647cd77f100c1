//! Automatic warp (issue 15): how much of a model overhangs, planar and under a warp
//! ([`overhangs`]), and which warps of the seed families leave the least overhang on a machine
//! ([`suggest`]).
//!
//! The measure is [`crate::overhang`]'s (facet overhangs when m·n(c) < −cos θ, the bed
//! excluded); admissibility is [`admissible`]'s (the machine prints the family, its tilt limit
//! and realised axis, the base blend's monotonicity, the anchor rule); the search is
//! [`search`]'s (a coarse grid, then a pattern search, with and without the base blend).
//! Everything here works on the input mesh in the model frame, not subdivided.

use serde::{Deserialize, Serialize};

use crate::machine::{MachineError, MachineSpec};
use crate::mesh::MeshError;
use crate::overhang::{OverhangMeasure, DEFAULT_OVERHANG_ANGLE_DEG};
use crate::schema::{Param, ParamDefault, ParamType};
use crate::tolerance::{DEFAULT_LAYER_HEIGHT, DEFAULT_MAX_EDGE};
use crate::warp::{WarpError, WarpParams};

pub mod admissible;
pub mod family;
pub mod fit;
pub mod model;
pub mod search;

pub use admissible::{admissible, Inadmissible, MachineLimits};
pub use family::{Family, FAMILIES, FAMILY_NAMES};
pub use model::Model;

/// A warp is suggested only when it leaves at least this much less overhang than planar
/// printing, mm² (area sums carry rounding of this order on large meshes).
pub const AREA_GAIN_MM2: f64 = 1e-6;

/// Suggestions listed when `--top` is not given.
pub const DEFAULT_TOP: usize = 5;

/// What `overhangs` and `suggest` are asked besides the model (and the machine).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SuggestOptions {
    /// θ, degrees: a facet overhangs when m·n < −cos θ.
    pub overhang_angle: f64,
    /// The families searched (a JSON list, or one comma-separated string).
    #[serde(deserialize_with = "families")]
    pub families: Vec<Family>,
    /// How many suggestions to list.
    #[serde(deserialize_with = "top")]
    pub top: usize,
    /// The layer height the part will be sliced with, mm (the anchor rule, the layer count).
    pub layer_height: f64,
}

impl Default for SuggestOptions {
    fn default() -> SuggestOptions {
        SuggestOptions {
            overhang_angle: DEFAULT_OVERHANG_ANGLE_DEG,
            families: FAMILIES.to_vec(),
            top: DEFAULT_TOP,
            layer_height: DEFAULT_LAYER_HEIGHT,
        }
    }
}

/// `top`: a count ([`crate::schema::count`]).
fn top<'de, D: serde::Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
    crate::schema::count(d, "top")
}

/// `["conic", "belt"]` or `"conic,belt"`.
fn families<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<Family>, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Given {
        List(Vec<String>),
        Text(String),
    }
    let names = match Given::deserialize(d)? {
        Given::List(v) => v,
        Given::Text(t) => t.split(',').map(str::to_string).collect(),
    };
    names
        .iter()
        .map(|n| n.parse().map_err(serde::de::Error::custom))
        .collect()
}

/// The printable overhang angle θ (`--overhang-angle`), shared by `overhangs` and `suggest`.
pub const OVERHANG_ANGLE: Param =
    Param::number("overhang_angle", "--overhang-angle", "Overhang angle")
        .unit("deg")
        .range(Some(0.0), Some(90.0), (false, true))
        .step(5.0)
        .default(ParamDefault::Number(DEFAULT_OVERHANG_ANGLE_DEG))
        .help(
            "θ: a facet overhangs when its normal leans more than θ below the layer (m·n < −cos θ)",
        );

/// The parameters of `suggest` besides the model and `--machine` (`overhangs` takes the
/// first).
pub const PARAMS: &[Param] = &[
    OVERHANG_ANGLE,
    Param::number("families", "--families", "Families")
        .choices(FAMILY_NAMES)
        .of(ParamType::Choices)
        .default(ParamDefault::Text("conic,belt,curved,tilted,field"))
        .help("the warp families searched (comma-separated)"),
    Param::number("top", "--top", "Suggestions")
        .range(Some(1.0), None, (false, false))
        .step(1.0)
        .default(ParamDefault::Number(DEFAULT_TOP as f64))
        .help("how many suggestions to list, best first"),
    Param::number("layer_height", "--layer-height", "Layer height")
        .unit("mm")
        .range(Some(0.0), None, (true, false))
        .step(0.05)
        .default(ParamDefault::Number(DEFAULT_LAYER_HEIGHT))
        .help("the layer height you will slice with (the anchor rule and the layer count)"),
];

/// Why `overhangs` or `suggest` cannot answer.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SuggestError {
    /// The STL cannot be read.
    Mesh(MeshError),
    /// The warp given to `overhangs` cannot be built for this model.
    Warp(WarpError),
    /// The machine cannot be set up.
    Machine(MachineError),
    /// An option outside its range.
    BadOption {
        /// The option's flag.
        flag: &'static str,
        /// The value given.
        value: String,
        /// What is allowed.
        allowed: &'static str,
    },
    /// The machine prints none of the families asked for.
    NoFamily {
        /// The machine's name.
        machine: String,
        /// The families asked for.
        asked: Vec<&'static str>,
        /// The warps the machine prints.
        prints: Vec<&'static str>,
    },
    /// `--suggested N` beyond the list.
    NoSuchSuggestion {
        /// N as given (1-based).
        n: usize,
        /// How many suggestions there are.
        found: usize,
    },
}

impl std::fmt::Display for SuggestError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SuggestError::Mesh(e) => write!(f, "{e}"),
            SuggestError::Warp(e) => write!(f, "{e}"),
            SuggestError::Machine(e) => write!(f, "{e}"),
            SuggestError::BadOption { flag, value, allowed } => {
                write!(f, "{flag} {value} is not allowed: {allowed}")
            }
            SuggestError::NoFamily { machine, asked, prints } => write!(
                f,
                "machine {machine} prints none of the families asked for ({}); it prints {}: give --families with one of those, or another --machine",
                asked.join(", "),
                if prints.is_empty() { "no warp the search covers".to_string() } else { prints.join(", ") }
            ),
            SuggestError::NoSuchSuggestion { n, found } => write!(
                f,
                "--suggested {n}: the search found {found} admissible warp{} for this model and machine; give --suggested 1 … {found} (`warpslice suggest` lists them)",
                if *found == 1 { "" } else { "s" }
            ),
        }
    }
}

impl std::error::Error for SuggestError {}

crate::error_codes!(SuggestError, ERROR_CODES, "suggest" {
    BadOption => "suggest.bad-option", "an overhangs/suggest option outside its range";
    NoFamily => "suggest.no-family", "the machine prints none of the families asked for";
    NoSuchSuggestion => "suggest.no-such-suggestion", "--suggested N beyond the suggestions found";
} wraps { Mesh, Warp, Machine });

impl SuggestOptions {
    /// Check the options' ranges.
    pub fn validate(&self) -> Result<(), SuggestError> {
        if !(self.overhang_angle >= 0.0 && self.overhang_angle < 90.0) {
            return Err(SuggestError::BadOption {
                flag: "--overhang-angle",
                value: self.overhang_angle.to_string(),
                allowed: "0 ≤ θ < 90 degrees",
            });
        }
        if self.top == 0 {
            return Err(SuggestError::BadOption {
                flag: "--top",
                value: "0".into(),
                allowed: "at least 1",
            });
        }
        if !(self.layer_height.is_finite() && self.layer_height > 0.0) {
            return Err(SuggestError::BadOption {
                flag: "--layer-height",
                value: self.layer_height.to_string(),
                allowed: "a layer height > 0 mm",
            });
        }
        if self.families.is_empty() {
            return Err(SuggestError::BadOption {
                flag: "--families",
                value: String::new(),
                allowed: "one or more of conic, belt, curved, tilted, field",
            });
        }
        Ok(())
    }
}

/// Read an STL and move it to the model frame (the XY box centred on the origin, the lowest
/// point at z = 0: the frame every warp is defined in).
pub fn model_of(stl: &[u8]) -> Result<Model, SuggestError> {
    let (mut mesh, report) = crate::mesh::read_stl(stl).map_err(SuggestError::Mesh)?;
    mesh.translate(crate::pipeline::input_to_model(&report.bbox));
    Ok(Model::new(mesh))
}

/// `warpslice overhangs`: the overhang planar and under `warp`, per facet.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OverhangReport {
    /// θ, degrees.
    pub overhang_angle_deg: f64,
    /// Facets of the input mesh.
    pub triangles: usize,
    /// Planar printing.
    pub planar: OverhangMeasure,
    /// Under the warp given (absent without one).
    pub warped: Option<OverhangMeasure>,
    /// The warp's flags (absent without one).
    pub flags: Option<String>,
    /// Per facet (input order): 1 when it overhangs planar, else 0 (`--json` only).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub planar_facets: Vec<u8>,
    /// Per facet: 1 when it overhangs under the warp, else 0 (`--json` only).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warped_facets: Vec<u8>,
    /// Per facet: the warp's tool tilt from +z at its centroid, degrees (`--json` only, with a
    /// warp): the page's tilt map.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warped_tilts_deg: Vec<f64>,
}

/// Measure the overhang of `model` planar and under `warp` (if given), with the per-facet
/// flags when `per_facet`.
pub fn overhangs(
    model: &Model,
    warp: Option<&WarpParams>,
    overhang_angle: f64,
    per_facet: bool,
) -> Result<OverhangReport, SuggestError> {
    SuggestOptions {
        overhang_angle,
        ..SuggestOptions::default()
    }
    .validate()?;
    let built = match warp {
        Some(p) => Some(p.clone().build(&model.bbox).map_err(SuggestError::Warp)?),
        None => None,
    };
    let bits = |w: Option<&dyn crate::warp::Warp>| -> Vec<u8> {
        model
            .facets
            .flags(w, overhang_angle)
            .into_iter()
            .map(u8::from)
            .collect()
    };
    Ok(OverhangReport {
        overhang_angle_deg: overhang_angle,
        triangles: model.mesh.triangles.len(),
        planar: model.facets.measure(None, overhang_angle),
        warped: built
            .as_ref()
            .map(|w| model.facets.measure(Some(w.as_ref()), overhang_angle)),
        flags: warp.map(family::flags),
        planar_facets: if per_facet { bits(None) } else { Vec::new() },
        warped_facets: match (&built, per_facet) {
            (Some(w), true) => bits(Some(w.as_ref())),
            _ => Vec::new(),
        },
        warped_tilts_deg: match (&built, per_facet) {
            (Some(w), true) => model.facets.tilts_deg(w.as_ref()),
            _ => Vec::new(),
        },
    })
}

/// One suggested warp.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Suggestion {
    /// The warp flags, one string `warpslice warp` accepts.
    pub flags: String,
    /// The warp (as the job file and the web page hold it).
    pub warp: WarpParams,
    /// The overhang area left, mm².
    pub overhang_area_mm2: f64,
    /// The same as a percentage of the surface.
    pub overhang_percent: f64,
    /// The largest tool tilt over the model, degrees.
    pub largest_tilt_deg: f64,
    /// Layers of the warped part at the layer height asked for.
    pub layers: usize,
    /// An estimate of the subdivided triangle count at the default `--max-edge`: each facet
    /// split into k² with k = ⌈longest warped edge / max edge⌉ (the chord rule adds a few more
    /// on curved warps).
    pub triangles_estimate: usize,
}

/// `warpslice suggest`: the ranked admissible warps and the planar baseline.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SuggestReport {
    /// The machine's name.
    pub machine: String,
    /// θ, degrees.
    pub overhang_angle_deg: f64,
    /// Planar printing.
    pub planar: OverhangMeasure,
    /// The suggestions, best first: the best of each family × direction × base blend that
    /// leaves less overhang than planar, each admissible at every facet centroid and vertex.
    pub suggestions: Vec<Suggestion>,
    /// Distinct warps measured by the search.
    pub measured: usize,
}

/// Search the admissible warps of `options.families` on `machine` for `model`.
pub fn suggest(
    model: &Model,
    machine: &MachineSpec,
    options: &SuggestOptions,
) -> Result<SuggestReport, SuggestError> {
    options.validate()?;
    let limits = MachineLimits::new(machine).map_err(SuggestError::Machine)?;
    if !options.families.iter().any(|&f| limits.prints(f)) {
        return Err(SuggestError::NoFamily {
            machine: machine.name.clone(),
            asked: options.families.iter().map(|f| f.name()).collect(),
            prints: limits
                .capabilities
                .warps
                .iter()
                .copied()
                .filter(|w| FAMILY_NAMES.contains(w))
                .collect(),
        });
    }
    let mut s = search::Search::new(model, &limits, options.overhang_angle, options.layer_height);
    let ranked = s.run(&options.families);
    let planar = model.facets.measure(None, options.overhang_angle);
    let mut suggestions = Vec::new();
    let mut groups = std::collections::BTreeSet::new();
    for c in ranked {
        if suggestions.len() == options.top {
            break;
        }
        // a warp that leaves as much as planar printing is no suggestion
        if c.area_mm2 >= planar.area_mm2 - AREA_GAIN_MM2 {
            break;
        }
        // the best of each family × direction × base: a list of choices, not of near-twins
        let direction = match c.params.spec {
            crate::warp::WarpSpec::Belt { .. } => None,
            _ => Some(c.point.direction),
        };
        let group = (
            c.point.family,
            direction.map(|d| d == crate::warp::Direction::Outward),
            c.params.base.is_some(),
        );
        if groups.contains(&group) {
            continue;
        }
        // the search checked the coarse samples: a listed warp holds at every sample
        let Ok(a) = admissible(
            &c.params,
            model,
            &limits,
            &model.samples,
            options.layer_height,
        ) else {
            continue;
        };
        let m = model
            .facets
            .measure(Some(a.warp.as_ref()), options.overhang_angle);
        let warped: Vec<_> = model
            .mesh
            .vertices
            .iter()
            .map(|&v| a.warp.forward(v))
            .collect();
        groups.insert(group);
        suggestions.push(Suggestion {
            flags: c.flags.clone(),
            warp: c.params.clone(),
            overhang_area_mm2: m.area_mm2,
            overhang_percent: m.percent,
            largest_tilt_deg: a.largest_tilt_deg,
            layers: layers(&warped, options.layer_height),
            triangles_estimate: triangles_estimate(&model.mesh.triangles, &warped),
        });
    }
    Ok(SuggestReport {
        machine: machine.name.clone(),
        overhang_angle_deg: options.overhang_angle,
        planar,
        suggestions,
        measured: s.measured(),
    })
}

/// ⌈(max z′ − min z′)/h⌉ over the warped vertices.
fn layers(warped: &[glam::DVec3], layer_height: f64) -> usize {
    let (lo, hi) = warped
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.z), hi.max(v.z))
        });
    if hi > lo {
        ((hi - lo) / layer_height).ceil() as usize
    } else {
        0
    }
}

/// Σ k², k = ⌈longest warped edge / [`DEFAULT_MAX_EDGE`]⌉ per facet.
fn triangles_estimate(triangles: &[[u32; 3]], warped: &[glam::DVec3]) -> usize {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| warped[i as usize]);
            let longest = (b - a).length().max((c - b).length()).max((a - c).length());
            let k = (longest / DEFAULT_MAX_EDGE).ceil().max(1.0) as usize;
            k * k
        })
        .sum()
}

/// Entry `n` (1-based) of the suggestions for `model` on `machine` (`warpslice warp
/// --suggested N`: the same deterministic search, run again).
pub fn suggested(
    model: &Model,
    machine: &MachineSpec,
    options: &SuggestOptions,
    n: usize,
) -> Result<Suggestion, SuggestError> {
    let opts = SuggestOptions {
        top: options.top.max(n),
        ..options.clone()
    };
    let report = suggest(model, machine, &opts)?;
    let found = report.suggestions.len();
    n.checked_sub(1)
        .and_then(|i| report.suggestions.into_iter().nth(i))
        .ok_or(SuggestError::NoSuchSuggestion { n, found })
}
