//! The one printing rule of the CLI: reports go to stdout with [`say!`], which ignores a
//! closed pipe (`warpslice … | head` must not panic); errors go to stderr once, from `main`.
//! Files are read and written here, naming the file in every error.

use std::path::Path;

/// `println!` that ignores a closed stdout.
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}
pub(crate) use say;

/// Text that already ends its lines, to stdout (ignoring a closed pipe, like [`say!`]).
pub fn put(text: &str) {
    use std::io::Write as _;
    let _ = std::io::stdout().write_all(text.as_bytes());
}

/// Read a text file, naming it in the error.
pub fn read_text(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// Write a file, naming it in the error.
pub fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))
}
