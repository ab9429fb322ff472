//! Memory estimates checked before the reader and the solver allocate their dense matrices.
//!
//! A TSPLIB header can declare any dimension, and the solver's own structures grow with the
//! square of the vertex count, so both estimate what they are about to allocate and refuse with
//! a [`MemoryError`] that says what was too big, instead of aborting on a failed allocation.

use std::fmt;

use thiserror::Error;

/// Largest single allocation the reader (an n × n cost matrix) or the solver (its renumbered
/// matrices and set tables) makes: 4 GiB. A matrix of that size takes minutes to fill and
/// search already, and two of them (the instance and the solver's copy) still fit in the 8 GB
/// address space the project's robustness checks run in. Raise it only together with the
/// solver's data structures (they are quadratic in the vertex count).
pub const MEMORY_LIMIT_BYTES: u64 = 4 << 30;

/// An allocation refused before it was made.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("{what} needs {} but {}; {hint}", Bytes(*.needed), self.budget())]
pub struct MemoryError {
    /// What would have been allocated, e.g. "a 100000 × 100000 cost matrix".
    pub what: String,
    /// Bytes it needs (`u64::MAX` when the size itself overflows).
    pub needed: u64,
    /// The budget it exceeded, in bytes.
    pub limit: u64,
    /// True when the budget was the memory available to the process, not
    /// [`MEMORY_LIMIT_BYTES`].
    pub available: bool,
    /// What to change, e.g. "use an instance of at most 23170 vertices".
    pub hint: String,
}

impl MemoryError {
    fn budget(&self) -> String {
        if self.available {
            format!("only {} of memory is available", Bytes(self.limit))
        } else {
            format!("the limit is {} (MEMORY_LIMIT_BYTES)", Bytes(self.limit))
        }
    }
}

/// A byte count printed with a binary unit.
struct Bytes(u64);

impl fmt::Display for Bytes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0 == u64::MAX {
            return f.write_str("more than 16 EiB");
        }
        let units = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
        let mut v = self.0 as f64;
        let mut u = 0;
        while v >= 1024.0 && u + 1 < units.len() {
            v /= 1024.0;
            u += 1;
        }
        if u == 0 {
            write!(f, "{} bytes", self.0)
        } else {
            write!(f, "{v:.1} {}", units[u])
        }
    }
}

/// Checks that `needed` bytes (`None` when the size computation overflowed) fit both
/// [`MEMORY_LIMIT_BYTES`] and the memory available to the process.
pub fn check(needed: Option<u64>, what: &str, hint: &str) -> Result<(), MemoryError> {
    let needed = needed.unwrap_or(u64::MAX);
    let err = |limit, available| MemoryError {
        what: what.to_string(),
        needed,
        limit,
        available,
        hint: hint.to_string(),
    };
    if needed > MEMORY_LIMIT_BYTES {
        return Err(err(MEMORY_LIMIT_BYTES, false));
    }
    // Small allocations are not worth reading /proc for.
    if needed >= 64 << 20
        && let Some(avail) = available_bytes()
        && needed > avail
    {
        return Err(err(avail, true));
    }
    Ok(())
}

/// Bytes of `count` elements of `size` bytes each, `None` on overflow.
pub fn bytes_of(count: u64, size: u64) -> Option<u64> {
    count.checked_mul(size)
}

/// Memory the process can still allocate: the smaller of the system's available memory
/// (`MemAvailable` of `/proc/meminfo`) and what the address-space limit (`ulimit -v`) leaves
/// above the current address-space size. `None` where `/proc` cannot tell.
pub fn available_bytes() -> Option<u64> {
    let mem = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| kib_field(&t, "MemAvailable:"));
    let rlimit = std::fs::read_to_string("/proc/self/limits")
        .ok()
        .and_then(|t| address_space_limit(&t));
    let used = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|t| kib_field(&t, "VmSize:"));
    let room = match (rlimit, used) {
        (Some(l), Some(u)) => Some(l.saturating_sub(u)),
        (Some(l), None) => Some(l),
        _ => None,
    };
    match (mem, room) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// The value in bytes of a `Key:   123 kB` line.
fn kib_field(text: &str, key: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kib: u64 = line[key.len()..].split_whitespace().next()?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The soft limit of the `Max address space` line of `/proc/self/limits`, if not unlimited.
fn address_space_limit(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..]
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn over_the_limit_is_refused_with_the_size_and_the_hint() {
        let e = check(
            Some(80_000_000_000),
            "a 100000 × 100000 cost matrix",
            "use less",
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "a 100000 × 100000 cost matrix needs 74.5 GiB but the limit is 4.0 GiB \
             (MEMORY_LIMIT_BYTES); use less"
        );
        let e = check(None, "x", "y").unwrap_err();
        assert!(e.to_string().starts_with("x needs more than 16 EiB"), "{e}");
        assert!(check(Some(1000), "x", "y").is_ok());
    }

    #[test]
    fn proc_fields_parse() {
        assert_eq!(
            kib_field("MemTotal: 10 kB\nMemAvailable:   3 kB\n", "MemAvailable:"),
            Some(3072)
        );
        let limits = "Limit Soft Hard Units\nMax address space         8192000000           unlimited            bytes\n";
        assert_eq!(address_space_limit(limits), Some(8_192_000_000));
        let unlimited =
            "Max address space         unlimited            unlimited            bytes\n";
        assert_eq!(address_space_limit(unlimited), None);
    }
}
