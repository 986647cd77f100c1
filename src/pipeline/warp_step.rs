//! The warp step: STL → warped STL and job.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::Error;
use crate::anchor;
use crate::job::{fnv1a64, Job, JOB_FORMAT};
use crate::mesh::{self, Aabb, Mesh, MeshReport, SubdivideOptions, SubdivideStats};
use crate::schema::{Param, ParamDefault, ParamType};
use crate::tolerance::{DEFAULT_LAYER_HEIGHT, DEFAULT_MAX_EDGE, DEFAULT_TOLERANCE};
use crate::warp::WarpParams;

/// Whether to put the removable anchor slab under the warped part (see [`crate::anchor`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum AnchorMode {
    /// When the warped bottom is not flat.
    #[default]
    Auto,
    /// Always: a slab even under a flat warped bottom.
    On,
    /// Never: the warped part goes to the slicer as it is.
    Off,
}

/// Options of the warp step (CLI: `warpslice warp`). Unknown keys are refused.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WarpOptions {
    /// The warp kind, its parameters and the optional flat base (`--warp` and its options).
    pub warp: WarpParams,
    /// `--max-edge`, mm.
    #[serde(default = "default_max_edge")]
    pub max_edge: f64,
    /// `--tolerance`, mm.
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// `--layer-height`, mm: the layer height you will slice with (anchor thickness).
    #[serde(default = "default_layer_height")]
    pub layer_height: f64,
    /// `--anchor auto|on|off`.
    #[serde(default)]
    pub anchor: AnchorMode,
    /// `--layer-thickness`, mm: the layer thickness wanted along the tool axis; when given, the
    /// vertical `layer_height` is computed from it ([`crate::warp::thickness`]) and replaces
    /// the one given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer_thickness: Option<f64>,
    /// `--thickness-at-tilt`, degrees: where `layer_thickness` holds (default: at the model's
    /// largest tilt). Shear warps only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness_at_tilt: Option<f64>,
}

fn default_max_edge() -> f64 {
    DEFAULT_MAX_EDGE
}
fn default_tolerance() -> f64 {
    DEFAULT_TOLERANCE
}
fn default_layer_height() -> f64 {
    DEFAULT_LAYER_HEIGHT
}

impl WarpOptions {
    /// Options from their JSON object (the CLI's and the web page's shape): parameters left out
    /// of the warp take their defaults ([`crate::warp::fill_defaults`]).
    pub fn from_json_value(mut v: serde_json::Value) -> Result<WarpOptions, Error> {
        if let Some(spec) = v
            .get_mut("warp")
            .and_then(|w| w.get_mut("spec"))
            .and_then(serde_json::Value::as_object_mut)
        {
            crate::warp::fill_defaults(spec);
        }
        serde_json::from_value(v).map_err(|e| Error::Option {
            name: "warp options",
            value: e.to_string(),
            allowed: "the warp options JSON of `describe()`",
        })
    }

    /// [`WarpOptions::from_json_value`] of a JSON text.
    pub fn from_json(text: &str) -> Result<WarpOptions, Error> {
        let v = serde_json::from_str(text).map_err(|e| Error::Option {
            name: "warp options",
            value: e.to_string(),
            allowed: "a JSON object",
        })?;
        WarpOptions::from_json_value(v)
    }

    /// The options for `warp` with every other option at its default.
    pub fn new(warp: WarpParams) -> WarpOptions {
        WarpOptions {
            warp,
            max_edge: DEFAULT_MAX_EDGE,
            tolerance: DEFAULT_TOLERANCE,
            layer_height: DEFAULT_LAYER_HEIGHT,
            anchor: AnchorMode::Auto,
            layer_thickness: None,
            thickness_at_tilt: None,
        }
    }
}

/// The parameters of the warp step besides the warp's own ([`crate::warp::WARPS`]): the
/// `--base` blend (key in the warp object) and the options' top-level keys.
pub const WARP_OPTION_PARAMS: &[Param] = &[
    Param::number("base", "--base", "Flat base z0,z1")
        .of(ParamType::Pair)
        .unit("mm")
        .optional()
        .help("keep the layers flat below z0 and blend the warp in up to z1 (shear warps only)"),
    Param::number("max_edge", "--max-edge", "Max edge")
        .unit("mm")
        .range(Some(0.0), None, (true, false))
        .step(0.1)
        .default(ParamDefault::Number(DEFAULT_MAX_EDGE))
        .help("split mesh edges longer than this before warping"),
    Param::number("tolerance", "--tolerance", "Tolerance")
        .unit("mm")
        .range(Some(0.0), None, (true, false))
        .step(0.001)
        .default(ParamDefault::Number(DEFAULT_TOLERANCE))
        .help("split where the warped midpoint of an edge (or a move) deviates more than this"),
    Param::number("layer_height", "--layer-height", "Layer height")
        .unit("mm")
        .range(Some(0.0), None, (true, false))
        .step(0.05)
        .default(ParamDefault::Number(DEFAULT_LAYER_HEIGHT))
        .help("the layer height you will slice with (the anchor's thickness and first layer)"),
    Param::number("anchor", "--anchor", "Anchor")
        .choices(&["auto", "on", "off"])
        .default(ParamDefault::Text("auto"))
        .help("a removable one-layer slab under a warped bottom that is not flat"),
    Param::number("layer_thickness", "--layer-thickness", "Layer thickness")
        .unit("mm")
        .range(Some(0.0), None, (true, false))
        .step(0.01)
        .optional()
        .help("the layer thickness along the tool axis; the layer height to slice with is computed from it (h = t/cos tilt on shear warps, Slicer4RTN's conic layer height) and replaces --layer-height"),
    Param::number("thickness_at_tilt", "--thickness-at-tilt", "Thickness at tilt")
        .unit("deg")
        .range(Some(0.0), Some(90.0), (false, true))
        .step(1.0)
        .optional()
        .help("with --layer-thickness: the tilt where the thickness holds (default: the model's largest tilt; shear warps only)"),
];

