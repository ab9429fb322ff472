//! Limits on what a log may make the reader do, shared by the replay, its configuration and the
//! error messages that name them.

/// Longest log accepted, s: a longer span means a bogus stamp, which would make the replay
/// tick through years of nothing.
pub const MAX_SPAN_S: f64 = 7.0 * 86400.0;

/// Largest record (and decompressed chunk) read, bytes: far above any sensor message, and a
/// bound on what a corrupted length field can make the reader allocate.
pub const MAX_RECORD_BYTES: usize = 256 << 20;
