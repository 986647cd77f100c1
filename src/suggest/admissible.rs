//! Admissibility of a warp on a machine (issue 15): a warp is admissible when
//!
//! 1. the machine prints its family (the machine's own [`Capabilities::warps`]);
//! 2. the base blend keeps the layers from folding: ∂z'/∂z = 1 + w′(z)·g > 0 over the model
//!    ([`WarpParams::build`]'s rule, [`crate::warp::base`]);
//! 3. its largest tool tilt over the model is within the machine's tilt limit: at every sample
//!    point p (facet centroids and vertices, model frame) the tilt ∠(n(p), +z) is at most the
//!    machine's `max_tilt_deg` ([`Capabilities::max_tilt_deg`]), and a machine that tilts
//!    realises n(p) to within [`DROPPED_TILT_WARN_DEG`]: `∠(realised_axis(p, n), n) ≤ 1°` —
//!    this is where the B head's collision clip (18° at the bed, 90° from 50 mm) and its XZ
//!    plane, the rotating nozzle's fixed angle and the A/B table's range come from, read from
//!    the machine itself (the part taken at the output origin, z = model z). A machine that
//!    never tilts (it realises +z for tilted requests: the 3-axis printer) prints any layer
//!    with its vertical nozzle and has only its `max_tilt_deg`. The vertical axis the seeds
//!    give a kink (a cone's apex, a roof's crease) is a point the machine's pole rule handles:
//!    it is not held against a fixed-tilt nozzle;
//! 4. every layer is sliceable (the anchor rule, [`crate::anchor`]): the warped part's first
//!    layer holds [`anchor::MIN_FIRST_LAYER_AREA`] of it, or the anchor slab can be put under it (the
//!    footprint's convex hull has an area: not a part drawn in one vertical plane).

use glam::DVec3;

use super::family::Family;
use super::model::Model;
use crate::anchor;
use crate::machine::{Capabilities, Machine, MachineError, MachineSpec, LIMIT_SLACK_DEG};
use crate::mesh::Mesh;
use crate::num;
use crate::tolerance::DROPPED_TILT_WARN_DEG;
use crate::warp::{Warp, WarpError, WarpParams};

/// A machine's limits as admissibility reads them.
#[derive(Debug)]
pub struct MachineLimits {
    /// The machine (its realised axis is asked at every sample).
    pub machine: Box<dyn Machine>,
    /// What it says of itself (warps, tilt limit).
    pub capabilities: Capabilities,
    /// Whether it tilts at all: false when it realises +z for tool axes tilted 10° toward x
    /// and toward y at two points (the 3-axis printer), which then has no realised-axis rule.
    pub tilts: bool,
}

impl MachineLimits {
    /// The limits of the machine `spec` describes.
    pub fn new(spec: &MachineSpec) -> Result<MachineLimits, MachineError> {
        let machine = spec.build()?;
        let capabilities = machine.capabilities();
        let (s, c) = (num::sin(num::rad(10.0)), num::cos(num::rad(10.0)));
        let tilts = [DVec3::ZERO, DVec3::new(10.0, 10.0, 10.0)]
            .into_iter()
            .flat_map(|p| [DVec3::new(s, 0.0, c), DVec3::new(0.0, s, c)].map(|n| (p, n)))
            .any(|(p, n)| machine.realised_axis(p, n) != DVec3::Z);
        Ok(MachineLimits {
            machine,
            capabilities,
            tilts,
        })
    }

    /// Whether the machine prints warps of `family`.
    pub fn prints(&self, family: Family) -> bool {
        self.capabilities.warps.contains(&family.name())
    }
}

/// Why a warp is not admissible on a machine.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Inadmissible {
    /// The machine does not print this family.
    NotPrinted {
        /// The warp's name.
        warp: &'static str,
        /// The warps the machine prints.
        prints: Vec<&'static str>,
    },
    /// The warp cannot be built (its base blend folds the layers, or a parameter is out of
    /// range).
    Warp(WarpError),
    /// The tool tilts beyond the machine's `max_tilt_deg` at `at`.
    TooSteep {
        /// The tilt there, degrees.
        tilt_deg: f64,
        /// The machine's limit, degrees.
        limit_deg: f64,
        /// The model-frame point, mm.
        at: [f64; 3],
    },
    /// The machine realises another tool axis than the warp's at `at` (its clip, plane or
    /// fixed angle).
    NotRealised {
        /// The angle between the two, degrees.
        dropped_deg: f64,
        /// The model-frame point, mm.
        at: [f64; 3],
    },
    /// Neither the warped part's first layer nor an anchor slab holds enough to print.
    NotSliceable {
        /// The first layer's area, mm².
        first_layer_mm2: f64,
    },
}