/// What the warp step did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WarpReport {
    /// What the input STL held and what is wrong with it.
    pub mesh: MeshReport,
    /// What the subdivision before warping did.
    pub subdivide: SubdivideStats,
    /// Anchor slab thickness, if one was added.
    pub anchor: Option<f64>,
    /// Bounding box of the warped part in STL coordinates.
    pub warped_bbox: Aabb,
    /// Largest angle between the tool axis and vertical over the mesh's vertices, degrees.
    pub largest_tilt_deg: f64,
    /// Triangles written (part + anchor).
    pub triangles_out: usize,
    /// The layer height to slice with, mm (the job's; computed from `layer_thickness` when
    /// given).
    #[serde(default)]
    pub layer_height: f64,
    /// With `--layer-thickness`: the thickness along the tool axis, the tilt where it holds
    /// (degrees) and `|∇T_z|` there.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer_thickness: Option<LayerThickness>,
    /// What the user should look at although the STL was written: what the STL reader
    /// tolerated in the model (`model: …`, also in `mesh.warnings`), a capped subdivision.
    #[serde(default)]
    pub warnings: Vec<String>,
}

/// What `--layer-thickness` asked and gave ([`crate::warp::thickness`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LayerThickness {
    /// The thickness along the tool axis asked, mm.
    pub thickness: f64,
    /// The tilt from vertical where it holds, degrees.
    pub at_tilt_deg: f64,
    /// `|∇T_z|` there: vertical layer height = thickness × factor (before rounding).
    pub factor: f64,
}

/// Result of the warp step.
#[derive(Clone, Debug)]
pub struct WarpOutput {
    /// The warped binary STL.
    pub stl: Vec<u8>,
    /// The job to slice and unwarp with (also written as `WARPED.job.json`).
    pub job: Job,
    /// What the warp step did.
    pub report: WarpReport,
}

fn check_positive(name: &'static str, v: f64) -> Result<(), Error> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::Option {
            name,
            value: v.to_string(),
            allowed: "a positive number (mm)",
        })
    }
}

/// The named error of a `--layer-thickness` that gives no layer height.
fn thickness_error(e: crate::warp::thickness::ThicknessError) -> Error {
    use crate::warp::thickness::ThicknessError as T;
    match e {
        T::Thickness(v) => Error::Option {
            name: "layer-thickness",
            value: v.to_string(),
            allowed: "a positive number (mm)",
        },
        T::Tilt(v) => Error::Option {
            name: "thickness-at-tilt",
            value: v.to_string(),
            allowed: "a tilt from 0 up to (not including) 90 degrees",
        },
        T::TiltOfRadialWarp => Error::Option {
            name: "thickness-at-tilt",
            value: "given".into(),
            allowed: "only with a shear warp (curved, tilted, conic, belt): the cylindrical and spherical warps' layers are as thick as the layer height at every tilt; leave it out",
        },
    }
}

/// The model-frame translation of a mesh: centre of the XY bbox to (0, 0), lowest point to z = 0.
pub fn input_to_model(bbox: &Aabb) -> DVec3 {
    let c = bbox.center();
    DVec3::new(-c.x, -c.y, -bbox.min.z)
}

/// Warp an STL: read, move to the model frame, subdivide, warp, add the anchor if needed,
/// lift to z ≥ 0 and write the warped STL and its job.
pub fn warp_model(stl: &[u8], opts: &WarpOptions) -> Result<WarpOutput, Error> {
    warp_model_capped(stl, opts, mesh::subdivide::MAX_TRIANGLES)
}

