//! Tests of the streaming cost signals (Prágr22 Eq. 19–20, Prágr19 roll variance,
//! MartinCorke/Prágr18 energy).

use approx::assert_relative_eq;
use strider_core::geom::Point3;
use strider_core::msg::{GaitId, PoseStamped, Proprioception};
use strider_learn::signals::{
    EnergyCost, EnergyParams, EnergySample, FallbackTimer, InverseVelocityCost,
    InverseVelocityParams, RATIO_CAP, RollVarianceCost, RollVarianceParams, SignalError,
    TurningTime, hotel_load_per_metre, tanh_bound,
};

const HZ: f64 = 20.0;

fn pose(k: u32, x: f64, gait: u8) -> PoseStamped {
    PoseStamped {
        stamp: k as f64 / HZ,
        position: Point3::new(x, 2.0, 0.1),
        gait: GaitId(gait),
        ..Default::default()
    }
}

/// Feeds tick `k` to `e`: the pose at `x` in gait 0, then a reading of `power(stamp)` watts.
fn energy_tick(
    e: &mut EnergyCost,
    k: u32,
    x: f64,
    power: impl FnOnce(f64) -> f64,
) -> Option<EnergySample> {
    let p = pose(k, x, 0);
    e.push_pose(&p);
    e.push(&Proprioception {
        stamp: p.stamp,
        power_w: power(p.stamp),
        ..Default::default()
    })
}

fn iv(window: f64, v_max: Vec<f64>) -> InverseVelocityCost {
    InverseVelocityCost::new(InverseVelocityParams::new(window, v_max, 20.0, 20.0)).unwrap()
}

#[test]
fn constant_speed_gives_hand_value_and_first_emission_after_one_window() {
    // v_max = 0.1 m/s, v = 0.05 m/s: v⁻¹/v_max⁻¹ = 2; c = 20·tanh(2/20) = 1.99335989249911...
    let hand = 20.0 * 0.1f64.tanh();
    assert_relative_eq!(hand, 1.993_359_892_499_116_4, max_relative = 1e-15);
    let mut c = iv(5.0, vec![0.1]);
    let mut first = None;
    for k in 0..400u32 {
        let t = k as f64 / HZ;
        if let Some(s) = c.push(&pose(k, 0.05 * t, 0), GaitId(0)) {
            first.get_or_insert(k);
            assert_relative_eq!(s.raw, 2.0, max_relative = 1e-9);
            assert_relative_eq!(s.cost, hand, max_relative = 1e-9);
            assert_eq!(s.gait, GaitId(0));
            assert!(!c.is_stuck());
        }
    }
    // 5 s at 20 Hz: the window is full at the 101st pose.
    assert_eq!(first, Some(100));
}

#[test]
fn ideal_speed_gives_about_one() {
    let mut c = iv(1.0, vec![0.25]);
    let mut last = None;
    for k in 0..100u32 {
        last = c
            .push(&pose(k, 0.25 * k as f64 / HZ, 0), GaitId(0))
            .or(last);
    }
    let s = last.unwrap();
    assert_relative_eq!(s.cost, 20.0 * (1.0f64 / 20.0).tanh(), max_relative = 1e-9);
    assert!((s.cost - 1.0).abs() < 1e-3);
}

#[test]
fn attributed_to_the_window_middle_pose() {
    let mut c = iv(5.0, vec![0.1]);
    for k in 0..300u32 {
        let x = 0.05 * k as f64 / HZ;
        if let Some(s) = c.push(&pose(k, x, 0), GaitId(0)) {
            let mid = k - 50;
            assert_relative_eq!(s.stamp, mid as f64 / HZ, epsilon = 1e-12);
            assert_relative_eq!(s.position.x, 0.05 * mid as f64 / HZ, epsilon = 1e-12);
            assert_eq!(s.position.y, 2.0);
        }
    }
}

