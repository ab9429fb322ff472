//! The MartinCorke repeated-tour loop against a small kinematic rover behind the robot interface: a
//! skid-steered robot that turns in place and drives at 0.1 m/s, reports a noisy 30 Hz pose and
//! a noisy 10 Hz power, and draws more power on a carpet band that lies across the straight
//! line between the base and the far waypoint (a MartinCorke §4 setup in which the carpet takes most of
//! the straight line, so learning has something to gain).

use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::{GaitId, Point2, Point3, PoseStamped, Proprioception};
use strider_explore::energy_tours::{
    EnergyMap, EnergyTourParams, TourError, TourPlanner, drive_fixed_tour, plan_shortest,
    run_energy_tours,
};

const HOTEL_W: f64 = 0.21;
const TIMBER_W: f64 = 0.63;
const CARPET_W: f64 = 1.21;
const SPEED: f64 = 0.1;
const TURN_RATE: f64 = 1.0;

/// The carpet: a band across the straight line from (0.3, 0.75) to (1.7, 0.75).
fn on_carpet(p: Point2) -> bool {
    (0.45..=1.55).contains(&p.x) && (0.6..=0.95).contains(&p.y)
}

/// A deterministic normal stream (xorshift64* and Box–Muller).
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

/// Follows polylines: turns in place while the heading error exceeds 20°, drives otherwise;
/// motion is integrated at the pose rate.
struct Rover {
    pos: Point2,
    yaw: f64,
    path: Vec<Point2>,
    next: usize,
    tick: u64,
    active: bool,
    noise: Noise,
}

const TICK: f64 = 1.0 / 30.0;

impl Rover {
    fn new(at: Point2, seed: u64) -> Self {
        Self {
            pos: at,
            yaw: 0.0,
            path: Vec::new(),
            next: 0,
            tick: 0,
            active: false,
            noise: Noise(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1),
        }
    }

    fn step(&mut self) {
        while self.next < self.path.len() && self.pos.dist(self.path[self.next]) <= 0.025 {
            self.next += 1;
        }
        self.active = self.next < self.path.len();
        if !self.active {
            return;
        }
        let t = self.path[self.next];
        let bearing = (t.y - self.pos.y).atan2(t.x - self.pos.x);
        let err = strider_core::geom::wrap_angle(bearing - self.yaw);
        let max_turn = TURN_RATE * TICK;
        self.yaw = strider_core::geom::wrap_angle(self.yaw + err.clamp(-max_turn, max_turn));
        if err.abs() > 20f64.to_radians() {
            return;
        }
        let d = (SPEED * TICK).min(self.pos.dist(t));
        self.pos = Point2::new(
            self.pos.x + d * self.yaw.cos(),
            self.pos.y + d * self.yaw.sin(),
        );
    }
}

impl Robot for Rover {
    type Error = std::convert::Infallible;

    fn now(&self) -> f64 {
        self.tick as f64 * TICK
    }

    fn follow(&mut self, path: &[Point2]) {
        self.path = path.to_vec();
        self.next = 0;
    }

    fn set_gait(&mut self, _gait: GaitId) {}

    fn advance(&mut self, dt: f64, sink: &mut dyn SensorSink) -> Result<MotionState, Self::Error> {
        let end = ((self.now() + dt) / TICK).round() as u64;
        while self.tick < end {
            self.step();
            self.tick += 1;
            let t = self.now();
            let (nx, ny) = (0.002 * self.noise.normal(), 0.002 * self.noise.normal());
            sink.on_pose(&PoseStamped {
                stamp: t,
                position: Point3::new(self.pos.x + nx, self.pos.y + ny, 0.0),
                yaw: self.yaw + 0.01 * self.noise.normal(),
                ..Default::default()
            });
            if self.tick.is_multiple_of(3) {
                let motive = match (self.active, on_carpet(self.pos)) {
                    (false, _) => 0.0,
                    (true, true) => CARPET_W,
                    (true, false) => TIMBER_W,
                };
                sink.on_proprioception(&Proprioception {
                    stamp: t,
                    power_w: (HOTEL_W + motive) * (1.0 + 0.03 * self.noise.normal()),
                    ..Default::default()
                });
            }
        }
        Ok(MotionState {
            idle: self.next >= self.path.len(),
            blocked: false,
        })
    }
}

fn params(n_tours: usize) -> EnergyTourParams {
    let mut p = EnergyTourParams::new(
        vec![Point2::new(0.3, 0.75), Point2::new(1.7, 0.75)],
        true,
        Point2::new(0.05, 0.05),
        Point2::new(1.95, 1.45),
        0.05,
        GaitId(0),
        SPEED,
        HOTEL_W,
        0.5,
    );
    p.n_tours = n_tours;
    p
}

