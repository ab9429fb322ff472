use strider_core::interface::{Robot, SensorSink};
use strider_core::{GaitId, Point2, PointCloud, PoseStamped};
use strider_learn::signals::InverseVelocityCost;
use strider_scenario::Scenario;
use strider_sim::Simulator;
struct Sink { poses: Vec<PoseStamped>, sig: InverseVelocityCost, costs: Vec<f64> }
impl SensorSink for Sink {
    fn on_pose(&mut self, p: &PoseStamped) { self.poses.push(*p); if let Some(s) = self.sig.push(p, p.gait) { self.costs.push(s.cost); } }
    fn on_cloud(&mut self, _c: &PointCloud) {}
    fn wants_cloud(&self, _s: u8) -> bool { false }
}
fn main() {
    let sc = Scenario::from_name_or_file("courtyard-small", 1).unwrap();
    let params = strider_cli::trial::mission_params(&sc, strider_explore::Strategy::Gtsp, 1).unwrap();
    for g in [0u8, 1] {
        let mut sim = Simulator::new(&sc, 1).unwrap();
        sim.set_gait(GaitId(g));
        let p = sim.pose();
        // A staircase (8-connected) approximation of a 25° line, cell 0.05.
        let mut pts = Vec::new();
        let (mut i, mut j) = (0i32, 0i32);
        for k in 1..=30 { i += 1; if (k * 2) % 5 == 0 { j += 1; } pts.push(Point2::new(p.x + 0.05 * i as f64, p.y + 0.05 * j as f64)); }
        let _ = p.yaw;
        sim.follow(&pts);
        let mut sink = Sink { poses: vec![], sig: InverseVelocityCost::new(params.inverse_velocity()).unwrap(), costs: vec![] };
        let t0 = sim.now();
        for _ in 0..20000 { let s = sim.advance(0.05, &mut sink).unwrap(); if s.idle { break; } }
        let q = sim.pose();
        let dist = ((q.x - p.x).powi(2) + (q.y - p.y).powi(2)).sqrt();
        let n = sink.costs.len();
        println!("gait {g}: {dist:.3} m in {:.1} s = {:.4} m/s; costs n={n} first {:?} median {:?}", sim.now() - t0, dist / (sim.now() - t0), sink.costs.first(), sink.costs.get(n / 2));
    }
}
