//! # strider-learn
//!
//! Traversal-cost learning (Prágr22 §4.3, Prágr19 §III–IV): everything between "the robot
//! experienced this cost on this terrain" and "these are the planning costs per gait, and these
//! are the goals where the models can still learn". One module per concept:
//!
//! * [`bench`](mod@bench): the learner benchmark harness of Prágr19 §V-A and Prágr18 (one
//!   interface over GP, RBCM, IGMN and tree; the incremental-stream and the aerial-view
//!   protocols).
//! * [`cost_model`]: the per-gait traversal cost model C^g (Prágr22 Alg. 5–10, Eq. 12–18, 22–26).
//! * [`descriptor_field`]: terrain descriptors (ta(ν) of Prágr22 §4.2 or the 5-D descriptor of
//!   Prágr19 Eq. 10) flattened for the learners, non-finite values refused.
//! * [`signals`]: cost measurements from pose/gait and proprioceptive streams — inverse velocity
//!   with the tanh bound (Prágr22 Eq. 19–20, decision 8), roll variance (Prágr19), energy per metre
//!   and cost of transport (Prágr18, MartinCorke), stuck detection (decision 9).
//! * [`gp`]: exact GP regression with O(n²) insert/remove of training points (Prágr22 Eq. 14–16,
//!   21; decisions 12–14).
//! * [`gp_csv`]: numeric CSV tables for GP regression from files, with size limits.
//! * [`rbcm`]: the robust Bayesian committee machine of GP experts (Prágr19 Eq. 7–9, decision 15).
//! * [`igng`]: incremental growing neural gas terrain classes (Prágr22 Alg. 11, decision 17).
//! * [`morphology`]: class erosion and dilation (Prágr22 Eq. 25–26, decision 18).
//! * [`igmn`]: the incremental Gaussian mixture network regressor (Prágr18, Prágr19 §V-A).
//! * [`regression_tree`]: the depth-5 CART regression tree (Prágr18).
//! * [`mixture`]: the GP mixture model of Nardi19 (Eq. 3–6): mean-shift clusters, gating
//!   regressions on position and aerial colour, heteroscedastic component GPs (decision 20).
//!
//! The crate works on the map crate's layers and descriptors and knows nothing of the simulator.

pub mod bench;
pub mod cost_model;
pub mod descriptor_field;
pub mod gp;
pub mod gp_csv;
pub mod igmn;
pub mod igng;
pub mod mixture;
pub mod morphology;
pub mod rbcm;
pub mod regression_tree;
pub mod signals;
mod training_data;
