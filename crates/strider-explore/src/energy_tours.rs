//! MartinCorke energy-optimal repeated tours: a robot drives the same set of waypoints again and
//! again, learns from its motor power where driving is expensive, and re-plans each tour to
//! spend less energy.
//!
//! # The paper's model
//!
//! MartinCorke §3 writes the energy of a tour of duration T along the path x(t) as
//!
//! E_t = ∫₀ᵀ { P_m(v(x(t)), θ(x(t)), τ(x(t))) + P_h } dt,
//!
//! the motive power P_m (a function of the terrain) plus a constant hotel load P_h, and seeks the
//! tour x* = argmin E_t that visits every waypoint. At the constant commanded speed v this is a
//! cost per metre: the motive energy per metre e_m(x) = P_m / v, which the robot learns, plus the
//! hotel load per metre P_h / v, which it knows. MartinCorke §3.1 models e_m with a zero-mean GP with
//! the squared exponential kernel of its Eq. 1, k(x, x') = σ_f² exp(−‖x − x'‖² / (2 l²)), with
//! σ_f and l learnt, on samples binned into cells; §3.2 plans with D* between every pair of
//! waypoints and orders them with an exact TSP; the first tour is the shortest one (the GP is
//! zero everywhere, so only the hotel load counts, decision 12), and the zero mean makes unseen
//! ground look cheap, which draws the robot into exploring it. The loop repeats for 25 tours or
//! until it converges.
//!
//! # This implementation
//!
//! * [`measure`]: the sensor sink of a tour. E_t is integrated from the power stream
//!   (trapezoids); e_m comes from [`strider_learn::signals::EnergyCost`] over a short window,
//!   fed with a moving average of the noisy pose stream (path lengths of raw 30 Hz poses with
//!   millimetre noise would be dominated by the noise). Windows that contain a turn in place
//!   are not learnt from: turning energy is not a property of the ground (MartinCorke §5 leaves it
//!   out of the model too), and a window with little travel turns it into a huge J/m.
//! * [`model`]: the samples binned into square cells (bin mean of e_m, MartinCorke §3.1), and the
//!   zero-mean GP of Eq. 1 on the bin centres, refitted after every tour with hyperparameters by
//!   type-II maximum likelihood within bounds ([`strider_learn::gp::fit_hyperparameters`]).
//! * [`route`]: the planning grid over the planning area with per-metre cost
//!   max(μ(x), 0) + P_h / v, Dijkstra between every pair of waypoints (our stand-in for D*, which
//!   computes the same cheapest paths), the exact TSP (Held–Karp in [`strider_plan::gtsp`]), and
//!   a pull of each grid path taut where the straight line is no dearer under the model (the
//!   robot turns in place at every kink of an 8-connected staircase, which costs energy the
//!   model does not see).
//! * [`run_energy_tours`]: the loop. Tour k drives the current plan, bins its samples, refits
//!   the GP and re-plans; when the new plan equals the one just driven (the same path within
//!   [`EnergyTourParams::unchanged_tolerance_m`]) the tour has converged, learning stops and the
//!   robot keeps driving that tour until the last one. [`drive_fixed_tour`] drives one plan
//!   every time: with [`plan_shortest`] it is the always-shortest baseline.
//!
//! The loop reaches the robot only through [`Robot`]: it reads poses and power, never the world.

pub mod measure;
pub mod model;
pub mod route;

pub use measure::TourMeasurement;
pub use model::{BinValue, EnergyMap, EnergyModel, FitSummary};
pub use route::{MAX_WAYPOINTS, MIN_COST, PlannedTour, TourPlanner};

use serde::Serialize;
use strider_core::interface::Robot;
use strider_core::{GaitId, Point2};
use strider_learn::gp::{GpError, GpParams, HyperBounds, Kernel, KernelKind};
use strider_learn::signals::SignalError;
use strider_plan::SolveError;
use strider_plan::grid::{GridError, SearchError};
use thiserror::Error;

use measure::EnergyMeter;

