//! Generated bad input: a built-in scenario, exported to TOML and PNG bytes, with values replaced
//! by extremes, keys deleted or renamed and values of the wrong type. Loading it never panics,
//! and whatever loads is valid and starts a simulator.
//!
//! `PROPTEST_CASES` sets the number of cases (default 96, a few seconds).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::OnceLock;

use proptest::prelude::*;
use strider_scenario::{Scenario, builtin};
use strider_sim::Simulator;
use toml::Value;

/// The exported scenario: TOML text and the PNG layers, by the names the TOML gives them.
struct Exported {
    text: String,
    layers: BTreeMap<String, Vec<u8>>,
}

fn exported() -> &'static Exported {
    static E: OnceLock<Exported> = OnceLock::new();
    E.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("strider-mutate-{}", std::process::id()));
        let s = builtin::generate("courtyard-small", 1).unwrap();
        let file = s.save(&dir).unwrap();
        let text = std::fs::read_to_string(&file).unwrap();
        let layers = ["color.png", "elevation.png", "terrain.png"]
            .iter()
            .map(|n| (n.to_string(), std::fs::read(dir.join(n)).unwrap()))
            .collect();
        let _ = std::fs::remove_dir_all(&dir);
        Exported { text, layers }
    })
}

/// A step from a value to one of its children.
#[derive(Clone, Debug)]
enum Seg {
    Key(String),
    Index(usize),
}

/// Paths to every value below the root, in document order.
fn paths(v: &Value, at: &mut Vec<Seg>, out: &mut Vec<Vec<Seg>>) {
    let children: Vec<(Seg, &Value)> = match v {
        Value::Table(t) => t.iter().map(|(k, c)| (Seg::Key(k.clone()), c)).collect(),
        Value::Array(a) => a
            .iter()
            .enumerate()
            .map(|(i, c)| (Seg::Index(i), c))
            .collect(),
        _ => Vec::new(),
    };
    for (seg, child) in children {
        at.push(seg);
        out.push(at.clone());
        paths(child, at, out);
        at.pop();
    }
}

