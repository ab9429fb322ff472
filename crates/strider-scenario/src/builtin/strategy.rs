//! The `[strategy]` table of a built-in: one `[strategy.<name>]` section per strategy (or
//! command) that the world is meant for.

/// A parameter table from float and integer entries (floats first, each in the given order).
pub(crate) fn params(floats: &[(&str, f64)], ints: &[(&str, i64)]) -> toml::Table {
    let mut t = toml::Table::new();
    for &(k, v) in floats {
        t.insert(k.to_string(), toml::Value::Float(v));
    }
    for &(k, v) in ints {
        t.insert(k.to_string(), toml::Value::Integer(v));
    }
    t
}

/// The scenario's `[strategy]` table: a copy of `table` as the section of each of `names`.
pub(crate) fn sections(names: &[&str], table: &toml::Table) -> toml::Table {
    names
        .iter()
        .map(|n| (n.to_string(), toml::Value::Table(table.clone())))
        .collect()
}
