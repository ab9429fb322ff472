//! # strider-sim (skeleton; filled by the simulator work)
