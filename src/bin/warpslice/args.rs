//! Argument value parsers shared by every subcommand (one set, one wording).

use glam::DVec3;
use warpslice::machine::MachineSpec;

/// Comma-separated finite numbers; names the first that is not one.
pub fn numbers(s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .map(|p| {
            p.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("'{}' is not a number", p.trim()))
        })
        .collect()
}

/// `a,b`.
pub fn pair(s: &str) -> Result<[f64; 2], String> {
    match numbers(s)?.as_slice() {
        [a, b] => Ok([*a, *b]),
        _ => Err(format!("expected two numbers a,b but got '{s}'")),
    }
}

/// `x,y,z`.
pub fn triple(s: &str) -> Result<[f64; 3], String> {
    match numbers(s)?.as_slice() {
        [x, y, z] => Ok([*x, *y, *z]),
        _ => Err(format!("expected three numbers x,y,z but got '{s}'")),
    }
}

/// `x,y,z` as a vector.
pub fn vec3(s: &str) -> Result<DVec3, String> {
    triple(s).map(DVec3::from_array)
}

/// `--machine`: a preset name or a machine JSON file (the core decides which,
/// [`MachineSpec::from_arg`]; this only lends it the filesystem).
pub fn machine_spec(arg: &str) -> Result<MachineSpec, String> {
    MachineSpec::from_arg(arg, |p| {
        std::fs::read_to_string(p).map_err(|e| e.to_string())
    })
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_and_triples_name_what_is_wrong() {
        assert_eq!(pair("-15, 0"), Ok([-15.0, 0.0]));
        assert_eq!(pair("1,x"), Err("'x' is not a number".to_string()));
        assert!(pair("1,2,3").unwrap_err().contains("two numbers"));
        assert_eq!(triple("1,2,3"), Ok([1.0, 2.0, 3.0]));
        assert!(triple("1,2").unwrap_err().contains("three numbers"));
        assert!(pair("inf,1").is_err());
    }
}