/// Everything the repeated-tour loop needs to know: the task, the robot's settings, and the
/// learning and planning constants. The CLI fills it from a scenario; nothing here is ground
/// truth.
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyTourParams {
    /// The tour's waypoints; the first is the base where the robot stands at the start.
    pub waypoints: Vec<Point2>,
    /// Return to the base after the last waypoint.
    pub closed: bool,
    /// Lower-left corner of the planning area (cells whose centre lies inside are plannable).
    pub area_min: Point2,
    /// Upper-right corner of the planning area.
    pub area_max: Point2,
    /// Planning cell size, metres.
    pub cell_size: f64,
    /// The gait (drive mode) to use.
    pub gait: GaitId,
    /// Commanded driving speed v, m/s (the hotel load per metre is P_h / v).
    pub speed_mps: f64,
    /// Hotel load P_h, W.
    pub hotel_load_w: f64,
    /// Robot mass, kg (only for the cost of transport the energy signal also reports).
    pub mass_kg: f64,
    /// Number of tours (MartinCorke: 25).
    pub n_tours: usize,
    /// Pose stream rate, Hz (sizes the signal buffers; MartinCorke: 30 Hz).
    pub pose_rate_hz: f64,
    /// Power stream rate, Hz (sizes the signal buffers; MartinCorke: 10 Hz).
    pub power_rate_hz: f64,
    /// Robot time per control step, seconds.
    pub control_dt_s: f64,
    /// Window of one energy-per-metre sample, seconds.
    pub energy_window_s: f64,
    /// Span of the centred moving average over the pose stream, seconds.
    pub pose_smoothing_s: f64,
    /// A smoothed heading rate above this, rad/s, marks a turn; windows with a turn are not
    /// learnt from.
    pub turn_rate_threshold: f64,
    /// Windows whose mean speed is below this fraction of the commanded speed are not learnt
    /// from (the robot was standing).
    pub min_speed_fraction: f64,
    /// Side of the square bins the samples are averaged in, metres (MartinCorke §3.1).
    pub bin_size_m: f64,
    /// Initial lengthscale of the first hyperparameter fit, metres (later fits start from the
    /// previous result).
    pub initial_lengthscale: f64,
    /// Bounds of the hyperparameter fit (MartinCorke Eq. 1: σ_f and l are learnt).
    pub hyper_bounds: HyperBounds,
    /// Two plans are the same tour when no point of either path lies farther than this from
    /// the other path, metres.
    pub unchanged_tolerance_m: f64,
    /// A tour that takes longer than this factor times its planned driving time (plus a
    /// minute for turns) has failed.
    pub timeout_factor: f64,
}