#[test]
fn gait_change_suppresses_one_window_and_resets_smoothing() {
    // Gait 0: v_max 0.1; gait 1: v_max 0.2; the robot walks 0.05 m/s throughout.
    let mut c = iv(5.0, vec![0.1, 0.2]);
    let mut emitted = Vec::new();
    for k in 0..500u32 {
        let g = if k < 200 { 0 } else { 1 };
        let x = 0.05 * k as f64 / HZ;
        if let Some(s) = c.push(&pose(k, x, g), GaitId(g)) {
            emitted.push((k, s));
        }
    }
    // Emissions 100..=199 in gait 0, none in 200..300 (the window holds the change), from 300 on
    // in gait 1.
    let ks: Vec<u32> = emitted.iter().map(|(k, _)| *k).collect();
    assert!(ks.iter().all(|&k| !(200..300).contains(&k)));
    assert!(ks.contains(&199));
    assert!(ks.contains(&300));
    let (_, first_new) = emitted.iter().find(|(k, _)| *k == 300).unwrap();
    assert_eq!(first_new.gait, GaitId(1));
    // Ratio 0.2/0.05 = 4, not mixed with gait 0's ratio of 2.
    assert_relative_eq!(first_new.raw, 4.0, max_relative = 1e-9);
    assert_relative_eq!(first_new.cost, 20.0 * 0.2f64.tanh(), max_relative = 1e-9);
}

#[test]
fn stopping_saturates_and_flags_stuck() {
    let mut c = iv(5.0, vec![0.1]);
    let mut last = None;
    let mut stuck_at = None;
    for k in 0..600u32 {
        let t = k as f64 / HZ;
        // Walks 10 s at v_max, then stands still.
        let x = 0.1 * t.min(10.0);
        let s = c.push(&pose(k, x, 0), GaitId(0));
        if k < 200 {
            assert!(!c.is_stuck(), "stuck while walking at k={k}");
        }
        if c.is_stuck() && stuck_at.is_none() {
            stuck_at = Some(k);
        }
        if let Some(s) = s {
            assert!(s.cost.is_finite() && s.raw.is_finite());
            assert!(s.cost <= 20.0);
            last = Some(s);
        }
    }
    // The window ending at t > 10 s holds 0.1·(15 − t) m of motion: ratio 5 / (15 − t) exceeds
    // c_max = 20 from t > 14.75 s (k = 295 is the exact boundary), and is saturated once the window is still (k ≥ 300).
    let k_stuck = stuck_at.unwrap();
    assert!((295..=296).contains(&k_stuck), "stuck at {k_stuck}"); // 295 is the float boundary
    assert!(c.is_stuck());
    assert_eq!(c.last_ratio(), Some(RATIO_CAP));
    let last = last.unwrap();
    assert_eq!(last.cost, 20.0);
}

#[test]
fn stuck_is_judged_on_a_window_of_one_gait_and_comes_with_its_sample() {
    // Gait 1 walks at v_max for 10 s, then gait 0 stands still (stuck). The window straddling
    // the switch is not judged; the first window walked wholly in gait 0 is stuck, and the same
    // tick emits gait 0's sample at the saturated cost.
    let mut c = iv(5.0, vec![0.1, 0.1]);
    let mut first_stuck = None;
    for k in 0..400u32 {
        let t = k as f64 / HZ;
        let gait = if t < 10.0 { 1 } else { 0 };
        let s = c.push(&pose(k, 0.1 * t.min(10.0), gait), GaitId(gait));
        if t < 15.0 {
            assert!(!c.is_stuck(), "stuck on a mixed window at t={t}");
            assert!(
                s.is_none_or(|s| s.gait == GaitId(1)),
                "gait 0 sample at t={t}"
            );
        }
        if c.is_stuck() && first_stuck.is_none() {
            first_stuck = Some(k);
            let s = s.expect("the stuck window is a sample");
            assert_eq!(s.gait, GaitId(0));
            assert_eq!(s.cost, 20.0);
        }
    }
    // The first window with one gait only starts at the first gait-0 pose (k = 200).
    assert_eq!(first_stuck, Some(300));
}

