//! What can go wrong when running a slicer, and the slicers' own refusals recognised in their
//! output.

use super::{SlicerKind, SlicerWarning};
use std::fmt;
use std::path::PathBuf;

/// Lines of slicer output kept in [`SlicerError::Failed`].
pub const OUTPUT_TAIL_LINES: usize = 12;
/// Characters kept of each such line (CuraEngine prints its whole settings list on one line).
pub const OUTPUT_TAIL_LINE_CHARS: usize = 240;

/// An error of the slicer driver. Every message says what to do.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SlicerError {
    /// The slicer name is not one of `prusaslicer`, `slic3r`, `curaengine`.
    UnknownSlicer {
        /// The name given.
        name: String,
    },
    /// An option value is out of range.
    InvalidOption {
        /// Which option.
        option: &'static str,
        /// The value given.
        value: String,
        /// What is accepted.
        expected: &'static str,
    },
    /// The slicer's executable was not found.
    NotInstalled {
        /// Which slicer.
        slicer: SlicerKind,
        /// Where it was looked for.
        searched: String,
        /// How to install it.
        hint: &'static str,
    },
    /// CuraEngine is present but its definitions (`fdmprinter.def.json`) are not.
    CuraDefinitionsMissing {
        /// The resource folders tried, in order.
        searched: Vec<PathBuf>,
    },
    /// A file could not be read, written or run.
    Io {
        /// The file.
        path: PathBuf,
        /// What was being done.
        action: &'static str,
        /// The operating system's message.
        message: String,
    },
    /// The slicer ran longer than the timeout and was killed.
    TimedOut {
        /// Which slicer.
        slicer: SlicerKind,
        /// The timeout, s.
        seconds: f64,
    },
    /// The slicer refused the model for a known reason.
    Refused {
        /// Which slicer.
        slicer: SlicerKind,
        /// The slicer's own message.
        message: String,
        /// What the user can change.
        advice: &'static str,
    },
    /// The slicer exited with an error not recognised.
    Failed {
        /// Which slicer.
        slicer: SlicerKind,
        /// Its exit status.
        status: String,
        /// The last meaningful lines of its output.
        output_tail: String,
    },
    /// The slicer exited successfully but wrote no (or empty) G-code.
    NoOutput {
        /// Which slicer.
        slicer: SlicerKind,
        /// Where the G-code should be.
        gcode_out: PathBuf,
        /// The last meaningful lines of its output.
        output_tail: String,
    },
}

impl fmt::Display for SlicerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SlicerError::UnknownSlicer { name } => write!(
                f,
                "unknown slicer '{name}': use prusaslicer, slic3r or curaengine"
            ),
            SlicerError::InvalidOption {
                option,
                value,
                expected,
            } => write!(f, "{option} is '{value}': expected {expected}"),
            SlicerError::NotInstalled {
                slicer,
                searched,
                hint,
            } => write!(
                f,
                "{slicer} is not installed (looked for {searched}): install it with `{hint}` \
                 (or `bash scripts/setup.sh`), or point {} at its executable",
                slicer.env_override()
            ),
            SlicerError::CuraDefinitionsMissing { searched } => {
                let list: Vec<String> = searched.iter().map(|p| p.display().to_string()).collect();
                write!(
                    f,
                    "CuraEngine's definitions (definitions/fdmprinter.def.json) were not found in \
                     {}: run `bash scripts/setup.sh`, or `apt-get download cura && dpkg-deb -x \
                     cura_*.deb DIR` and set CURA_RES=DIR/usr/share/cura/resources",
                    list.join(", ")
                )
            }
            SlicerError::Io {
                path,
                action,
                message,
            } => write!(f, "could not {action} {}: {message}", path.display()),
            SlicerError::TimedOut { slicer, seconds } => write!(
                f,
                "{slicer} was still running after {seconds:.0} s and was stopped: simplify the \
                 model (larger --max-edge) or raise the timeout"
            ),
            SlicerError::Refused {
                slicer,
                message,
                advice,
            } => write!(
                f,
                "{slicer} refused the model: {message}\n  what to do: {advice}"
            ),
            SlicerError::Failed {
                slicer,
                status,
                output_tail,
            } => write!(
                f,
                "{slicer} failed ({status}); its last output lines:\n{output_tail}\n  \
                 try slicing the warped STL in {slicer} by hand to see the full message"
            ),
            SlicerError::NoOutput {
                slicer,
                gcode_out,
                output_tail,
            } => write!(
                f,
                "{slicer} reported success but wrote no G-code to {}; its last output lines:\n\
                 {output_tail}\n  check that the folder is writable and the model is not empty",
                gcode_out.display()
            ),
        }
    }
}

impl std::error::Error for SlicerError {}

