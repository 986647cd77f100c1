//! Finding the slicer executables and CuraEngine's definitions.

use super::{SlicerError, SlicerKind};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};

/// Where the Cura resources are looked for when neither an override nor `CURA_RES` is given:
/// the folder `scripts/setup.sh` extracts the `cura` package into, then Debian's own.
pub const CURA_RES_FALLBACKS: [&str; 2] = [
    "/opt/cura-res/usr/share/cura/resources",
    "/usr/share/cura/resources",
];

/// The file that marks a Cura resources folder.
const CURA_MARKER: &str = "definitions/fdmprinter.def.json";

/// Finds the executable of `kind`: `override_exe` if given, else the environment variable
/// [`SlicerKind::env_override`], else [`SlicerKind::executable_name`] on `PATH`.
pub fn find_executable(
    kind: SlicerKind,
    override_exe: Option<&Path>,
) -> Result<PathBuf, SlicerError> {
    let from_env = std::env::var_os(kind.env_override()).filter(|v| !v.is_empty());
    let path_var = std::env::var_os("PATH");
    resolve(
        kind,
        override_exe.map(Path::as_os_str).or(from_env.as_deref()),
        path_var.as_deref(),
    )
}

/// Pure lookup: `wanted` (a path if it holds a `/`, else a name) or the default name, searched
/// in the `:`-separated `path_var`.
pub fn resolve(
    kind: SlicerKind,
    wanted: Option<&OsStr>,
    path_var: Option<&OsStr>,
) -> Result<PathBuf, SlicerError> {
    let name = wanted.unwrap_or(OsStr::new(kind.executable_name()));
    let as_path = Path::new(name);
    let not_installed = |searched: String| SlicerError::NotInstalled {
        slicer: kind,
        searched,
        hint: kind.install_hint(),
    };
    if as_path.components().count() > 1 || as_path.is_absolute() {
        return if is_executable(as_path) {
            Ok(as_path.to_path_buf())
        } else {
            Err(not_installed(as_path.display().to_string()))
        };
    }
    let dirs: Vec<PathBuf> = path_var
        .map(|p| std::env::split_paths(p).collect())
        .unwrap_or_default();
    dirs.iter()
        .map(|d| d.join(name))
        .find(|candidate| is_executable(candidate))
        .ok_or_else(|| not_installed(format!("'{}' on PATH", as_path.display())))
}

#[cfg(unix)]
fn is_executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

#[cfg(not(unix))]
fn is_executable(p: &Path) -> bool {
    p.is_file()
}

/// The Cura resources folder (holding `definitions/fdmprinter.def.json`): `override_dir` if
/// given, else the environment variable `CURA_RES`, else [`CURA_RES_FALLBACKS`]. An explicit
/// folder that lacks the definitions is an error, not skipped.
pub fn cura_resources(override_dir: Option<&Path>) -> Result<PathBuf, SlicerError> {
    let env = std::env::var_os("CURA_RES").filter(|v| !v.is_empty());
    let explicit: Option<PathBuf> = override_dir
        .map(Path::to_path_buf)
        .or(env.map(PathBuf::from));
    let candidates: Vec<PathBuf> = match explicit {
        Some(dir) => vec![dir],
        None => CURA_RES_FALLBACKS.iter().map(PathBuf::from).collect(),
    };
    candidates
        .iter()
        .find(|dir| dir.join(CURA_MARKER).is_file())
        .cloned()
        .ok_or(SlicerError::CuraDefinitionsMissing {
            searched: candidates,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bogus_absolute_override_is_not_installed() {
        let r = resolve(
            SlicerKind::Slic3r,
            Some(OsStr::new("/nonexistent/dir/slic3r")),
            Some(OsStr::new("/usr/bin:/bin")),
        );
        match r {
            Err(SlicerError::NotInstalled {
                slicer, searched, ..
            }) => {
                assert_eq!(slicer, SlicerKind::Slic3r);
                assert_eq!(searched, "/nonexistent/dir/slic3r");
            }
            other => panic!("expected NotInstalled, got {other:?}"),
        }
    }

    #[test]
    fn name_is_searched_on_path_in_order() {
        // `sh` exists in /bin or /usr/bin on every Unix machine this runs on.
        let found = resolve(
            SlicerKind::PrusaSlicer,
            Some(OsStr::new("sh")),
            Some(OsStr::new("/nonexistent:/bin:/usr/bin")),
        );
        let found = found.unwrap_or_else(|e| panic!("sh not found: {e}"));
        assert!(found.ends_with("sh"));
        assert!(resolve(SlicerKind::PrusaSlicer, Some(OsStr::new("sh")), None).is_err());
    }

    #[test]
    fn a_directory_is_not_an_executable() {
        assert!(resolve(SlicerKind::CuraEngine, Some(OsStr::new("/tmp")), None).is_err());
    }

    #[test]
    fn explicit_cura_folder_without_definitions_is_reported_not_skipped() {
        let r = cura_resources(Some(Path::new("/nonexistent/cura")));
        assert_eq!(
            r,
            Err(SlicerError::CuraDefinitionsMissing {
                searched: vec![PathBuf::from("/nonexistent/cura")]
            })
        );
    }
}
