//! End-to-end: `strider learn bench` with tiny settings writes its files, fills every C1 cell
//! with finite numbers, and is a function of its seed (apart from wall times).

mod common;

use common::{one_line_error, strider, temp_dir};
use serde_json::Value;

fn read_json(p: &std::path::Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

#[test]
fn tiny_bench_writes_every_output_and_is_deterministic() {
    let run = |name: &str| {
        let d = temp_dir("learn", name);
        let o = strider(&[
            "learn",
            "bench",
            "--reps",
            "2",
            "--streams",
            "1",
            "--pairs",
            "30",
            "--c1-runs",
            "1",
            "--c1-pairs",
            "50",
            "--seed",
            "3",
            "--jobs",
            "2",
            "--out",
            d.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(
            out.contains("learn bench:") && out.contains("best"),
            "{out}"
        );
        d
    };
    let a = run("a");
    for f in [
        "learn_bench.json",
        "learn_bench.png",
        "c1_table.md",
        "c1_table.json",
    ] {
        assert!(a.join(f).metadata().unwrap().len() > 0, "{f}");
    }
    // Stream: every learner has one finite RMSE per pair; the GP family has a confidence, the
    // IGMN and the tree do not.
    let s = read_json(&a.join("learn_bench.json"));
    let n = s["pairs"].as_u64().unwrap() as usize;
    assert!(n >= 20, "{n} pairs");
    assert_eq!(s["reps"], 2);
    let learners = s["learners"].as_object().unwrap();
    for name in [
        "rbcm-exp",
        "rbcm-m32",
        "rbcm-m52",
        "rbcm-rbf",
        "rbcm-exp-mmin1",
        "gp-exp",
        "igmn",
        "tree",
    ] {
        let l = &learners[name];
        for key in ["learn_s", "infer_s", "rmse"] {
            let v = l[key].as_array().unwrap();
            assert_eq!(v.len(), n, "{name} {key}");
            assert!(
                v.iter().all(|x| x.as_f64().is_some_and(f64::is_finite)),
                "{name} {key}"
            );
        }
        assert_eq!(
            l["mean_std"].is_null(),
            name == "igmn" || name == "tree",
            "{name}"
        );
    }
    // C1: all 4 learners × 24 descriptors filled with finite numbers; a best cell is named.
    let c = read_json(&a.join("c1_table.json"));
    let cells = c["cells"].as_array().unwrap();
    assert_eq!(cells.len(), 96);
    for cell in cells {
        let (m, v) = (cell["mean"].as_f64(), cell["variance"].as_f64());
        assert!(m.is_some_and(|m| m.is_finite() && m >= 0.0), "{cell}");
        assert!(v.is_some_and(|v| v.is_finite() && v >= 0.0), "{cell}");
    }
    assert_eq!(c["filled_cells"], 96);
    assert!(c["best"]["learner"].is_string());
    let md = std::fs::read_to_string(a.join("c1_table.md")).unwrap();
    assert!(md.contains("Best: **"), "{md}");
    // Same seed, same numbers (wall times aside).
    let b = run("b");
    assert_eq!(md, std::fs::read_to_string(b.join("c1_table.md")).unwrap());
    let t = read_json(&b.join("learn_bench.json"));
    for name in ["rbcm-exp", "gp-exp", "igmn"] {
        assert_eq!(
            s["learners"][name]["rmse"], t["learners"][name]["rmse"],
            "{name}"
        );
    }
}

#[test]
fn bad_arguments_are_one_line_errors() {
    let d = temp_dir("learn", "bad");
    let out = d.to_str().unwrap();
    let e = one_line_error(&strider(&[
        "learn",
        "bench",
        "--protocol",
        "nope",
        "--out",
        out,
    ]));
    assert!(e.contains("--protocol"), "{e}");
    let e = one_line_error(&strider(&["learn", "bench", "--reps", "0", "--out", out]));
    assert!(e.contains("--reps"), "{e}");
}
