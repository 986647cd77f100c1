//! STL in (ASCII and binary, via stl_io) and out (binary). STUB: being written.

use super::{Mesh, MeshError, MeshReport};

/// Which kind of STL a file was.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StlFormat {
    Ascii,
    Binary,
    /// Binary whose 80-byte header starts with `solid`.
    BinarySolidHeader,
}

/// Read an STL (input frame). Defects are counted in the report, not refused.
pub fn read_stl(_bytes: &[u8]) -> Result<(Mesh, MeshReport), MeshError> {
    Err(MeshError::Empty)
}

/// Write a binary STL whose 80-byte header holds `header` (truncated to 80 bytes).
pub fn write_stl(_mesh: &Mesh, _header: &str) -> Vec<u8> {
    Vec::new()
}
