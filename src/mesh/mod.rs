//! Triangle meshes: read and write STL, report defects, subdivide before warping.
//!
//! A [`Mesh`] is indexed (shared vertices), f64, in whatever frame its producer says.

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub mod achieved;
mod edges;
mod fxhash;
pub mod report;
pub mod shapes;
pub mod stl;
mod stl_ascii;
pub mod subdivide;

pub use report::MeshReport;
pub use stl::{read_stl, write_stl, StlFormat};
pub use subdivide::{
    subdivide, subdivide_warped, SubdivideLimit, SubdivideOptions, SubdivideStats,
};

/// An indexed triangle mesh (counter-clockwise triangles seen from outside).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions, mm (each stored once, shared by the triangles that use it).
    pub vertices: Vec<DVec3>,
    /// Triangles as indices into `vertices`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// An axis-aligned bounding box, mm.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    /// Lowest corner (smallest x, y, z), mm.
    pub min: DVec3,
    /// Highest corner (largest x, y, z), mm.
    pub max: DVec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The empty box (min = +∞, max = −∞); `include` grows it.
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };

    /// Grow the box to contain `p`.
    pub fn include(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }
    /// Whether the box contains no point (some min > max, or a NaN): e.g. [`Aabb::EMPTY`].
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }
    /// Edge lengths along x, y, z (`max − min`), mm.
    pub fn size(&self) -> DVec3 {
        self.max - self.min
    }
    /// The centre point `(min + max) / 2`, mm.
    pub fn center(&self) -> DVec3 {
        (self.min + self.max) * 0.5
    }
    /// The smallest box containing every point ([`Aabb::EMPTY`] for none).
    pub fn of_points(points: impl IntoIterator<Item = DVec3>) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            b.include(p);
        }
        b
    }
}

impl Mesh {
    /// Bounding box of the vertices that some triangle uses.
    pub fn bbox(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        for t in &self.triangles {
            for &i in t {
                b.include(self.vertices[i as usize]);
            }
        }
        b
    }
    /// The enclosed volume Σ a·(b × c)/6 over the triangles, mm³: positive for a closed mesh
    /// whose triangles are counter-clockwise seen from outside.
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Move every vertex by `d`.
    pub fn translate(&mut self, d: DVec3) {
        for v in &mut self.vertices {
            *v += d;
        }
    }
}

/// Why an STL could not be read. Each message says what to fix.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MeshError {
    /// The file has no bytes.
    Empty,
    /// Binary STL shorter than its header + face count + faces say.
    Truncated {
        /// File size the header's face count requires (header, count and facets), bytes.
        expected_bytes: u64,
        /// The file's actual size, bytes.
        actual_bytes: u64,
    },
    /// Binary STL whose face count disagrees with the file size.
    FaceCountMismatch {
        /// Face count stored in the binary header.
        header_count: u64,
        /// Number of whole 50-byte facet records the bytes after the header hold.
        bytes_for: u64,
    },
    /// A coordinate is NaN or infinite (triangle index, 0-based).
    NonFinite {
        /// 0-based index of the triangle (in file order) with the bad coordinate.
        triangle: usize,
    },
    /// The file holds no triangles.
    NoTriangles,
    /// ASCII STL: a facet with other than three vertices (1-based line number).
    NotATriangle {
        /// 1-based line number of the facet's `facet` keyword.
        line: usize,
        /// Number of `vertex` lines the facet holds (not 3).
        vertices: usize,
    },
    /// The model is smaller than anything a slicer prints (a model in metres, or scaled wrong).
    TooSmall {
        /// Its size x, y, z, mm.
        size: [f64; 3],
        /// The smallest accepted width (x or y) and height, mm.
        min: f64,
    },
    /// The file is another kind of file (its first bytes are another format's signature).
    NotStl {
        /// What it looks like (e.g. "a PNG image").
        looks_like: &'static str,
    },
    /// ASCII STL that does not parse (1-based line number and what was found).
    Syntax {
        /// 1-based line number where the ASCII STL stops parsing.
        line: usize,
        /// What was expected and what was found instead.
        message: String,
    },
}

impl std::fmt::Display for MeshError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MeshError::Empty => write!(f, "the STL file is empty (0 bytes): export the model again"),
            MeshError::Truncated { expected_bytes, actual_bytes } => write!(
                f,
                "the binary STL is truncated: its header announces {expected_bytes} bytes but the file has {actual_bytes}; export it again"
            ),
            MeshError::FaceCountMismatch { header_count, bytes_for } => write!(
                f,
                "the binary STL's face count says {header_count} triangles but the file holds {bytes_for}; export it again"
            ),
            MeshError::NonFinite { triangle } => write!(
                f,
                "triangle {triangle} has a non-finite coordinate (NaN or infinity); repair the model"
            ),
            MeshError::NoTriangles => write!(f, "the STL holds no triangles"),
            MeshError::NotATriangle { line, vertices } => write!(
                f,
                "line {line}: a facet with {vertices} vertices; STL facets must be triangles"
            ),
            MeshError::Syntax { line, message } => write!(f, "line {line}: {message}"),
            MeshError::TooSmall { size, min } => write!(
                f,
                "the model is {} × {} × {} mm: smaller than a printed line ({min} mm), a slicer prints nothing of it — is it in metres (scale ×1000) or inches (×25.4)? Scale it in your CAD program or slicer and export again",
                size[0], size[1], size[2]
            ),
            MeshError::NotStl { looks_like } => write!(
                f,
                "this is not an STL file: it starts like {looks_like}; export the model as STL (binary, or ASCII in UTF-8/ASCII) and open that"
            ),
        }
    }
}

impl std::error::Error for MeshError {}

crate::error_codes!(MeshError, ERROR_CODES, "mesh" {
    Empty => "mesh.empty", "the STL file has no bytes";
    Truncated => "mesh.truncated", "a binary STL shorter than its header says";
    FaceCountMismatch => "mesh.face-count", "a binary STL whose face count disagrees with its size";
    NonFinite => "mesh.non-finite", "a coordinate is NaN or infinite";
    NoTriangles => "mesh.no-triangles", "the file holds no triangles";
    NotATriangle => "mesh.not-a-triangle", "an ASCII facet with other than three vertices";
    Syntax => "mesh.syntax", "an ASCII STL line that does not parse";
    TooSmall => "mesh.too-small", "the model is smaller than a printed line (metres or inches?)";
    NotStl => "mesh.not-stl", "the file is another format (an image, a text in UTF-16, an archive)";
} wraps {});