/// The true motive J/m of the rover's world on the planner's cells.
fn truth(p: &EnergyTourParams, planner: &TourPlanner) -> EnergyMap {
    let rect = planner.rect();
    EnergyMap {
        rect,
        cell_size: p.cell_size,
        mean: rect
            .cells()
            .map(|c| {
                let w = if on_carpet(c.center(p.cell_size)) {
                    CARPET_W
                } else {
                    TIMBER_W
                };
                (w / SPEED) as f32
            })
            .collect(),
        variance: vec![0.0; rect.len()],
        bins: Vec::new(),
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

#[test]
fn learning_avoids_the_carpet_and_pays_off() {
    let p = params(12);
    let out = run_energy_tours(&mut Rover::new(p.waypoints[0], 7), &p, |_| {}).unwrap();
    let e: Vec<f64> = out.tours.iter().map(|t| t.measured.energy_j).collect();

    // Tour 1 is the always-shortest tour: the straight line there and back.
    let shortest = plan_shortest(&p).unwrap();
    assert_eq!(out.tours[0].plan, shortest);
    assert!(
        (shortest.length_m - 2.8).abs() < 1e-9,
        "{}",
        shortest.length_m
    );
    let base = drive_fixed_tour(&mut Rover::new(p.waypoints[0], 7), &p, &shortest, |_| {}).unwrap();
    let s: Vec<f64> = base.iter().map(|t| t.measured.energy_j).collect();
    assert_eq!(e[0], s[0], "same robot, same commands, same noise");

    // What the planner reaches on the true costs bounds what learning can gain.
    let mut planner = TourPlanner::new(&p).unwrap();
    let known_plan = planner
        .plan(&planner.cost_grid(&truth(&p, &planner), &p).unwrap())
        .unwrap();
    let known =
        drive_fixed_tour(&mut Rover::new(p.waypoints[0], 7), &p, &known_plan, |_| {}).unwrap();
    let known_j = mean(
        &known
            .iter()
            .map(|t| t.measured.energy_j)
            .collect::<Vec<_>>(),
    );
    let shortest_j = mean(&s);
    assert!(
        known_j < 0.85 * shortest_j,
        "known {known_j} vs shortest {shortest_j}"
    );

    // It converges, and the converged tour keeps most of that gain.
    let c = out.convergence_tour.expect("converged");
    assert!(c <= 10, "converged at tour {c}");
    let converged_j = mean(&e[c - 1..]);
    let gain = shortest_j - converged_j;
    assert!(
        gain > 0.75 * (shortest_j - known_j),
        "tours {e:?}, known {known_j}"
    );
    assert!(converged_j < 0.9 * e[0], "tours {e:?}");
    // On the way it explored: some tour before convergence was longer than both.
    let longest = out.tours[..c]
        .iter()
        .map(|t| t.plan.length_m)
        .fold(0.0, f64::max);
    assert!(longest > out.tours[c - 1].plan.length_m + 0.5);
    // Once converged, the same plan is driven and nothing more is learnt.
    for t in &out.tours[c..] {
        assert_eq!(t.plan, out.tours[c - 1].plan);
        assert!(!t.learned && t.fit.is_none());
    }
    assert_eq!(out.maps.len(), c);
    let fit = out.tours[c - 1].fit.as_ref().unwrap();
    let (lo, hi) = p.hyper_bounds.lengthscale;
    assert!(fit.lengthscale >= lo && fit.lengthscale <= hi);

    // The learnt map knows the carpet is dearer than the timber it has driven on.
    let (_, map) = out.maps.last().unwrap();
    let at = |x: f64, y: f64| {
        let cell = strider_core::Cell::containing(x, y, p.cell_size).unwrap();
        map.mean[map.rect.index(cell).unwrap()] as f64
    };
    assert!(
        at(1.0, 0.75) > at(0.3, 0.75) + 3.0,
        "{} vs {}",
        at(1.0, 0.75),
        at(0.3, 0.75)
    );

    // Cumulative energy of exploring falls below always-shortest and stays there.
    let (mut a, mut b) = (0.0, 0.0);
    let mut below_from = None;
    for k in 0..e.len() {
        a += e[k];
        b += s[k];
        if a < b {
            below_from.get_or_insert(k + 1);
        } else {
            below_from = None;
        }
    }
    assert!(
        below_from.is_some_and(|k| k < 10),
        "{below_from:?}: {e:?} vs {s:?}"
    );
}

#[test]
fn runs_are_deterministic() {
    let p = params(3);
    let a = run_energy_tours(&mut Rover::new(p.waypoints[0], 3), &p, |_| {}).unwrap();
    let b = run_energy_tours(&mut Rover::new(p.waypoints[0], 3), &p, |_| {}).unwrap();
    assert_eq!(a, b);
}

#[test]
fn bad_tours_are_refused_before_driving() {
    let mut p = params(1);
    // The same point twice, and two points a few millimetres apart in one planning cell.
    for dup in [Point2::new(0.3, 0.75), Point2::new(1.71, 0.76)] {
        p.waypoints = vec![Point2::new(0.3, 0.75), Point2::new(1.715, 0.765), dup];
        let mut robot = Rover::new(p.waypoints[0], 1);
        let e = run_energy_tours(&mut robot, &p, |_| {}).unwrap_err();
        assert!(
            matches!(e, TourError::DuplicateWaypoint { second: 2, .. }),
            "{e}"
        );
        assert!(e.to_string().contains("duplicates"), "{e}");
        assert_eq!(robot.now(), 0.0, "nothing was driven");
    }
    let mut robot = Rover::new(p.waypoints[0], 1);

    p.waypoints = vec![Point2::new(0.3, 0.75), Point2::new(2.5, 0.75)];
    let e = run_energy_tours(&mut robot, &p, |_| {}).unwrap_err();
    assert!(e.to_string().contains("unreachable"), "{e}");

    let mut p = params(1);
    p.speed_mps = 0.0;
    assert!(matches!(
        run_energy_tours(&mut robot, &p, |_| {}).unwrap_err(),
        TourError::BadParameter {
            name: "speed_mps",
            ..
        }
    ));
    let mut p = params(1);
    p.energy_window_s = f64::NAN;
    assert!(plan_shortest(&p).is_err());
}
