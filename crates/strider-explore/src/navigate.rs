//! `004` repeated start–goal navigation with a GP mixture model (work in progress).