#[test]
fn non_finite_and_out_of_order_poses_are_skipped_and_counted() {
    let mut c = iv(1.0, vec![0.1]);
    for k in 0..100u32 {
        let mut p = pose(k, 0.05 * k as f64 / HZ, 0);
        if k % 10 == 3 {
            p.position.x = f64::NAN;
        }
        if k % 10 == 7 {
            p.stamp = f64::INFINITY;
        }
        if let Some(s) = c.push(&p, GaitId(0)) {
            assert!(s.cost.is_finite());
            assert_relative_eq!(s.raw, 2.0, max_relative = 1e-9);
        }
        // A repeated stamp (of an accepted pose) is out of order.
        if k % 10 != 3 && k % 10 != 7 {
            let _ = c.push(&pose(k, 0.0, 0), GaitId(0));
        }
    }
    let sk = c.skips();
    assert_eq!(sk.non_finite, 20);
    assert_eq!(sk.out_of_order, 80);
    assert!(c.push(&pose(200, 0.0, 9), GaitId(9)).is_none());
    assert_eq!(c.skips().unknown_gait, 1);
}

#[test]
fn invalid_parameters_are_errors() {
    let bad = InverseVelocityParams::new(f64::NAN, vec![0.1], 20.0, 20.0);
    assert!(matches!(
        InverseVelocityCost::new(bad),
        Err(SignalError::InvalidParameter {
            name: "window_s",
            ..
        })
    ));
    let bad = InverseVelocityParams::new(1.0, vec![0.0], 20.0, 20.0);
    assert!(InverseVelocityCost::new(bad).is_err());
    assert!(InverseVelocityCost::new(InverseVelocityParams::new(1.0, vec![], 20.0, 20.0)).is_err());
    assert!(FallbackTimer::new(-1.0).is_err());
    assert!(EnergyCost::new(EnergyParams::new(1.0, 0.0, 1.0)).is_err());
    let rp = RollVarianceParams {
        window_s: 0.0,
        ..Default::default()
    };
    assert!(RollVarianceCost::new(rp).is_err());
}

#[test]
fn buffers_never_grow() {
    let mut c = iv(5.0, vec![0.1]);
    let mut r = RollVarianceCost::new(RollVarianceParams::default()).unwrap();
    let mut e = EnergyCost::new(EnergyParams::new(5.0, 2.0, 1.0)).unwrap();
    let caps = (c.capacity(), r.capacity(), e.capacity());
    for k in 0..20_000u32 {
        let p = pose(k, 0.05 * k as f64 / HZ, (k / 3000 % 2) as u8);
        c.push_pose(&p);
        r.push_pose(&p);
        e.push_pose(&p);
        let pr = Proprioception {
            stamp: p.stamp,
            roll: (k as f64).sin() * 0.1,
            power_w: 5.0,
            ..Default::default()
        };
        r.push(&pr);
        e.push(&pr);
    }
    assert_eq!((c.capacity(), r.capacity(), e.capacity()), caps);
    assert_eq!(c.skips().overrun, 0);
    assert_eq!(r.skips().overrun, 0);
    assert_eq!(e.skips().overrun, 0);
}

#[test]
fn faster_than_configured_stream_counts_overruns_without_panicking() {
    let mut c = iv(1.0, vec![0.1]);
    for k in 0..1000u32 {
        let p = PoseStamped {
            stamp: k as f64 / 200.0, // 10x the configured 20 Hz
            position: Point3::new(k as f64 * 1e-4, 0.0, 0.0),
            ..Default::default()
        };
        if let Some(s) = c.push_pose(&p) {
            assert!(s.cost.is_finite());
        }
    }
    assert!(c.skips().overrun > 0);
}

/// Pseudo-random but deterministic roll values.
fn roll_value(k: u32) -> f64 {
    let x = (k as f64 * 12.9898).sin() * 43758.5453;
    0.05 * (x - x.floor() - 0.5)
}

fn direct_two_pass(v: &[f64]) -> f64 {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0)
}