/// [`warp_model`] with the subdivision's triangle cap `max_triangles` instead of
/// [`mesh::subdivide::MAX_TRIANGLES`] (tests reach it on a small model). When a cap stops the
/// subdivision, the job records what was achieved ([`crate::mesh::achieved`]) and the report
/// warns.
pub fn warp_model_capped(
    stl: &[u8],
    opts: &WarpOptions,
    max_triangles: usize,
) -> Result<WarpOutput, Error> {
    check_positive("max-edge", opts.max_edge)?;
    check_positive("tolerance", opts.tolerance)?;
    check_positive("layer-height", opts.layer_height)?;
    let (mut model, mesh_report) = mesh::read_stl(stl)?;
    let size = mesh_report.bbox.size();
    let min = crate::tolerance::MIN_MODEL_SIZE;
    if size.x.max(size.y) < min || size.z < min {
        return Err(mesh::MeshError::TooSmall {
            size: size.to_array(),
            min,
        }
        .into());
    }
    let t = input_to_model(&mesh_report.bbox);
    model.translate(t);
    let model_bbox = model.bbox();
    let mut params = opts.warp.clone();
    let warp = params.build(&model_bbox)?;

    let sub = SubdivideOptions {
        max_edge: opts.max_edge,
        tolerance: opts.tolerance,
    };
    let (model, warped_vertices, stats) =
        mesh::subdivide::subdivide_warped_capped(&model, &sub, &|p| warp.forward(p), max_triangles);
    let achieved = stats.limit_hit.map(|limit| {
        crate::mesh::achieved::measure(
            &model,
            &warped_vertices,
            &|p| warp.forward(p),
            limit,
            opts.max_edge,
            opts.tolerance,
        )
    });
    // what the STL reader tolerated (trailing bytes, a missing `endsolid`, flipped normals)
    let mut warnings: Vec<String> = mesh_report
        .warnings
        .iter()
        .map(|w| format!("model: {w}"))
        .collect();
    if let Some(a) = achieved {
        let cap = match a.limit {
            mesh::subdivide::SubdivideLimit::Triangles => {
                format!("the triangle cap ({max_triangles} triangles)")
            }
            mesh::subdivide::SubdivideLimit::Passes => {
                format!("the pass cap ({} passes)", mesh::subdivide::MAX_PASSES)
            }
        };
        warnings.push(format!(
            "the subdivision stopped at {cap} before --max-edge {} and --tolerance {} held: edges up to {:.3} mm (median {:.3} mm) and warped chords up to {:.4} mm from the warped surface{} — the warped STL's layers are coarser than asked; scale the model down, raise --max-edge (or --tolerance), or split the model",
            opts.max_edge,
            opts.tolerance,
            a.max_edge,
            a.median_edge,
            a.worst_deviation,
            if a.bounds_met { " (both bounds hold nevertheless)" } else { "" }
        ));
    }
    let mut warped = Mesh {
        vertices: warped_vertices,
        triangles: model.triangles.clone(),
    };
    let min_nz = model
        .vertices
        .iter()
        .map(|&p| warp.tool_axis(p).z)
        .fold(1.0, f64::min);
    let largest_tilt_deg = crate::num::deg(crate::num::acos(min_nz.clamp(-1.0, 1.0)));
    let (layer_height, layer_thickness) = match opts.layer_thickness {
        None => (opts.layer_height, None),
        Some(t) => {
            let v = crate::warp::thickness::vertical_layer_height(
                &*warp,
                params.spec.is_shear(),
                &model.vertices,
                t,
                opts.thickness_at_tilt,
            )
            .map_err(thickness_error)?;
            let lt = LayerThickness {
                thickness: t,
                at_tilt_deg: v.at_tilt_deg,
                factor: v.factor,
            };
            (v.layer_height, Some(lt))
        }
    };

    let part_bbox_t = warped.bbox();
    let anchor = match opts.anchor {
        AnchorMode::On => true,
        AnchorMode::Off => false,
        AnchorMode::Auto => anchor::needs_anchor(&warped, layer_height),
    };
    let mut anchor_thickness = None;
    if anchor && anchor::add_slab(&mut warped, part_bbox_t.min.z, layer_height) {
        anchor_thickness = Some(layer_height);
    }
    let stl_z_offset = -part_bbox_t.min.z + anchor_thickness.unwrap_or(0.0);
    warped.translate(DVec3::new(0.0, 0.0, stl_z_offset));
    let warped_bbox = Aabb {
        min: part_bbox_t.min + DVec3::new(0.0, 0.0, stl_z_offset),
        max: part_bbox_t.max + DVec3::new(0.0, 0.0, stl_z_offset),
    };

    let mut job = Job {
        version: env!("CARGO_PKG_VERSION").to_string(),
        format: JOB_FORMAT,
        warp: params,
        input_to_model: t.to_array(),
        model_bbox,
        stl_z_offset,
        warped_bbox,
        layer_height,
        layer_thickness: layer_thickness.map(|l| l.thickness),
        thickness_at_tilt_deg: layer_thickness.map(|l| l.at_tilt_deg),
        anchor: anchor_thickness,
        max_edge: opts.max_edge,
        tolerance: opts.tolerance,
        subdivision_achieved: achieved,
        input_hash: format!("{:016x}", fnv1a64(stl)),
        hash: String::new(),
    };
    job.seal();
    let header = format!("warpslice job {} {}", job.hash, job.warp.spec.name());
    let out = mesh::write_stl(&warped, &header);
    let report = WarpReport {
        mesh: mesh_report,
        subdivide: stats,
        anchor: anchor_thickness,
        warped_bbox,
        largest_tilt_deg,
        triangles_out: warped.triangles.len(),
        layer_height,
        layer_thickness,
        warnings,
    };
    Ok(WarpOutput {
        stl: out,
        job,
        report,
    })
}
