//! Fuzz target: scenario files (TOML plus PNG layers). Every accepted scenario must give a
//! simulator that stands at its start and scans without a panic or an unbounded allocation;
//! every refusal is one clean line.

mod common;

use std::fs;
use std::path::Path;

use strider_fuzz::{Bundle, CappedAlloc, Outcome, config, fuzz};
use strider_scenario::{Scenario, builtin};
use strider_sim::Simulator;

#[global_allocator]
static ALLOC: CappedAlloc = CappedAlloc::new();

const DICTIONARY: &[&str] = &[
    "name",
    "description",
    "world",
    "resolution",
    "origin",
    "width",
    "height",
    "layers",
    "color",
    "elevation",
    "terrain",
    "scale",
    "offset",
    "terrains",
    "id",
    "label",
    "rgb",
    "robot",
    "profile",
    "gaits",
    "v_max",
    "sensors",
    "range",
    "hfov_deg",
    "vfov_deg",
    "rate_hz",
    "width_px",
    "height_px",
    "mount",
    "footprint",
    "r_robot",
    "sim",
    "dt",
    "pose_rate_hz",
    "sigma_d",
    "start",
    "x",
    "y",
    "yaw",
    "bounds",
    "min",
    "max",
    "tours",
    "waypoints",
    "map",
    "cell_size",
    "tile_size",
    "strategy",
    "n_min",
    "true",
    "false",
    "inf",
    "nan",
];

/// The small built-ins: large worlds make each case slow without reaching new code.
const SEED_WORLDS: &[&str] = &["energy-arena", "courtyard-small", "lab-track", "cot-track"];

fn bundle_of(dir: &Path) -> Bundle {
    let mut files: Vec<(String, Vec<u8>)> = fs::read_dir(dir)
        .expect("exported scenario folder")
        .filter_map(|e| e.ok())
        .map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            (name, fs::read(e.path()).expect("exported file"))
        })
        .collect();
    files.sort();
    Bundle(files)
}

/// Writes `b` as the only files of `dir`.
fn write_bundle(b: &Bundle, dir: &Path) -> std::io::Result<()> {
    let _ = fs::remove_dir_all(dir);
    fs::create_dir_all(dir)?;
    for (name, bytes) in &b.0 {
        // Names come from stored inputs too: keep them inside `dir`.
        if name.is_empty() || name.contains(['/', '\\']) || name.starts_with('.') {
            continue;
        }
        fs::write(dir.join(name), bytes)?;
    }
    Ok(())
}

#[test]
fn fuzz_scenario_files() {
    let scratch = common::scratch(env!("CARGO_TARGET_TMPDIR"), "scenario");
    let seeds: Vec<Bundle> = SEED_WORLDS
        .iter()
        .map(|name| {
            let sc = builtin::generate(name, 1).expect("built-in scenario");
            let dir = scratch.join(format!("seed-{name}"));
            sc.save(&dir).expect("export");
            bundle_of(&dir)
        })
        .collect();
    let case_dir = scratch.join("case");
    let check = |input: &Bundle| -> Result<Outcome, String> {
        write_bundle(input, &case_dir).map_err(|e| format!("scratch write: {e}"))?;
        let sc = match Scenario::load(&case_dir) {
            Ok(sc) => sc,
            Err(e) => return Ok(Outcome::Rejected(e.to_string())),
        };
        let mut sim = match Simulator::new(&sc, 1) {
            Ok(sim) => sim,
            Err(e) => return Ok(Outcome::Rejected(e.to_string())),
        };
        for cloud in sim.scan_now() {
            if cloud
                .points
                .iter()
                .any(|p| !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()))
            {
                return Err("a scan holds a non-finite point".into());
            }
        }
        Ok(Outcome::Accepted)
    };
    for (k, s) in seeds.iter().enumerate() {
        assert!(
            matches!(check(s), Ok(Outcome::Accepted)),
            "seed {} must load: {:?}",
            SEED_WORLDS[k],
            check(s)
        );
    }
    fuzz(config!("scenario", 600), &ALLOC, seeds, DICTIONARY, check);
}