fn run_roll(offset: f64) -> Vec<(u32, f64, f64)> {
    let mut r = RollVarianceCost::new(RollVarianceParams::default()).unwrap();
    let mut rolls = Vec::new();
    let mut out = Vec::new();
    for k in 0..600u32 {
        let p = pose(k, 0.05 * k as f64 / HZ, 0);
        r.push_pose(&p);
        let roll = offset + roll_value(k);
        rolls.push(roll);
        let pr = Proprioception {
            stamp: p.stamp,
            roll,
            ..Default::default()
        };
        if let Some(s) = r.push(&pr) {
            // Window [t - 10 s, t] at 20 Hz: 201 samples.
            let expected = direct_two_pass(&rolls[(k - 200) as usize..=k as usize]);
            out.push((k, s.cost, expected));
            assert_relative_eq!(s.stamp, (k - 100) as f64 / HZ, epsilon = 1e-12);
        }
    }
    out
}

#[test]
fn roll_variance_equals_direct_two_pass() {
    let out = run_roll(0.0);
    assert_eq!(out.first().map(|o| o.0), Some(200));
    assert_eq!(out.len(), 400);
    for (_, got, expected) in &out {
        assert_relative_eq!(*got, *expected, max_relative = 1e-12);
    }
}

#[test]
fn roll_variance_is_stable_under_a_large_offset() {
    let plain = run_roll(0.0);
    let shifted = run_roll(1e3);
    for ((_, a, _), (_, b, _)) in plain.iter().zip(&shifted) {
        // Representation error of 1e3 + x is ~1e-13 absolute; the variance (~2e-4) must keep
        // nearly all its digits.
        assert_relative_eq!(*a, *b, max_relative = 1e-8);
    }
}

#[test]
fn roll_variance_suppressed_across_a_gait_change() {
    let mut r = RollVarianceCost::new(RollVarianceParams::default()).unwrap();
    let mut ks = Vec::new();
    for k in 0..800u32 {
        let g = if k < 300 { 0 } else { 1 };
        let p = pose(k, 0.05 * k as f64 / HZ, g);
        r.push_pose(&p);
        let pr = Proprioception {
            stamp: p.stamp,
            roll: roll_value(k),
            ..Default::default()
        };
        if let Some(s) = r.push(&pr) {
            ks.push((k, s.gait));
        }
    }
    assert!(ks.iter().all(|&(k, _)| !(300..500).contains(&k)));
    assert!(ks.contains(&(299, GaitId(0))));
    assert!(ks.contains(&(500, GaitId(1))));
}

#[test]
fn energy_per_metre_equals_hand_value() {
    // 10 W total, 2 W hotel, 0.1 m/s, 2 kg, 5-s window: E = 50 J over 0.5 m.
    let mut e = EnergyCost::new(EnergyParams::new(5.0, 2.0, 2.0)).unwrap();
    let mut last = None;
    for k in 0..200u32 {
        if let Some(s) = energy_tick(&mut e, k, 0.1 * k as f64 / HZ, |_| 10.0) {
            last = Some((k, s));
        }
    }
    let (k, s) = last.unwrap();
    assert_eq!(k, 199);
    assert_relative_eq!(s.energy_j, 50.0, max_relative = 1e-9);
    assert_relative_eq!(s.distance_m, 0.5, max_relative = 1e-9);
    assert_relative_eq!(s.energy_per_m, 100.0, max_relative = 1e-9);
    assert_relative_eq!(s.motive_energy_per_m, 80.0, max_relative = 1e-9);
    assert_relative_eq!(s.hotel_per_m, 20.0, max_relative = 1e-9);
    assert_relative_eq!(
        s.hotel_per_m,
        hotel_load_per_metre(2.0, 0.1).unwrap(),
        max_relative = 1e-9
    );
    // CoT = P / (m g v) = 10 / (2 · 9.80665 · 0.1).
    assert_relative_eq!(
        s.cost_of_transport,
        10.0 / (2.0 * 9.806_65 * 0.1),
        max_relative = 1e-9
    );
    assert_relative_eq!(s.stamp, (199 - 50) as f64 / HZ, epsilon = 1e-12);
}

