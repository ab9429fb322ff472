//! Fuzz target: the MCAP container and the ROS 2 messages in it, through a replay of the whole
//! log. Every accepted log must replay to its end without a panic, a NaN pose or an endless
//! loop.

mod common;

use strider_fuzz::{Binary, CappedAlloc, Outcome, config, fuzz};
use strider_log::{LogReplay, ReplayConfig};

#[global_allocator]
static ALLOC: CappedAlloc = CappedAlloc::new();

const CONFIG: &str = "world_frame = \"map\"\n[mission]\ngaits = [{ name = \"fast\", v_max = 0.05 }, \
{ name = \"tall\", v_max = 0.0125 }]\nsensor_hfov_deg = [360.0]\n";

/// Replay steps allowed per case: the seed log is 0.5 s (10 steps); a mutated stamp may claim
/// years, which the replay must handle without walking every step of them here.
const MAX_STEPS: usize = 2000;

#[test]
fn fuzz_mcap_replay() {
    let dir = common::scratch(env!("CARGO_TARGET_TMPDIR"), "mcap");
    let seed_path = dir.join("seed.mcap");
    common::small_log(&seed_path).expect("seed log");
    let seed = Binary(std::fs::read(&seed_path).expect("seed log bytes"));
    let cfg = ReplayConfig::parse(CONFIG).expect("seed config");
    let case_path = dir.join("case.mcap");
    let check = |input: &Binary| -> Result<Outcome, String> {
        std::fs::write(&case_path, &input.0).map_err(|e| format!("scratch write: {e}"))?;
        let mut replay = match LogReplay::open(&case_path, &cfg, &common::gaits()) {
            Ok(r) => r,
            Err(e) => return Ok(Outcome::Rejected(e.to_string())),
        };
        match common::drain(&mut replay, MAX_STEPS) {
            Ok(_) => Ok(Outcome::Accepted),
            Err(e) => Ok(Outcome::Rejected(e.to_string())),
        }
    };
    assert!(
        matches!(check(&seed), Ok(Outcome::Accepted)),
        "the seed log must replay: {:?}",
        check(&seed)
    );
    fuzz(config!("mcap", 1500), &ALLOC, vec![seed], &[], check);
}
