//! Typed strategy parameters: each strategy's parameters are a struct with the papers' table
//! values as defaults, read from a TOML table (a scenario's `[strategy.<name>]`) and from
//! `key=value` overrides, with unknown keys and wrong types rejected by the key's name and
//! every value checked against its range once, where it enters.

use serde::Serialize;
use serde::de::DeserializeOwned;

/// What `strider strategies` shows of one parameter, and the values it may take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamDoc {
    /// The key in `[strategy.<name>]` and in `--set key=value`.
    pub key: &'static str,
    /// Unit (empty: none).
    pub unit: &'static str,
    /// What it is, and where it comes from.
    pub doc: &'static str,
    /// The values it may take.
    pub range: Range,
}

impl ParamDoc {
    /// The doc of `key` in `unit` (empty: none), of any value its type allows.
    pub const fn new(key: &'static str, unit: &'static str, doc: &'static str) -> Self {
        Self {
            key,
            unit,
            doc,
            range: Range::Any,
        }
    }

    /// A finite number > `lo` and ≤ `hi`.
    pub const fn above(self, lo: f64, hi: f64) -> Self {
        self.with(Range::Above(lo, hi))
    }

    /// A finite number in [`lo`, `hi`].
    pub const fn within(self, lo: f64, hi: f64) -> Self {
        self.with(Range::Within(lo, hi))
    }

    /// A whole number in `lo..=hi`.
    pub const fn count(self, lo: u64, hi: u64) -> Self {
        self.with(Range::Count(lo, hi))
    }

    /// `true` or `false`.
    pub const fn flag(self) -> Self {
        self.with(Range::Flag)
    }

    /// A string.
    pub const fn name(self) -> Self {
        self.with(Range::Name)
    }

    /// One of `names`.
    pub const fn one_of(self, names: &'static [&'static str]) -> Self {
        self.with(Range::OneOf(names))
    }

    /// A table of numbers, each in [`lo`, `hi`].
    pub const fn each_within(self, lo: f64, hi: f64) -> Self {
        self.with(Range::EachWithin(lo, hi))
    }

    const fn with(self, range: Range) -> Self {
        Self { range, ..self }
    }

    /// Checks `value` against the range: one line naming the key, the value, the allowed
    /// range and the unit.
    pub fn check(&self, value: &toml::Value) -> Result<(), ParamError> {
        if self.range.admits(value) {
            Ok(())
        } else {
            Err(ParamError::new(
                self.key,
                format!("= {value}: must be {}", self.range.describe(self.unit)),
            ))
        }
    }
}

/// The values a parameter may take. Every number is bounded on both sides: a value beyond
/// the upper bound is no longer a meaningful setting, and the bounds keep the allocations and
/// loops the parameter sizes within reach (each cap is given with its parameter's doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// Any value of the parameter's type (checked by deserialisation).
    Any,
    /// A finite number > lo and ≤ hi.
    Above(f64, f64),
    /// A finite number in [lo, hi].
    Within(f64, f64),
    /// A whole number in lo..=hi.
    Count(u64, u64),
    /// `true` or `false`.
    Flag,
    /// A string.
    Name,
    /// One of these strings.
    OneOf(&'static [&'static str]),
    /// A table of numbers, each in [lo, hi].
    EachWithin(f64, f64),
}

impl Range {
    /// True when `v` is in the range.
    pub fn admits(&self, v: &toml::Value) -> bool {
        let number = |v: &toml::Value| match v {
            toml::Value::Float(f) => Some(*f),
            toml::Value::Integer(i) => Some(*i as f64),
            _ => None,
        };
        let within = |x: f64, lo: f64, hi: f64| x.is_finite() && lo <= x && x <= hi;
        match *self {
            Range::Any => true,
            Range::Above(lo, hi) => number(v).is_some_and(|x| x > lo && within(x, lo, hi)),
            Range::Within(lo, hi) => number(v).is_some_and(|x| within(x, lo, hi)),
            Range::Count(lo, hi) => v
                .as_integer()
                .and_then(|i| u64::try_from(i).ok())
                .is_some_and(|i| (lo..=hi).contains(&i)),
            Range::Flag => v.is_bool(),
            Range::Name => v.is_str(),
            Range::OneOf(names) => v.as_str().is_some_and(|s| names.contains(&s)),
            Range::EachWithin(lo, hi) => v.as_table().is_some_and(|t| {
                t.values()
                    .all(|x| number(x).is_some_and(|x| within(x, lo, hi)))
            }),
        }
    }

    /// What the range allows, in `unit` (empty: none): "a finite number > 0 m and ≤ 5 m".
    pub fn describe(&self, unit: &str) -> String {
        let u = |x: f64| {
            if unit.is_empty() {
                format!("{x}")
            } else {
                format!("{x} {unit}")
            }
        };
        match *self {
            Range::Any => "a value of the parameter's type".into(),
            Range::Above(lo, hi) => format!("a finite number > {} and ≤ {}", u(lo), u(hi)),
            Range::Within(lo, hi) => format!("a finite number ≥ {} and ≤ {}", u(lo), u(hi)),
            Range::Count(lo, hi) if unit.is_empty() => {
                format!("a whole number ≥ {lo} and ≤ {hi}")
            }
            Range::Count(lo, hi) => format!("a whole number of {unit} ≥ {lo} and ≤ {hi}"),
            Range::Flag => "true or false".into(),
            Range::Name => "a quoted name".into(),
            Range::OneOf(names) => format!("one of {}", names.join(", ")),
            Range::EachWithin(lo, hi) => format!(
                "a table of numbers, each finite, ≥ {} and ≤ {}",
                u(lo),
                u(hi)
            ),
        }
    }
}