#[test]
fn energy_trapezoid_integrates_a_power_ramp() {
    // P(t) = t W over [t-1, t]: E = t - 0.5 J exactly by the trapezoid rule.
    let mut params = EnergyParams::new(1.0, 1.0, 0.0);
    params.gravity = 10.0;
    let mut e = EnergyCost::new(params).unwrap();
    let mut last = None;
    for k in 0..60u32 {
        last = energy_tick(&mut e, k, 0.2 * k as f64 / HZ, |t| t).or(last);
    }
    let s = last.unwrap();
    let t = 59.0 / HZ;
    assert_relative_eq!(s.energy_j, t - 0.5, max_relative = 1e-9);
    assert_relative_eq!(s.energy_per_m, (t - 0.5) / 0.2, max_relative = 1e-9);
}

#[test]
fn zero_distance_emits_nothing_and_never_inf() {
    let mut e = EnergyCost::new(EnergyParams::new(1.0, 2.0, 1.0)).unwrap();
    for k in 0..100u32 {
        assert!(energy_tick(&mut e, k, 3.0, |_| 7.0).is_none());
    }
    assert_eq!(e.short_windows(), 80);
    assert!(hotel_load_per_metre(1.0, 0.0).is_none());
    let bad = Proprioception {
        stamp: 100.0,
        power_w: f64::NAN,
        ..Default::default()
    };
    assert!(e.push(&bad).is_none());
    assert_eq!(e.skips().non_finite, 1);
}

#[test]
fn fallback_timer_runs_for_dt_fallback() {
    let mut f = FallbackTimer::new(3.0).unwrap();
    assert!(!f.update(0.0, false));
    assert!(f.update(1.0, true));
    assert!(f.update(2.0, true)); // no extension
    assert!(f.update(3.9, false));
    assert!(!f.update(4.0, false));
    assert!(!f.is_active(4.0));
    assert!(f.update(5.0, true));
    assert!(f.is_active(7.9));
    assert_eq!(f.triggers(), 2);
}

#[test]
fn tanh_bound_is_eq_20() {
    for r in [0.0, 0.5, 1.0, 2.0, 10.0, 100.0] {
        assert_relative_eq!(tanh_bound(r, 20.0), 20.0 * (r / 20.0).tanh());
    }
    assert_eq!(tanh_bound(-1.0, 20.0), 0.0);
}

// ---------------------------------------------------------------------------------------------
// Turning time.

const OMEGA: f64 = 0.1;

/// A baseline shorter than any tick: the heading rate from one pose to the next.
const TICK: f64 = 0.001;

/// Brute force: Σ over accepted poses with stamp ≥ now − span of their tick's duration when the
/// heading rate exceeds OMEGA, the rate taken from the newest earlier pose at least `baseline`
/// old and at least `baseline · rate_hz` poses back (the first pose when none is).
fn brute_turning(accepted: &[(f64, f64)], span: f64, baseline: f64, rate_hz: f64) -> f64 {
    let poses = ((baseline * rate_hz).round() as usize).max(1);
    let Some(&(now, _)) = accepted.last() else {
        return 0.0;
    };
    (1..accepted.len())
        .filter(|&i| accepted[i].0 >= now - span)
        .map(|i| {
            let (t, y) = accepted[i];
            let j = (0..i)
                .rev()
                .find(|&j| accepted[j].0 <= t - baseline && i - j >= poses)
                .unwrap_or(0);
            let rate =
                strider_core::geom::wrap_angle(y - accepted[j].1).abs() / (t - accepted[j].0);
            if rate > OMEGA {
                t - accepted[i - 1].0
            } else {
                0.0
            }
        })
        .sum()
}

