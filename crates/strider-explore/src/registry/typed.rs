//! Typed strategy parameters: each strategy's parameters are a struct with the papers' table
//! values as defaults, read from a TOML table (a scenario's `[strategy.<name>]`) and from
//! `key=value` overrides, with unknown keys and wrong types rejected by the key's name and
//! every value checked against its range once, where it enters.

use serde::Serialize;
use serde::de::DeserializeOwned;

/// What `strider strategies` shows of one parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParamDoc {
    /// The key in `[strategy.<name>]` and in `--set key=value`.
    pub key: &'static str,
    /// Unit (empty: none).
    pub unit: &'static str,
    /// What it is, and where it comes from.
    pub doc: &'static str,
}

impl ParamDoc {
    /// The doc of `key` in `unit` (empty: none).
    pub const fn new(key: &'static str, unit: &'static str, doc: &'static str) -> Self {
        Self { key, unit, doc }
    }
}

/// A parameter that is wrong: its key and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct ParamError {
    /// One line naming the key, what was wrong and the allowed range.
    pub message: String,
}

impl ParamError {
    /// The robot has no gait to choose.
    pub fn no_gait() -> Self {
        Self::new("gait", "cannot be chosen: the robot has no gait")
    }

    /// An error about `key`.
    pub fn new(key: &str, what: impl std::fmt::Display) -> Self {
        Self {
            message: format!("`{key}` {what}"),
        }
    }
}

/// A strategy's parameter struct.
pub trait StrategyParams: Serialize + DeserializeOwned + Default + Clone {
    /// Every parameter, in the order `strider strategies` lists them.
    const DOCS: &'static [ParamDoc];

    /// Checks every value against its range.
    fn validate(&self) -> Result<(), ParamError>;
}

/// Parses `table` over the defaults: unknown keys and wrong types are errors naming the key;
/// the result is validated.
pub fn from_table<P: StrategyParams>(table: &toml::Table) -> Result<P, ParamError> {
    let p: P = toml::Value::Table(table.clone())
        .try_into()
        .map_err(|e: toml::de::Error| ParamError {
            message: one_line(&e.to_string()),
        })?;
    p.validate()?;
    Ok(p)
}

/// `params` with `key` set to `value` (TOML syntax: `3`, `0.5`, `true`, `"lab"`; a bare word
/// is taken as a string). Unknown keys, wrong types and values out of range are errors naming
/// the key.
pub fn with_set<P: StrategyParams>(params: &P, key: &str, value: &str) -> Result<P, ParamError> {
    if !P::DOCS.iter().any(|d| d.key == key) {
        let keys: Vec<&str> = P::DOCS.iter().map(|d| d.key).collect();
        return Err(ParamError::new(
            key,
            format!("is not a parameter; the parameters are {}", keys.join(", ")),
        ));
    }
    let mut table = to_table(params);
    table.insert(key.to_string(), parse_value(value));
    from_table(&table)
}

/// The parameters as a TOML table (every key, with its value).
pub fn to_table<P: Serialize>(params: &P) -> toml::Table {
    toml::Table::try_from(params).unwrap_or_default()
}

/// The default of every parameter, as TOML text (`auto` for an optional one left unset).
pub fn defaults<P: StrategyParams>() -> Vec<(ParamDoc, String)> {
    let table = to_table(&P::default());
    P::DOCS
        .iter()
        .map(|d| {
            let v = table
                .get(d.key)
                .map_or_else(|| "auto".to_string(), |v| v.to_string());
            (*d, v)
        })
        .collect()
}

/// A `--set` value: TOML when it parses as a TOML value, else a string.
fn parse_value(value: &str) -> toml::Value {
    let doc = format!("v = {value}");
    toml::from_str::<toml::Table>(&doc)
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(value.to_string()))
}

/// A deserialiser's message on one line: "invalid value …, expected usize in `n_min`".
fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Range checks shared by the parameter structs.
pub mod check {
    use super::ParamError;

    /// A finite number > 0.
    pub fn positive(key: &str, v: f64) -> Result<(), ParamError> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(ParamError::new(
                key,
                format!("must be a positive number, got {v}"),
            ))
        }
    }

    /// A finite number ≥ 0.
    pub fn non_negative(key: &str, v: f64) -> Result<(), ParamError> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(ParamError::new(
                key,
                format!("must be a number ≥ 0, got {v}"),
            ))
        }
    }

    /// A finite number in `lo..=hi`.
    pub fn within(key: &str, v: f64, lo: f64, hi: f64) -> Result<(), ParamError> {
        if v.is_finite() && (lo..=hi).contains(&v) {
            Ok(())
        } else {
            Err(ParamError::new(
                key,
                format!("must be in [{lo}, {hi}], got {v}"),
            ))
        }
    }

    /// An integer in `lo..=hi`.
    pub fn count(key: &str, v: usize, lo: usize, hi: usize) -> Result<(), ParamError> {
        if (lo..=hi).contains(&v) {
            Ok(())
        } else {
            Err(ParamError::new(
                key,
                format!("must be in {lo}..={hi}, got {v}"),
            ))
        }
    }

    /// Every value a finite number > 0; the first that is not names its key.
    pub fn all_positive(values: &[(&str, f64)]) -> Result<(), ParamError> {
        values.iter().try_for_each(|&(k, v)| positive(k, v))
    }

    /// Every value a finite number ≥ 0; the first that is not names its key.
    pub fn all_non_negative(values: &[(&str, f64)]) -> Result<(), ParamError> {
        values.iter().try_for_each(|&(k, v)| non_negative(k, v))
    }

    /// An optional finite number > 0.
    pub fn positive_opt(key: &str, v: Option<f64>) -> Result<(), ParamError> {
        v.map_or(Ok(()), |v| positive(key, v))
    }
}
