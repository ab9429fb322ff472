//! Reader check: every GTSPLIB best-known tour in `<dir>/tours/` must be a
//! feasible g-tour whose re-evaluated cost equals the value in its file
//! name and in `best_known.csv`.
//!
//! ```text
//! cargo run --release -p strider-plan --example check_tours -- [/work/shared/data/gtsplib]
//! ```

use std::collections::HashMap;
use std::path::PathBuf;

use strider_plan::tsplib::{read_instance_file, read_tour_file};

fn main() {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or("/work/shared/data/gtsplib".into()),
    );
    let csv = std::fs::read_to_string(dir.join("best_known.csv")).expect("best_known.csv");
    let best: HashMap<String, i64> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].to_string(), f[3].parse().unwrap())
        })
        .collect();
    let mut files: Vec<_> = std::fs::read_dir(dir.join("tours"))
        .expect("tours/")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "tour"))
        .collect();
    files.sort();
    let mut bad = 0;
    for f in &files {
        let stem = f.file_name().unwrap().to_string_lossy().to_string();
        let mut parts = stem.split('.');
        let name = parts.next().unwrap();
        let value: i64 = parts.next().unwrap().parse().unwrap();
        let inst = read_instance_file(dir.join(format!("{name}.gtsp"))).expect("instance");
        let tour = read_tour_file(f).expect("tour");
        let feasible = inst.check_tour(&tour);
        let cost = inst.tour_cost(&tour);
        let ok = feasible.is_ok() && cost == value && best.get(name) == Some(&value);
        if !ok {
            bad += 1;
        }
        println!(
            "{name:<12} tour={value:<8} recomputed={cost:<8} {}",
            if ok { "ok" } else { "MISMATCH" }
        );
    }
    for extra in [
        "glns_examples/39rat195.gtsp",
        "glns_examples/107si535.gtsp",
        "glns_examples/207si1032.gtsp",
    ] {
        let inst = read_instance_file(dir.join(extra)).expect("glns example");
        println!(
            "{extra}: n={} sets={} symmetric={}",
            inst.n,
            inst.sets.len(),
            inst.symmetric
        );
    }
    let tiny = read_instance_file(dir.join("glns_examples/tiny.gtsp")).expect("tiny");
    let sol = strider_plan::solve(&tiny, &Default::default()).unwrap();
    println!(
        "glns_examples/tiny.gtsp: optimum {} tour {:?}",
        sol.cost, sol.tour
    );
    println!("tours={} mismatches={bad}", files.len());
    assert_eq!(bad, 0);
}
