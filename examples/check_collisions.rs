//! The collision check over machine G-code files, with its speed: `cargo run --release
//! --example check_collisions -- PRESET FILE.gcode [PRESET FILE.gcode …]`. Prints, per file,
//! the findings by head part and obstacle, the first three, the moves and poses checked, and
//! the time (MB/s of G-code).

use std::collections::BTreeMap;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 || !args.len().is_multiple_of(2) {
        eprintln!("usage: check_collisions PRESET FILE.gcode [PRESET FILE.gcode …]");
        std::process::exit(2);
    }
    for pair in args.chunks(2) {
        let spec = match warpslice::machine::preset(&pair[0]) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        };
        let bytes = std::fs::read(&pair[1]).expect("read the G-code");
        let t = Instant::now();
        match warpslice::collision::check_gcode(&bytes, &spec) {
            Err(e) => println!("{} {}: {e}", pair[0], pair[1]),
            Ok((f, stats)) => {
                let dt = t.elapsed().as_secs_f64();
                let mut by: BTreeMap<(String, String), (usize, f64)> = BTreeMap::new();
                for x in &f {
                    let e = by.entry((x.part.clone(), x.obstacle.clone())).or_default();
                    e.0 += 1;
                    e.1 = e.1.max(x.depth_mm);
                }
                println!(
                    "{} {}: {} findings; {} moves, {} poses, {} under-sampled; {:.3} s, {:.1} MB/s",
                    pair[0],
                    pair[1],
                    f.len(),
                    stats.moves,
                    stats.samples,
                    stats.under_sampled,
                    dt,
                    bytes.len() as f64 / 1e6 / dt
                );
                for ((part, obstacle), (n, d)) in by {
                    println!("    {part} into {obstacle}: {n} moves, deepest {d:.3} mm");
                }
                for x in f.iter().take(3) {
                    println!(
                        "    line {} layer {}: {} into {} {:.3} mm at ({:.2}, {:.2}, {:.2})",
                        x.line, x.layer, x.part, x.obstacle, x.depth_mm, x.at[0], x.at[1], x.at[2]
                    );
                }
            }
        }
    }
}