crate::error_codes!(SlicerError, ERROR_CODES, "slicer" {
    UnknownSlicer => "slicer.unknown", "not one of the supported slicers";
    InvalidOption => "slicer.invalid-option", "a slicer option out of range";
    NotInstalled => "slicer.not-installed", "the slicer's executable was not found";
    CuraDefinitionsMissing => "slicer.cura-definitions-missing", "CuraEngine's definitions were not found";
    Io => "slicer.io", "a file could not be read, written or run";
    TimedOut => "slicer.timed-out", "the slicer ran longer than the timeout";
    Refused => "slicer.refused", "the slicer refused the model for a known reason";
    Failed => "slicer.failed", "the slicer failed for a reason not recognised";
    NoOutput => "slicer.no-output", "the slicer wrote no G-code";
} wraps {});

/// A message a slicer prints, and what it means for the user.
struct Known {
    /// `None`: any slicer.
    slicer: Option<SlicerKind>,
    /// Case-sensitive substring of the slicer's output.
    needle: &'static str,
    advice: &'static str,
}

const FIRST_LAYER_ADVICE: &str = "the warped bottom touches the bed only at a point or an edge, \
    so the first layer is empty; use --base z0,z1 (blend the warp back to flat near the bed) or \
    keep the anchor on";
const UNREADABLE_ADVICE: &str = "the slicer could not read the STL; check that it is a valid, \
    non-empty STL (run `warpslice check FILE`)";
const BED_ADVICE: &str = "the warped model is larger than the slicer's 200 x 200 mm bed; pass a \
    larger bed in the extra slicer arguments, e.g. --bed-shape 0x0,400x0,400x400,0x400 for \
    PrusaSlicer, or lower the warp angle";
const EMPTY_LAYER_ADVICE: &str = "the warped model has a gap in z (a part floats above the rest); \
    lower the warp angle, use a smaller --max-edge, or use --base so the bottom stays flat";

/// Refusals: a non-zero exit (or no G-code) with one of these in the output.
const REFUSALS: &[Known] = &[
    Known {
        slicer: Some(SlicerKind::PrusaSlicer),
        needle: "There is an object with no extrusions in the first layer",
        advice: FIRST_LAYER_ADVICE,
    },
    Known {
        slicer: Some(SlicerKind::PrusaSlicer),
        needle: "Empty layers detected",
        advice: EMPTY_LAYER_ADVICE,
    },
    Known {
        slicer: Some(SlicerKind::PrusaSlicer),
        needle: "Objects could not fit on the bed",
        advice: BED_ADVICE,
    },
    Known {
        slicer: Some(SlicerKind::PrusaSlicer),
        needle: "Loading of a model file failed",
        advice: UNREADABLE_ADVICE,
    },
    Known {
        slicer: Some(SlicerKind::Slic3r),
        needle: "Error while reading STL file",
        advice: UNREADABLE_ADVICE,
    },
    Known {
        slicer: Some(SlicerKind::CuraEngine),
        needle: "Failed to load model",
        advice: UNREADABLE_ADVICE,
    },
];

/// Warnings: printed while the slicer still succeeded.
const WARNINGS: &[Known] = &[
    Known {
        slicer: Some(SlicerKind::PrusaSlicer),
        needle: "Empty layer between",
        advice: EMPTY_LAYER_ADVICE,
    },
    Known {
        slicer: Some(SlicerKind::Slic3r),
        needle: "might not fit in the configured bed shape",
        advice: BED_ADVICE,
    },
];

fn applies(k: &Known, slicer: SlicerKind) -> bool {
    match k.slicer {
        None => true,
        Some(s) => s == slicer,
    }
}

/// The whole output line holding `needle`, trimmed and shortened (CuraEngine joins several
/// messages on one line).
fn line_with<'a>(text: &'a str, needle: &str) -> Option<&'a str> {
    text.lines()
        .find(|l| l.contains(needle))
        .map(|l| truncate(l.trim(), OUTPUT_TAIL_LINE_CHARS))
}

fn truncate(s: &str, max_chars: usize) -> &str {
    match s.char_indices().nth(max_chars) {
        Some((i, _)) => &s[..i],
        None => s,
    }
}

/// The first known refusal in `text`, if any.
pub fn recognise_refusal(slicer: SlicerKind, text: &str) -> Option<SlicerError> {
    REFUSALS
        .iter()
        .filter(|k| applies(k, slicer))
        .find_map(|k| {
            line_with(text, k.needle).map(|line| SlicerError::Refused {
                slicer,
                message: line.to_string(),
                advice: k.advice,
            })
        })
}

/// Every known warning in `text`, one per distinct line.
pub fn recognise_warnings(slicer: SlicerKind, text: &str) -> Vec<SlicerWarning> {
    let mut out: Vec<SlicerWarning> = Vec::new();
    for k in WARNINGS.iter().filter(|k| applies(k, slicer)) {
        for line in text.lines().filter(|l| l.contains(k.needle)) {
            let message = truncate(line.trim(), OUTPUT_TAIL_LINE_CHARS).to_string();
            if !out.iter().any(|w| w.message == message) {
                out.push(SlicerWarning {
                    message,
                    advice: k.advice,
                });
            }
        }
    }
    out
}