proptest::proptest! {
    #[test]
    fn turning_time_equals_brute_force(
        steps in proptest::collection::vec((0.01f64..0.2, -0.05f64..0.05, 0u8..20), 1..400),
        window in 0.3f64..3.0,
        extra in 0.0f64..3.0,
        baseline in proptest::prop_oneof![proptest::strategy::Just(TICK), 0.01f64..1.0],
    ) {
        // Sized for the fastest stream the steps make, so no pose is dropped.
        let mut h = TurningTime::new(window, window + extra, 100.0, OMEGA, baseline).unwrap();
        let mut accepted: Vec<(f64, f64)> = Vec::new();
        let (mut t, mut yaw) = (0.0, 3.0);
        for &(dt, dyaw, bad) in &steps {
            t += dt;
            yaw = strider_core::geom::wrap_angle(yaw + dyaw);
            match bad {
                // Invalid poses are skipped and leave the sums unchanged.
                0 => h.push(f64::NAN, yaw),
                1 => h.push(t, f64::INFINITY),
                2 if !accepted.is_empty() => h.push(accepted.last().unwrap().0, yaw),
                _ => {
                    h.push(t, yaw);
                    accepted.push((t, yaw));
                }
            }
            proptest::prop_assert!(
                (h.in_window() - brute_turning(&accepted, window, baseline, 100.0)).abs() < 1e-9
            );
            proptest::prop_assert!(
                (h.in_support() - brute_turning(&accepted, window + extra, baseline, 100.0)).abs()
                    < 1e-9
            );
        }
    }
}

/// Heading jitter of a logged pose stream is not turning over a 0.5 s baseline (tick to tick
/// it is), and a real turn still is.
#[test]
fn turning_time_over_a_baseline_ignores_heading_jitter() {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(7);
    // Gaussian heading jitter of 5 mrad (Box–Muller).
    let mut jitter = move || {
        let (u, v): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random());
        0.005 * (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    };
    let mut smooth = TurningTime::new(5.0, 5.0, 20.0, OMEGA, 0.5).unwrap();
    let mut raw = TurningTime::new(5.0, 5.0, 20.0, OMEGA, TICK).unwrap();
    for k in 0..200u32 {
        let (t, yaw) = (k as f64 / HZ, 1.0 + jitter());
        smooth.push(t, yaw);
        raw.push(t, yaw);
    }
    assert_eq!(smooth.in_window(), 0.0);
    assert!(raw.in_window() > 1.0, "tick to tick: {}", raw.in_window());
    // Then a 2 s turn at 0.4 rad/s with the same jitter: turning for about its length.
    for k in 200..240u32 {
        let yaw = 1.0 + 0.4 * (k - 199) as f64 / HZ + jitter();
        smooth.push(k as f64 / HZ, yaw);
    }
    assert!(
        (smooth.in_window() - 2.0).abs() <= 0.15,
        "{}",
        smooth.in_window()
    );
}

/// A stream slower than the nominal rate gets a baseline of as many poses as the nominal one:
/// wheel odometry logged at about 5 Hz with jittered stamps and 40 mrad of heading noise,
/// driving straight, does not count as turning (over 0.5 s, three or four poses, it would);
/// a real turn still does.
#[test]
fn turning_baseline_adapts_to_a_slow_pose_stream() {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(11);
    let mut h = TurningTime::new(5.0, 10.0, 20.0, OMEGA, 0.5).unwrap();
    let mut t = 0.0;
    let mut turning_ticks = 0;
    for k in 0..300u32 {
        // Stamps 0.1–0.3 s apart, heading 1 rad ± 40 mrad: at most 0.08 rad/s over 10 poses (at
        // least 1 s), up to 0.16 rad/s over 0.5 s.
        t += rng.random_range(0.1..0.3);
        h.push(t, 1.0 + rng.random_range(-0.04..0.04));
        // After the stream's first poses (measured over fewer) have left the 5 s window.
        if k > 50 && h.in_window() > 0.0 {
            turning_ticks += 1;
        }
    }
    assert_eq!(turning_ticks, 0, "straight driving counted as turning");
    // The same stream over a 0.5 s baseline alone (the nominal rate taken as the stream's
    // fastest, 10 Hz, so that 0.5 s is five poses; at 2 Hz it is one) reads as turning.
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(11);
    let mut short = TurningTime::new(5.0, 10.0, 2.0, OMEGA, 0.5).unwrap();
    let mut t = 0.0;
    for _ in 0..300u32 {
        t += rng.random_range(0.1..0.3);
        short.push(t, 1.0 + rng.random_range(-0.04..0.04));
    }
    assert!(short.in_support() > 0.0, "{}", short.in_support());
    // A turn of 0.3 rad/s for 4 s at 5 Hz: turning.
    let mut yaw = 1.0;
    for _ in 0..20u32 {
        t += 0.2;
        yaw += 0.3 * 0.2;
        h.push(t, yaw);
    }
    assert!(h.in_window() > 2.0, "{}", h.in_window());
}

