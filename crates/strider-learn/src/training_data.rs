//! Row-major training data as the batch learners take it: n inputs of `dim` values each (`x`,
//! n × dim) and n targets (`y`).

/// The first non-finite entry of (`x`, `y`), named like "x\[2\] of sample 7" or "y of sample 7"
/// with `item` for "sample"; inputs are searched before targets. `None` when every entry is
/// finite.
pub(crate) fn first_non_finite(dim: usize, x: &[f64], y: &[f64], item: &str) -> Option<String> {
    if let Some(k) = x.iter().position(|v| !v.is_finite()) {
        return Some(format!("x[{}] of {item} {}", k % dim, k / dim));
    }
    y.iter()
        .position(|v| !v.is_finite())
        .map(|i| format!("y of {item} {i}"))
}