/// Log noise: PrusaSlicer's timestamped trace lines and progress lines (`90 => Exporting`),
/// Slic3r's progress, CuraEngine's licence banner and settings dumps.
fn is_noise(line: &str) -> bool {
    let t = line.trim();
    if t.is_empty() || t.starts_with("=>") || t.starts_with("[20") {
        return true;
    }
    if let Some((head, _)) = t.split_once(" => ") {
        if head.chars().all(|c| c.is_ascii_digit()) {
            return true;
        }
    }
    if t.contains(" -s ") && !t.contains("[ERROR]") {
        return true;
    }
    const CURA_BANNER: [&str; 8] = [
        "Cura_SteamEngine",
        "Copyright (C)",
        "This program is free software",
        "it under the terms",
        "the Free Software Foundation",
        "(at your option)",
        "WITHOUT ANY WARRANTY",
        "GNU Affero General Public License",
    ];
    CURA_BANNER.iter().any(|b| t.contains(b))
        || t.starts_with("MERCHANTABILITY")
        || t.starts_with("You should have received")
        || t.starts_with("along with this program")
        || t.starts_with("This program is distributed")
}

/// The last [`OUTPUT_TAIL_LINES`] meaningful lines of `text`, each at most
/// [`OUTPUT_TAIL_LINE_CHARS`] characters, indented by two spaces.
pub fn meaningful_tail(text: &str) -> String {
    let lines: Vec<&str> = text.lines().filter(|l| !is_noise(l)).collect();
    let start = lines.len().saturating_sub(OUTPUT_TAIL_LINES);
    if lines.is_empty() {
        return "  (no output)".to_string();
    }
    lines[start..]
        .iter()
        .map(|l| format!("  {}", truncate(l.trim(), OUTPUT_TAIL_LINE_CHARS)))
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression: PrusaSlicer 2.5's output for a warped mesh standing on its tip.
    #[test]
    fn prusaslicer_no_first_layer_extrusions_is_a_refusal_with_base_advice() {
        let text = "[2026-11-22 00:05:26.694074] [0x00007fb6dce8fd80] [trace]   Initializing\n\
                    90 => Exporting G-code to tip.gcode\n\
                    There is an object with no extrusions in the first layer.\n\
                    Object name: tip.stl\n";
        match recognise_refusal(SlicerKind::PrusaSlicer, text) {
            Some(SlicerError::Refused {
                message, advice, ..
            }) => {
                assert_eq!(
                    message,
                    "There is an object with no extrusions in the first layer."
                );
                assert!(advice.contains("--base"));
            }
            other => panic!("expected a refusal, got {other:?}"),
        }
        // The same text from another slicer is not claimed as PrusaSlicer's refusal.
        assert!(recognise_refusal(SlicerKind::Slic3r, text).is_none());
    }

    #[test]
    fn prusaslicer_empty_layer_is_a_warning() {
        let text = "Print warning: Empty layer between 5 and 8.2.\n\nObject name: gap.stl\n";
        let w = recognise_warnings(SlicerKind::PrusaSlicer, text);
        assert_eq!(w.len(), 1);
        assert_eq!(
            w[0].message,
            "Print warning: Empty layer between 5 and 8.2."
        );
        assert!(recognise_refusal(SlicerKind::PrusaSlicer, text).is_none());
    }

    #[test]
    fn cura_error_inside_a_long_line_is_found_and_shortened() {
        let long = format!(
            "[WARNING] Unable to recognize the extension.[ERROR] Failed to load model: x.stl. {}",
            "y".repeat(1000)
        );
        match recognise_refusal(SlicerKind::CuraEngine, &long) {
            Some(SlicerError::Refused { message, .. }) => {
                assert_eq!(message.chars().count(), OUTPUT_TAIL_LINE_CHARS);
            }
            other => panic!("expected a refusal, got {other:?}"),
        }
    }

    #[test]
    fn tail_drops_noise_and_keeps_the_last_lines() {
        let mut text = String::from("Cura_SteamEngine version 4.13.0\n10 => Processing\n");
        for i in 0..20 {
            text.push_str(&format!("line {i}\n"));
        }
        let tail = meaningful_tail(&text);
        assert_eq!(tail.lines().count(), OUTPUT_TAIL_LINES);
        assert!(tail.ends_with("  line 19"));
        assert!(!tail.contains("Processing"));
        assert_eq!(meaningful_tail("\n\n"), "  (no output)");
    }

    #[test]
    fn truncate_respects_char_boundaries() {
        assert_eq!(truncate("ééé", 2), "éé");
        assert_eq!(truncate("ab", 5), "ab");
    }
}