impl EnergyTourParams {
    /// The task (waypoints, closed or open, planning area and cell size) and the robot (gait,
    /// speed, hotel load, mass) with the defaults of MartinCorke for everything else: 25 tours,
    /// 30 Hz poses, 10 Hz power, 0.1 m bins, SE kernel with fitted hyperparameters.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        waypoints: Vec<Point2>,
        closed: bool,
        area_min: Point2,
        area_max: Point2,
        cell_size: f64,
        gait: GaitId,
        speed_mps: f64,
        hotel_load_w: f64,
        mass_kg: f64,
    ) -> Self {
        Self {
            waypoints,
            closed,
            area_min,
            area_max,
            cell_size,
            gait,
            speed_mps,
            hotel_load_w,
            mass_kg,
            n_tours: 25,
            pose_rate_hz: 30.0,
            power_rate_hz: 10.0,
            control_dt_s: 0.1,
            energy_window_s: 0.5,
            pose_smoothing_s: 0.5,
            turn_rate_threshold: 0.3,
            min_speed_fraction: 0.25,
            bin_size_m: 0.1,
            initial_lengthscale: 0.3,
            // Lengthscales from one to three bins. At least one: the GP must reach the
            // neighbouring bins, or every gap between two driven paths would look unexplored.
            // At most three: the samples lie along the few lines the robot drove, across which
            // the lengthscale is not identified, so the fit runs to whatever upper bound it is
            // given; beyond a few bins it spreads one crossing of the carpet over the whole
            // arena and the optimism of the zero mean (MartinCorke §3.2: visited cells are known,
            // unvisited ones optimistically cheap) never draws the robot anywhere. Signal and
            // noise variances span the J/m a small robot can show.
            hyper_bounds: HyperBounds {
                lengthscale: (0.1, 0.3),
                signal_variance: (1e-2, 1e4),
                noise_variance: (1e-4, 1e2),
                max_iterations: 100,
            },
            unchanged_tolerance_m: 0.1,
            timeout_factor: 5.0,
        }
    }

    /// Checks every number; the first invalid one is the error.
    pub fn validate(&self) -> Result<(), TourError> {
        let positive = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(TourError::BadParameter {
                    name,
                    value: v,
                    why: "must be a positive number",
                })
            }
        };
        let non_negative = |name: &'static str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(TourError::BadParameter {
                    name,
                    value: v,
                    why: "must be a non-negative number",
                })
            }
        };
        positive("cell_size", self.cell_size)?;
        positive("speed_mps", self.speed_mps)?;
        non_negative("hotel_load_w", self.hotel_load_w)?;
        positive("mass_kg", self.mass_kg)?;
        positive("pose_rate_hz", self.pose_rate_hz)?;
        positive("power_rate_hz", self.power_rate_hz)?;
        positive("control_dt_s", self.control_dt_s)?;
        positive("energy_window_s", self.energy_window_s)?;
        non_negative("pose_smoothing_s", self.pose_smoothing_s)?;
        positive("turn_rate_threshold", self.turn_rate_threshold)?;
        non_negative("min_speed_fraction", self.min_speed_fraction)?;
        positive("bin_size_m", self.bin_size_m)?;
        positive("initial_lengthscale", self.initial_lengthscale)?;
        non_negative("unchanged_tolerance_m", self.unchanged_tolerance_m)?;
        positive("timeout_factor", self.timeout_factor)?;
        for (name, v) in [
            ("area_min.x", self.area_min.x),
            ("area_min.y", self.area_min.y),
            ("area_max.x", self.area_max.x),
            ("area_max.y", self.area_max.y),
        ] {
            if !v.is_finite() {
                return Err(TourError::BadParameter {
                    name,
                    value: v,
                    why: "must be finite",
                });
            }
        }
        // Checked here as well as by the fit, so that bad bounds stop the loop before tour 1.
        let b = &self.hyper_bounds;
        for (name, (lo, hi)) in [
            ("hyper_bounds.lengthscale", b.lengthscale),
            ("hyper_bounds.signal_variance", b.signal_variance),
            ("hyper_bounds.noise_variance", b.noise_variance),
        ] {
            positive(name, lo)?;
            positive(name, hi)?;
            if lo > hi {
                return Err(TourError::BadParameter {
                    name,
                    value: lo,
                    why: "must not exceed its upper bound",
                });
            }
        }
        if self.n_tours == 0 {
            return Err(TourError::BadParameter {
                name: "n_tours",
                value: 0.0,
                why: "must be at least 1",
            });
        }
        Ok(())
    }

    /// The hotel load per metre P_h / v, J/m (decision 12: added to the learned motive energy).
    pub fn hotel_per_m(&self) -> f64 {
        self.hotel_load_w / self.speed_mps
    }

    /// The GP of MartinCorke Eq. 1 before any fit: zero prior mean, SE kernel with the initial
    /// lengthscale, unit signal variance and a small noise (replaced by the first fit).
    pub fn initial_gp(&self) -> GpParams {
        GpParams {
            kernel: Kernel {
                kind: KernelKind::SquaredExponential,
                lengthscales: vec![self.initial_lengthscale],
                signal_variance: 1.0,
            },
            noise_variance: 0.01,
            prior_mean: 0.0,
        }
    }
}

