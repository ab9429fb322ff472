//! # strider-experiments
//!
//! The experiments of the papers Strider reproduces, run in Strider's simulator, and the
//! harness they share. The `strider` binary parses its arguments, calls in here and prints; the
//! algorithms (map, learn, plan, explore) never depend on this crate or on the simulator.
//!
//! One module per paper (the keys of `docs/papers.md`), each with its scenario setup, metrics,
//! published figures and typed serde reports:
//!
//! * [`pragr22`]: exploration with simultaneous environment and traversability models
//!   learning — one mission with its benchmark tours (`strider run`), the Table 5 bench;
//! * [`pragr19`]: online incremental learning of the traversal cost — the `rbcm-greedy`
//!   mission, the learner benchmark of its Fig. 5;
//! * [`pragr18`]: the cost of transport predicted from an aerial view (thesis contribution C1),
//!   its Table I;
//! * [`pragr23`]: traversable yet visually rigid obstacles (thesis contribution C4) — the
//!   `escape` mission, the vegetation bench;
//! * [`martin_corke`]: energy-optimal repeated tours;
//! * [`nardi19`]: repeated navigation with a GP mixture and a lower confidence bound.
//!
//! Shared by them: [`trial`] (a scenario's world in the simulator behind the robot interface,
//! a mission on it, the benchmark tours), [`run`] (`strider run` of any strategy), [`compare`]
//! (strategies of different papers on the same worlds), [`replay`] (a recorded log through the
//! mission's mapping and learning), [`live`] and [`pace`] (a mission recorded, served to
//! Foxglove while it runs, paced to the wall clock), [`map_build`] (the map judged against ground truth),
//! [`stats`] (one definition of each statistic), [`report`] and [`render`] (the HTML report and
//! the figures), [`scenario_figures`], [`gtsp`] (a GTSPLIB instance solved and checked), [`io`], [`parallel`], [`progress`] and [`cancel`] (stopping
//! early on Ctrl-C without losing what was done). [`soak`] runs every strategy on many worlds and
//! checks the invariants every mission must keep; [`scale`] samples one exploration of a large
//! world over time (latencies against the area explored).

pub mod cancel;
pub mod compare;
pub mod gtsp;
pub mod io;
mod journal;
pub mod live;
pub mod map_build;
pub mod martin_corke;
pub mod nardi19;
pub mod pace;
mod pairs;
pub mod parallel;
pub mod pragr18;
pub mod pragr19;
pub mod pragr22;
pub mod pragr23;
pub mod progress;
pub mod render;
pub mod replay;
pub mod report;
pub mod run;
pub mod scale;
pub mod scenario_figures;
pub mod soak;
pub mod stats;
pub mod trial;
