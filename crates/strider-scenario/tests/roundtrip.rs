//! save → load round trips exactly.

use std::path::PathBuf;

use strider_scenario::{Scenario, builtin};

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "strider-scenario-{tag}-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn builtins_round_trip() {
    for &name in builtin::names() {
        let s = builtin::generate(name, 2).unwrap();
        let dir = temp_dir(name);
        let file = s.save(&dir).unwrap();
        let back = Scenario::load(&file).unwrap();
        assert_eq!(back, s, "{name}");
        let back = Scenario::load(&dir).unwrap();
        assert_eq!(back, s, "{name} (directory)");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
