//! `003` energy-optimal repeated tours (work in progress).