/// What can go wrong in the repeated-tour loop.
#[derive(Debug, Error)]
pub enum TourError {
    /// A parameter out of its domain.
    #[error("parameter {name} = {value} {why}")]
    BadParameter {
        /// Parameter name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is required.
        why: &'static str,
    },
    /// Fewer than two waypoints.
    #[error("a tour needs the base and at least one more waypoint, got {0} waypoint(s)")]
    TooFewWaypoints(usize),
    /// More waypoints than the exact TSP takes.
    #[error("{count} waypoints are too many for the exact TSP (at most {max})")]
    TooManyWaypoints {
        /// Number of waypoints.
        count: usize,
        /// The most the exact solver takes.
        max: usize,
    },
    /// A waypoint with a non-finite coordinate.
    #[error("waypoint {index} ({x}, {y}) is not a finite point")]
    NonFiniteWaypoint {
        /// Index in the tour.
        index: usize,
        /// x.
        x: f64,
        /// y.
        y: f64,
    },
    /// A waypoint the robot cannot reach because it lies outside the planning area.
    #[error("waypoint {index} ({x:.3}, {y:.3}) is unreachable: outside the planning area {area}")]
    WaypointOutsideArea {
        /// Index in the tour.
        index: usize,
        /// x.
        x: f64,
        /// y.
        y: f64,
        /// The area, for the message.
        area: String,
    },
    /// Two waypoints in the same planning cell.
    #[error(
        "waypoints {first} and {second} are duplicates: both at ({x:.3}, {y:.3}) within one {cell} m cell"
    )]
    DuplicateWaypoint {
        /// The earlier index.
        first: usize,
        /// The later index.
        second: usize,
        /// x of the later one.
        x: f64,
        /// y of the later one.
        y: f64,
        /// The cell size.
        cell: f64,
    },
    /// No path between two waypoints on the planning grid.
    #[error("waypoint {to} cannot be reached from waypoint {from}")]
    Unreachable {
        /// Source waypoint index.
        from: usize,
        /// Target waypoint index.
        to: usize,
    },
    /// The GP could not be fitted.
    #[error("energy model: {0}")]
    Gp(#[from] GpError),
    /// The planning grid was rejected.
    #[error("planning grid: {0}")]
    Grid(#[from] GridError),
    /// A search could not start.
    #[error("path search: {0}")]
    Search(#[from] SearchError),
    /// The TSP solver rejected the instance.
    #[error("TSP: {0}")]
    Tsp(#[from] SolveError),
    /// The energy signal rejected its parameters.
    #[error("energy signal: {0}")]
    Signal(#[from] SignalError),
    /// The robot failed.
    #[error("robot: {0}")]
    Robot(String),
    /// No pose arrived although the robot was driving.
    #[error("tour {tour}: no pose arrived from the robot")]
    NoPose {
        /// 1-based tour index.
        tour: usize,
    },
    /// A tour took far longer than planned.
    #[error("tour {tour} did not finish within {limit_s:.0} s of robot time")]
    Timeout {
        /// 1-based tour index.
        tour: usize,
        /// The limit, seconds.
        limit_s: f64,
    },
    /// The robot refused to go on for too long.
    #[error("tour {tour}: the robot was blocked near ({x:.3}, {y:.3})")]
    Blocked {
        /// 1-based tour index.
        tour: usize,
        /// Last pose x.
        x: f64,
        /// Last pose y.
        y: f64,
    },
    /// The robot finished the path without passing a waypoint.
    #[error("tour {tour}: waypoint {index} was missed (closest pose {dist_m:.3} m away)")]
    WaypointMissed {
        /// 1-based tour index.
        tour: usize,
        /// Waypoint index.
        index: usize,
        /// Closest distance of the pose stream to it.
        dist_m: f64,
    },
}

/// One driven tour.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TourRecord {
    /// 1-based tour index.
    pub tour: usize,
    /// The plan driven.
    pub plan: PlannedTour,
    /// What was measured while driving it.
    pub measured: TourMeasurement,
    /// Whether the tour's samples were learnt from (false once converged, and in fixed-tour
    /// runs).
    pub learned: bool,
    /// The hyperparameter fit after this tour (when it was learnt from).
    pub fit: Option<FitSummary>,
    /// Whether the plan made after this tour differs from the one driven (`None` when no plan
    /// was made).
    pub next_changed: Option<bool>,
    /// Largest distance between the plan driven and the next one, metres.
    pub next_deviation_m: Option<f64>,
}

/// The outcome of the repeated-tour loop.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToursOutcome {
    /// Every tour in order.
    pub tours: Vec<TourRecord>,
    /// The first tour after which the plan did not change (`None`: it never converged).
    pub convergence_tour: Option<usize>,
    /// The learnt energy map after each learnt tour: (tour, map).
    pub maps: Vec<(usize, EnergyMap)>,
}

/// Validated task geometry: the planner and the waypoints on its grid.
fn prepare(params: &EnergyTourParams) -> Result<TourPlanner, TourError> {
    params.validate()?;
    TourPlanner::new(params)
}

/// The always-shortest tour: the plan of the empty model, on which only the hotel load counts
/// (what tour 1 of [`run_energy_tours`] drives).
pub fn plan_shortest(params: &EnergyTourParams) -> Result<PlannedTour, TourError> {
    let mut planner = prepare(params)?;
    let model = EnergyModel::new(params);
    let grid = planner.cost_grid(&model.map(planner.rect(), params.cell_size)?, params)?;
    planner.plan(&grid)
}

/// Drives `plan` `n_tours` times without learning (the always-shortest baseline with
/// [`plan_shortest`], or any other fixed tour such as one planned on known costs).
pub fn drive_fixed_tour<R: Robot>(
    robot: &mut R,
    params: &EnergyTourParams,
    plan: &PlannedTour,
    mut observe: impl FnMut(&TourRecord),
) -> Result<Vec<TourRecord>, TourError> {
    params.validate()?;
    let mut meter = EnergyMeter::new(params)?;
    robot.set_gait(params.gait);
    let mut out = Vec::with_capacity(params.n_tours);
    for k in 1..=params.n_tours {
        let measured = meter.drive(robot, params, plan, k)?;
        let rec = TourRecord {
            tour: k,
            plan: plan.clone(),
            measured,
            learned: false,
            fit: None,
            next_changed: None,
            next_deviation_m: None,
        };
        observe(&rec);
        out.push(rec);
    }
    Ok(out)
}

/// The MartinCorke loop: plan on the current model (tour 1: the shortest tour), drive, bin the
/// energy per metre, refit the GP, re-plan; once a re-plan leaves the tour unchanged, keep
/// driving it without learning until `n_tours` tours are done. `observe` sees each tour as it
/// ends.
pub fn run_energy_tours<R: Robot>(
    robot: &mut R,
    params: &EnergyTourParams,
    mut observe: impl FnMut(&TourRecord),
) -> Result<ToursOutcome, TourError> {
    let mut planner = prepare(params)?;
    let mut meter = EnergyMeter::new(params)?;
    let mut model = EnergyModel::new(params);
    let rect = planner.rect();
    let grid = planner.cost_grid(&model.map(rect, params.cell_size)?, params)?;
    let mut plan = planner.plan(&grid)?;
    robot.set_gait(params.gait);
    let mut tours = Vec::with_capacity(params.n_tours);
    let mut maps = Vec::new();
    let mut convergence_tour = None;
    for k in 1..=params.n_tours {
        let measured = meter.drive(robot, params, &plan, k)?;
        let learn = convergence_tour.is_none();
        let mut rec = TourRecord {
            tour: k,
            plan: plan.clone(),
            measured,
            learned: learn,
            fit: None,
            next_changed: None,
            next_deviation_m: None,
        };
        if learn {
            model.add_samples(&meter.take_samples());
            rec.fit = Some(model.refit()?);
            let map = model.map(rect, params.cell_size)?;
            let grid = planner.cost_grid(&map, params)?;
            maps.push((k, map));
            let next = planner.plan(&grid)?;
            let deviation = plan.deviation_m(&next, params.cell_size / 4.0);
            let changed = deviation > params.unchanged_tolerance_m;
            rec.next_changed = Some(changed);
            rec.next_deviation_m = Some(deviation);
            if changed {
                plan = next;
            } else {
                convergence_tour = Some(k);
            }
        } else {
            // Converged: the samples are not learnt from, but the buffer must not grow.
            meter.take_samples();
        }
        observe(&rec);
        tours.push(rec);
    }
    Ok(ToursOutcome {
        tours,
        convergence_tour,
        maps,
    })
}

/// Parameters of the unit tests' 2 × 1 m arena: a closed tour over `waypoints`, 5 cm cells, gait
/// 0 at 0.1 m/s, 0.2 W hotel load, a 0.5 kg rover.
#[cfg(test)]
pub(crate) fn test_params(waypoints: Vec<Point2>) -> EnergyTourParams {
    EnergyTourParams::new(
        waypoints,
        true,
        Point2::new(0.0, 0.0),
        Point2::new(2.0, 1.0),
        0.05,
        GaitId(0),
        0.1,
        0.2,
        0.5,
    )
}