/// The parent of the value at `path` and the last step to it.
fn parent<'a>(root: &'a mut Value, path: &[Seg]) -> Option<(&'a mut Value, Seg)> {
    let (last, init) = path.split_last()?;
    let mut v = root;
    for seg in init {
        v = match (v, seg) {
            (Value::Table(t), Seg::Key(k)) => t.get_mut(k)?,
            (Value::Array(a), Seg::Index(i)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some((v, last.clone()))
}

/// Marks an integer too large for TOML's i64, patched into the text after serialising.
const U64_MAX_MARK: &str = "__u64_max__";

/// The extreme values a number is replaced with.
fn extreme(k: usize, was_integer: bool) -> Value {
    const FLOATS: [f64; 10] = [
        0.0,
        -1.0,
        1e-9,
        1e9,
        1e300,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        -0.0,
        18_446_744_073_709_551_615.0,
    ];
    const INTS: [i64; 6] = [0, -1, 1_000_000_000, i64::MAX, i64::MIN, 100_000];
    if was_integer && k.is_multiple_of(2) {
        let k = k / 2;
        if k == INTS.len() {
            return Value::String(U64_MAX_MARK.into());
        }
        return Value::Integer(INTS[k % INTS.len()]);
    }
    Value::Float(FLOATS[k % FLOATS.len()])
}

/// A value of a type the format does not expect at most places.
fn wrong_type(k: usize) -> Value {
    match k % 5 {
        0 => Value::String("x".into()),
        1 => Value::Boolean(true),
        2 => Value::Array(vec![Value::Integer(1)]),
        3 => Value::Table(toml::Table::new()),
        _ => Value::Integer(7),
    }
}

/// Applies mutation `kind` (with variant `k`) to the value at `path`.
fn mutate(root: &mut Value, path: &[Seg], kind: u8, k: usize) {
    let Some((p, last)) = parent(root, path) else {
        return;
    };
    match (p, last) {
        (Value::Table(t), Seg::Key(key)) => match kind {
            0 => {
                let was_int = matches!(t.get(&key), Some(Value::Integer(_)));
                t.insert(key, extreme(k, was_int));
            }
            1 => {
                t.remove(&key);
            }
            2 => {
                if let Some(v) = t.remove(&key) {
                    t.insert(format!("{key}x"), v);
                }
            }
            _ => {
                t.insert(key, wrong_type(k));
            }
        },
        (Value::Array(a), Seg::Index(i)) => match kind {
            0 => {
                let was_int = matches!(a[i], Value::Integer(_));
                a[i] = extreme(k, was_int);
            }
            1 | 2 => {
                a.remove(i);
            }
            _ => a[i] = wrong_type(k),
        },
        _ => {}
    }
}

/// Loads `text` with the exported layers; when it loads, checks that it validates and that a
/// simulator starts on it and runs a little.
fn load_and_check(text: &str) -> Result<(), TestCaseError> {
    let file = Path::new("mutated.toml");
    let Ok(s) = Scenario::from_toml_str(text, file, &exported().layers) else {
        return Ok(());
    };
    prop_assert!(s.validate(file).is_ok(), "loaded but invalid: {text}");
    let sim = Simulator::new(&s, 1);
    prop_assert!(
        sim.is_ok(),
        "valid but the simulator refuses it: {sim:?}\n{text}"
    );
    Ok(())
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(96)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenarios_never_panic(edits in prop::collection::vec((any::<prop::sample::Index>(), 0u8..4, 0usize..64), 1..4)) {
        let mut doc: Value = toml::from_str(&exported().text).unwrap();
        for (at, kind, k) in edits {
            let mut all = Vec::new();
            paths(&doc, &mut Vec::new(), &mut all);
            if all.is_empty() {
                break;
            }
            let path = at.get(&all).clone();
            mutate(&mut doc, &path, kind, k);
        }
        let Ok(text) = toml::to_string(&doc) else {
            return Ok(());
        };
        let text = text.replace(&format!("\"{U64_MAX_MARK}\""), "18446744073709551615");
        load_and_check(&text)?;
    }
}

#[test]
fn the_unmutated_export_loads() {
    let s = Scenario::from_toml_str(
        &exported().text,
        Path::new("exported.toml"),
        &exported().layers,
    )
    .unwrap();
    assert_eq!(s, builtin::generate("courtyard-small", 1).unwrap());
}

/// Every extreme in every numeric value of the export, one at a time.
#[test]
fn every_number_at_every_extreme() {
    let doc: Value = toml::from_str(&exported().text).unwrap();
    let mut all = Vec::new();
    paths(&doc, &mut Vec::new(), &mut all);
    // `[strategy.*]` values are the strategies' to check (when a strategy is configured), not
    // the loader's: they would only repeat the load of the unmutated scenario.
    let numeric: Vec<&Vec<Seg>> = all
        .iter()
        .filter(|p| !matches!(p.first(), Some(Seg::Key(k)) if k == "strategy"))
        .filter(|p| {
            let mut d = doc.clone();
            parent(&mut d, p).is_some_and(|(v, last)| {
                let x = match (v, last) {
                    (Value::Table(t), Seg::Key(k)) => t.get(&k).cloned(),
                    (Value::Array(a), Seg::Index(i)) => a.get(i).cloned(),
                    _ => None,
                };
                matches!(x, Some(Value::Float(_) | Value::Integer(_)))
            })
        })
        .collect();
    assert!(numeric.len() > 50, "{}", numeric.len());
    eprintln!("{} numeric values", numeric.len());
    for path in numeric {
        let mut d = doc.clone();
        let was_int = parent(&mut d, path).is_some_and(|(v, last)| match (v, last) {
            (Value::Table(t), Seg::Key(k)) => matches!(t.get(&k), Some(Value::Integer(_))),
            (Value::Array(a), Seg::Index(i)) => matches!(a.get(i), Some(Value::Integer(_))),
            _ => false,
        });
        // Every distinct extreme of `extreme` once: the integers at even k (and one float),
        // the floats at k < 10.
        let ks: Vec<usize> = if was_int {
            vec![0, 2, 4, 6, 8, 10, 12, 1]
        } else {
            (0..10).collect()
        };
        for k in ks {
            let mut d = doc.clone();
            mutate(&mut d, path, 0, k);
            let text = toml::to_string(&d)
                .unwrap()
                .replace(&format!("\"{U64_MAX_MARK}\""), "18446744073709551615");
            load_and_check(&text).unwrap();
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    /// Bytes of one layer overwritten, or the layer cut short: a clean error or a valid
    /// scenario (a flip may land in a chunk the decoder ignores).
    #[test]
    fn corrupted_layers_never_panic(
        layer in 0usize..3,
        flips in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 0..6),
        cut in prop::option::of(any::<prop::sample::Index>()),
    ) {
        let mut layers = exported().layers.clone();
        let name = ["color.png", "elevation.png", "terrain.png"][layer];
        let bytes = layers.get_mut(name).unwrap();
        for (at, b) in flips {
            let k = at.index(bytes.len());
            bytes[k] = b;
        }
        if let Some(at) = cut {
            let k = at.index(bytes.len());
            bytes.truncate(k);
        }
        let file = Path::new("corrupted.toml");
        if let Ok(s) = Scenario::from_toml_str(&exported().text, file, &layers) {
            prop_assert!(s.validate(file).is_ok());
        }
    }
}