#[test]
fn turning_time_of_a_turn_on_the_spot_then_straight() {
    // 0.3 rad/s for 5 s (an 86° turn), then straight: the 5 s window forgets the turn 5 s after
    // it ended, the 10 s support 10 s after.
    let mut h = TurningTime::new(5.0, 10.0, 20.0, OMEGA, TICK).unwrap();
    let mut yaw = 0.0;
    for k in 0..=100u32 {
        yaw = 0.3 * k as f64 / HZ;
        h.push(k as f64 / HZ, yaw);
    }
    assert_relative_eq!(h.in_window(), 5.0, max_relative = 1e-9);
    assert_relative_eq!(h.in_support(), 5.0, max_relative = 1e-9);
    for k in 101..=300u32 {
        h.push(k as f64 / HZ, yaw);
        let t = k as f64 / HZ;
        if t > 10.0 + 1e-9 {
            assert_eq!(h.in_window(), 0.0, "t={t}");
        }
        if t > 15.0 + 1e-9 {
            assert_eq!(h.in_support(), 0.0, "t={t}");
        } else if t < 14.9 {
            // The turning ticks still in the support: those over [max(t − 10, 0), 5].
            assert_relative_eq!(h.in_support(), 15.0 - t.max(10.0), epsilon = 0.06);
        }
    }
    // Wrapping across ±π counts the short way round: 0.1 rad in 0.05 s is turning, a slow
    // drift of 0.004 rad per tick (0.08 rad/s) is not.
    let mut h = TurningTime::new(5.0, 5.0, 20.0, OMEGA, TICK).unwrap();
    h.push(0.0, std::f64::consts::PI - 0.05);
    h.push(0.05, -std::f64::consts::PI + 0.05);
    assert_relative_eq!(h.in_window(), 0.05, max_relative = 1e-9);
    h.reset();
    assert_eq!(h.in_window(), 0.0);
    for k in 0..100u32 {
        h.push(k as f64 / HZ, 0.004 * k as f64);
    }
    assert_eq!(h.in_window(), 0.0);
}

#[test]
fn turning_time_rejects_bad_parameters_and_counts_skips() {
    assert!(TurningTime::new(0.0, 1.0, 20.0, OMEGA, TICK).is_err());
    assert!(TurningTime::new(1.0, f64::NAN, 20.0, OMEGA, TICK).is_err());
    assert!(TurningTime::new(1.0, 1.0, -1.0, OMEGA, TICK).is_err());
    assert!(TurningTime::new(1.0, 1.0, 20.0, 0.0, TICK).is_err());
    assert!(TurningTime::new(1.0, 1.0, 20.0, OMEGA, 0.0).is_err());
    let mut h = TurningTime::new(1.0, 2.0, 20.0, OMEGA, TICK).unwrap();
    h.push(1.0, 0.0);
    h.push(1.0, 1.0);
    h.push(0.5, 1.0);
    h.push(f64::NAN, 1.0);
    assert_eq!(h.skips().out_of_order, 2);
    assert_eq!(h.skips().non_finite, 1);
    assert_eq!(h.in_window(), 0.0);
    // A stream faster than the ring was sized for drops the oldest poses from both sums.
    let mut h = TurningTime::new(1.0, 1.0, 1.0, OMEGA, TICK).unwrap();
    for k in 0..100 {
        h.push(k as f64 * 0.001, k as f64 * 0.01);
    }
    assert!(h.skips().overrun > 0);
    assert!(h.in_window() > 0.0 && h.in_window() < 0.099);
}
