//! A warped 20 mm cube through the CLI with the synthetic slicer's G-code (no real slicer: a
//! test using it cannot skip), and the machine presets with a warp each prints, where the part
//! goes, and the axis letters docs/machines.md gives them.

use std::path::PathBuf;
use std::process::Command;

use super::synthetic;

const CLI: &str = env!("CARGO_BIN_EXE_warpslice");

pub fn run(args: &[&str]) -> std::process::Output {
    Command::new(CLI).args(args).output().expect("run the CLI")
}

pub fn ok(args: &[&str]) -> String {
    let o = run(args);
    assert!(
        o.status.success(),
        "warpslice {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A warped 20 mm cube, the synthetic slicer's G-code of it, in a fresh directory.
pub struct Part {
    pub dir: PathBuf,
}

impl Part {
    pub fn new(tag: &str, warp: &[&str]) -> Part {
        let dir =
            std::env::temp_dir().join(format!("warpslice-config-{}-{tag}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = |f: &str| dir.join(f).to_str().unwrap().to_string();
        ok(&["example", "cube", "-o", &p("cube.stl")]);
        let mut args = vec!["warp".to_string(), p("cube.stl")];
        args.extend(warp.iter().map(|s| s.to_string()));
        args.extend(["-o".to_string(), p("W.stl")]);
        ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
        let job =
            warpslice::job::Job::from_json(&std::fs::read_to_string(p("W.job.json")).unwrap())
                .unwrap();
        std::fs::write(p("W.gcode"), synthetic::gcode(&job, true, 1.0)).unwrap();
        Part { dir }
    }

    pub fn path(&self, f: &str) -> String {
        self.dir.join(f).to_str().unwrap().to_string()
    }

    /// `unwarp … --config-out` with `flags`: (G-code, configuration, stdout); `Err(stderr)`
    /// when refused (and then no configuration file may exist).
    pub fn unwarp(&self, name: &str, flags: &[&str]) -> Result<(String, String, String), String> {
        let (g, c) = (
            self.path(&format!("{name}.gcode")),
            self.path(&format!("{name}.cfg")),
        );
        let mut args = vec![
            "unwarp",
            "W.gcode",
            "--job",
            "W.job.json",
            "--offset",
            "100,100",
            "-o",
            &g,
            "--config-out",
            &c,
        ];
        let gc = self.path("W.gcode");
        let jb = self.path("W.job.json");
        args[1] = &gc;
        args[3] = &jb;
        args.extend_from_slice(flags);
        let o = run(&args);
        if !o.status.success() {
            assert!(
                !std::path::Path::new(&c).exists(),
                "a refused run wrote its configuration"
            );
            return Err(String::from_utf8_lossy(&o.stderr).into_owned());
        }
        Ok((
            std::fs::read_to_string(&g).unwrap(),
            std::fs::read_to_string(&c).unwrap(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
        ))
    }
}

impl Drop for Part {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// docs/machines.md: each preset's axis letters, and which of them turn.
pub fn documented(preset: &str) -> (&'static str, &'static str) {
    match preset {
        "cartesian" => ("XYZ", ""),
        "fullcontrol-prusa-b" => ("XYZB", "B"),
        "rtn-slicer4rtn" => ("XYZA", "A"),
        "rotbot" => ("XYZU", "U"),
        "pax-5axis" | "open5x-ab" => ("XYZAB", "AB"),
        // Open5x's published configurations: U V turn but its Duet 2 config.g creates them
        // linear (no R1), so RepRapFirmware and Marlin are told they are linear
        "open5x-prusa-uv" => ("XYZUV", ""),
        "open5x-jubilee-bc" => ("XYZBC", "BC"),
        "ratrig-vcore3-3z" => ("XYZUV", ""),
        "core-r-theta" => ("XCZB", "CB"),
        "lathe" => ("XZA", "A"),
        _ => unreachable!("{preset}"),
    }
}

/// The presets with a warp each prints and where the part goes (the README's commands).
pub fn cases() -> Vec<(&'static str, Vec<&'static str>, Vec<&'static str>)> {
    let conic25 = vec!["--warp", "conic", "--angle", "25", "--center", "-15,0"];
    let curved = vec!["--warp", "curved", "--strength", "0.3"];
    vec![
        ("cartesian", curved.clone(), vec![]),
        ("fullcontrol-prusa-b", curved, vec![]),
        (
            "rtn-slicer4rtn",
            vec!["--warp", "conic", "--angle", "45", "--center", "-15,0"],
            vec![],
        ),
        (
            "rotbot",
            vec!["--warp", "conic", "--angle", "45", "--center", "0,0"],
            vec![],
        ),
        ("pax-5axis", conic25.clone(), vec![]),
        ("open5x-ab", conic25.clone(), vec!["--place", "0,0"]),
        ("open5x-prusa-uv", conic25.clone(), vec!["--place", "0,0"]),
        ("open5x-jubilee-bc", conic25.clone(), vec!["--place", "0,0"]),
        (
            "ratrig-vcore3-3z",
            vec!["--warp", "belt", "--angle", "20"],
            vec![],
        ),
        ("core-r-theta", conic25, vec!["--place", "60,0"]),
        (
            "lathe",
            vec!["--warp", "cylindrical", "--radius", "20"],
            vec!["--place", "0,0"],
        ),
    ]
}

/// The `--machine` argument of a case: the preset's name, or for `lathe` the README's
/// lathe.json (the `lathe-a` preset with the mandrel 20 mm under the part), written into the
/// part's directory.
pub fn machine_arg(part: &Part, preset: &str) -> String {
    if preset != "lathe" {
        return preset.to_string();
    }
    let mut spec = warpslice::machine::preset("lathe-a").unwrap();
    if let warpslice::machine::spec::Kinematics::LatheA(p) = &mut spec.kinematics {
        p.axis_z_mm = -20.0;
    }
    let f = part.path("lathe.json");
    std::fs::write(&f, spec.to_json()).unwrap();
    f
}