/// A parameter that is wrong: its key and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct ParamError {
    /// One line naming the key, the value and the allowed range.
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

/// A strategy's parameter struct: each parameter's range is given in [`StrategyParams::DOCS`]
/// and checked from there; rules between parameters in [`StrategyParams::check_together`].
pub trait StrategyParams: Serialize + DeserializeOwned + Default + Clone {
    /// Every parameter, in the order `strider strategies` lists them.
    const DOCS: &'static [ParamDoc];

    /// Checks the rules between parameters (e.g. m_min ≤ m_max).
    fn check_together(&self) -> Result<(), ParamError> {
        Ok(())
    }

    /// Checks every value against its range, then the rules between them.
    fn validate(&self) -> Result<(), ParamError> {
        check_table::<Self>(&to_table(self))?;
        self.check_together()
    }
}

/// Checks every entry of `table`: a parameter of `P`, in its range.
fn check_table<P: StrategyParams>(table: &toml::Table) -> Result<(), ParamError> {
    for (key, value) in table {
        let Some(doc) = P::DOCS.iter().find(|d| d.key == key) else {
            return Err(unknown::<P>(key));
        };
        doc.check(value)?;
    }
    Ok(())
}

/// The error of a key that is not a parameter of `P`: the nearest parameter's name when the
/// key looks like a misspelling of it, else all of them.
fn unknown<P: StrategyParams>(key: &str) -> ParamError {
    let nearest = P::DOCS
        .iter()
        .map(|d| (edit_distance(key, d.key), d.key))
        .min()
        .filter(|&(d, k)| d <= 2.max(k.len() / 4));
    match nearest {
        Some((_, k)) => ParamError::new(key, format!("is not a parameter; did you mean `{k}`?")),
        None => {
            let keys: Vec<&str> = P::DOCS.iter().map(|d| d.key).collect();
            ParamError::new(
                key,
                format!("is not a parameter; the parameters are {}", keys.join(", ")),
            )
        }
    }
}

/// Levenshtein distance of two short keys.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// Parses `table` over the defaults: unknown keys and wrong types are errors naming the key;
/// the result is validated.
pub fn from_table<P: StrategyParams>(table: &toml::Table) -> Result<P, ParamError> {
    check_table::<P>(table)?;
    let p: P = toml::Value::Table(table.clone())
        .try_into()
        .map_err(|e: toml::de::Error| ParamError {
            message: one_line(&e.to_string()),
        })?;
    p.check_together()?;
    Ok(p)
}

/// `params` with `key` set to `value` (TOML syntax: `3`, `0.5`, `true`, `"lab"`; a bare word
/// is taken as a string). Unknown keys, wrong types and values out of range are errors naming
/// the key.
pub fn with_set<P: StrategyParams>(params: &P, key: &str, value: &str) -> Result<P, ParamError> {
    if !P::DOCS.iter().any(|d| d.key == key) {
        return Err(unknown::<P>(key));
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

/// The caps of the parameter ranges that bound what a parameter sizes (the `DOCS` of each
/// strategy use them).
pub mod limits {
    /// Fastest rate of any module, Hz: the fastest control tick; a module at a higher rate
    /// than the tick runs once a tick anyway.
    pub const MAX_RATE_HZ: f64 = 1000.0;
    /// Longest window, manoeuvre or budget, s: an hour is beyond any measuring window or
    /// manoeuvre of a mission, and bounds the buffers a window sizes.
    pub const MAX_DURATION_S: f64 = 3600.0;
    /// Largest descriptor neighbourhood, m: a descriptor is computed over a disc of map cells
    /// around each cell, 2 m over 1 cm cells is 126 k cells per descriptor.
    pub const MAX_DESCRIPTOR_RADIUS_M: f64 = 2.0;
    /// Largest exclusion or cluster radius, m: such a disc is laid out once as cell offsets,
    /// 20 m over 1 cm cells is 12.6 M offsets (100 MB).
    pub const MAX_RADIUS_M: f64 = 20.0;
    /// Most sampling sites per cost goal: a tour's instance runs one shortest-path search per
    /// site and holds a cost matrix over all sites; 64 sites for 50 goals is a 3200-vertex
    /// matrix (80 MB).
    pub const MAX_SITES_PER_GOAL: u64 = 64;
    /// Most (descriptor, cost) pairs of an RBCM expert: its GP fit is cubic in them and holds
    /// their square matrix, and an expert is refitted while the robot drives.
    pub const MAX_EXPERT_PAIRS: u64 = 1000;
    /// Largest IGNG batch: the batch's descriptors are held in memory and clustered at once.
    pub const MAX_IGNG_BATCH: u64 = 1_000_000;
    /// Most measurements kept per map cell.
    pub const MAX_MEASUREMENTS_PER_CELL: u64 = 1000;
    /// Largest variance, cost or force bound: beyond it the GP's and the tours' sums lose
    /// their precision (tour costs are summed in integer millicost units).
    pub const MAX_MAGNITUDE: f64 = 1e6;
}
