//! The fitted field's convergence (not a test): `cargo run --release --example field_fit --
//! MODEL.stl PRESET [θ]` runs `suggest`'s search with every family and prints the fit's
//! objective J = A + λ·R (mm²) at the start and after each sweep of its pattern search, the
//! candidates measured, the best family warp's overhang area and the fitted field's.

use warpslice::suggest::admissible::MachineLimits;
use warpslice::suggest::family::Family;
use warpslice::suggest::search::Search;
use warpslice::suggest::{model_of, FAMILIES};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(path), Some(preset)) = (args.first(), args.get(1)) else {
        eprintln!("usage: field_fit MODEL.stl PRESET [overhang angle, deg]");
        std::process::exit(2);
    };
    let theta: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(45.0);
    let bytes = std::fs::read(path).expect("read the model");
    let model = model_of(&bytes).expect("a model");
    let spec = warpslice::machine::preset(preset).expect("a preset");
    let limits = MachineLimits::new(&spec).expect("the machine");
    let t = std::time::Instant::now();
    let mut search = Search::new(&model, &limits, theta, 0.2);
    let ranked = search.run(FAMILIES);
    let secs = t.elapsed().as_secs_f64();
    for (k, j) in search.fit_trace().iter().enumerate() {
        println!("sweep {k:3}: J = {j:.6} mm²");
    }
    let best = |field: bool| {
        ranked
            .iter()
            .find(|c| (c.point.family == Family::Field) == field)
            .map(|c| (c.area_mm2, c.flags.clone()))
    };
    println!("best family warp: {:?}", best(false));
    println!("fitted field: {:?}", best(true).map(|b| b.0));
    println!(
        "search {:.2} s, {} candidates measured",
        secs,
        search.measured()
    );
}