impl std::fmt::Display for Inadmissible {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Inadmissible::NotPrinted { warp, prints } => write!(
                f,
                "the machine does not print the {warp} warp (it prints {})",
                prints.join(", ")
            ),
            Inadmissible::Warp(e) => write!(f, "{e}"),
            Inadmissible::TooSteep {
                tilt_deg,
                limit_deg,
                at,
            } => write!(
                f,
                "the tool tilts {tilt_deg:.2}° at ({:.2}, {:.2}, {:.2}), beyond the machine's {limit_deg}°",
                at[0], at[1], at[2]
            ),
            Inadmissible::NotRealised { dropped_deg, at } => write!(
                f,
                "the machine cannot give the tool axis at ({:.2}, {:.2}, {:.2}): it would print {dropped_deg:.2}° off it",
                at[0], at[1], at[2]
            ),
            Inadmissible::NotSliceable { first_layer_mm2 } => write!(
                f,
                "the warped part's first layer holds {first_layer_mm2:.2} mm² and its footprint has no area for an anchor slab (a part in one vertical plane)"
            ),
        }
    }
}

/// An admissible warp: the warp built, and its largest tilt over the samples checked.
#[derive(Debug)]
pub struct Admitted {
    /// The warp.
    pub warp: Box<dyn Warp>,
    /// The largest tool tilt from +z over the samples, degrees.
    pub largest_tilt_deg: f64,
}

/// Check `params` on `limits` for `model` at `samples` (model-frame points; the search passes
/// [`Model::coarse_samples`], a reported suggestion [`Model::samples`]), with the layer height
/// `layer_height` for the anchor rule.
pub fn admissible(
    params: &WarpParams,
    model: &Model,
    limits: &MachineLimits,
    samples: &[DVec3],
    layer_height: f64,
) -> Result<Admitted, Inadmissible> {
    let family = Family::of(&params.spec);
    if !family.is_some_and(|f| limits.prints(f)) {
        return Err(Inadmissible::NotPrinted {
            warp: params.spec.name(),
            prints: limits.capabilities.warps.clone(),
        });
    }
    let warp = params
        .clone()
        .build(&model.bbox)
        .map_err(Inadmissible::Warp)?;
    let largest_tilt_deg = tilt_rule(params, warp.as_ref(), limits, samples)?;
    sliceable(warp.as_ref(), model, layer_height)?;
    Ok(Admitted {
        warp,
        largest_tilt_deg,
    })
}

/// Rule 3; returns the largest tilt, degrees.
fn tilt_rule(
    params: &WarpParams,
    warp: &dyn Warp,
    limits: &MachineLimits,
    samples: &[DVec3],
) -> Result<f64, Inadmissible> {
    let limit = limits.capabilities.max_tilt_deg;
    // the seeds give a kink (apex, crease) the vertical axis: the pole, not a tilt to realise
    let kinked = params.base.is_none()
        && matches!(
            Family::of(&params.spec),
            Some(Family::Conic | Family::Tilted)
        );
    let cos_limit = limit.map_or(-1.0, |max| num::cos(num::rad(max + LIMIT_SLACK_DEG)));
    let mut least_cos: f64 = 1.0;
    for &p in samples {
        let n = warp.tool_axis(p);
        least_cos = least_cos.min(n.z);
        if n.z < cos_limit {
            return Err(Inadmissible::TooSteep {
                tilt_deg: tilt_deg(n),
                limit_deg: limit.unwrap_or(180.0),
                at: p.to_array(),
            });
        }
        if !limits.tilts || (kinked && n == DVec3::Z) {
            continue;
        }
        let realised = limits.machine.realised_axis(p, n);
        if realised == n {
            continue;
        }
        let dropped = num::deg(num::angle_between(realised, n));
        if dropped > DROPPED_TILT_WARN_DEG {
            return Err(Inadmissible::NotRealised {
                dropped_deg: dropped,
                at: p.to_array(),
            });
        }
    }
    let largest = tilt_deg(DVec3::new(0.0, 0.0, least_cos));
    Ok(largest)
}

/// ∠(n, +z) of a unit n, degrees.
fn tilt_deg(n: DVec3) -> f64 {
    num::deg(num::acos(n.z.clamp(-1.0, 1.0)))
}

/// Rule 4.
fn sliceable(warp: &dyn Warp, model: &Model, layer_height: f64) -> Result<(), Inadmissible> {
    if model.hull_area_mm2 > 0.0 {
        return Ok(()); // the anchor slab gives the first layer when the part does not
    }
    let warped = Mesh {
        vertices: model
            .mesh
            .vertices
            .iter()
            .map(|&v| warp.forward(v))
            .collect(),
        triangles: model.mesh.triangles.clone(),
    };
    if !anchor::needs_anchor(&warped, layer_height) {
        return Ok(());
    }
    Err(Inadmissible::NotSliceable {
        first_layer_mm2: anchor::first_layer_area(&warped, layer_height),
    })
}
