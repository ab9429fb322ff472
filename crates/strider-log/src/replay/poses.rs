//! The robot's poses of a replay: in the world frame, with the gait of each.

use super::index::LogIndex;
use super::tf::Iso;
use crate::config::ReplayConfig;
use crate::error::LogError;
use crate::ros2::nanos_to_seconds;
use strider_core::{GaitId, GaitSpec, Point3, PoseStamped};

/// A pose with its stamp relative to the start of the log (ns) and its number among the
/// file's messages.
pub(super) type TimedPose = (i64, u64, PoseStamped);

/// A pose before its gait is known.
struct RawPose {
    ns: i64,
    seq: u64,
    pose: PoseStamped,
}

/// The gait before the first gait message (or throughout without one): the configured one,
/// else the fastest of `gaits`.
pub(super) fn default_gait(cfg: &ReplayConfig, gaits: &[GaitSpec]) -> Result<GaitId, LogError> {
    let Some(name) = &cfg.gait.default else {
        return Ok(strider_core::snapshot::fastest_gait(gaits));
    };
    let k = gaits.iter().position(|g| g.name == *name).ok_or_else(|| {
        let names: Vec<&str> = gaits.iter().map(|g| g.name.as_str()).collect();
        LogError::Config(format!(
            "[gait] default {name:?} is not a gait of the robot ({})",
            names.join(", ")
        ))
    })?;
    Ok(GaitId(k as u8))
}

/// The poses of the log in the world frame, relative to `start` (ns), in (stamp, file) order:
/// (stamp, seq, pose). Poses whose orientation is zero or not finite are skipped; the second
/// value counts them.
pub(super) fn world_poses(
    ix: &LogIndex,
    cfg: &ReplayConfig,
    start: i64,
    default_gait: GaitId,
) -> Result<(Vec<TimedPose>, usize), LogError> {
    let world = &cfg.world_frame;
    let mut raw: Vec<RawPose> = Vec::new();
    let mut bad = 0usize;
    let mut push = |ns: i64, seq: u64, iso: Iso| {
        if !iso.q.w.is_finite() {
            bad += 1;
            return;
        }
        let (roll, pitch, yaw) = iso.q.to_rpy();
        raw.push(RawPose {
            ns: ns.saturating_sub(start),
            seq,
            pose: PoseStamped {
                stamp: nanos_to_seconds(ns.saturating_sub(start)),
                position: Point3::new(iso.t[0], iso.t[1], iso.t[2]),
                roll,
                pitch,
                yaw,
                gait: default_gait,
            },
        });
    };
    if cfg.pose.from_tf {
        for &(ns, s) in &ix.base_tf {
            let iso =
                ix.tf
                    .lookup(&cfg.pose.base_frame, ns)
                    .map_err(|reason| LogError::Content {
                        topic: cfg.tf.topic.clone(),
                        index: 0,
                        reason,
                    })?;
            push(ns, s, iso);
        }
    } else {
        for (ns, s, index, frame, iso) in &ix.odoms {
            let iso = if *frame == *world || !iso.q.w.is_finite() {
                *iso
            } else {
                ix.tf
                    .lookup(frame, *ns)
                    .map_err(|reason| LogError::Content {
                        topic: cfg.pose.topic.clone(),
                        index: *index,
                        reason,
                    })?
                    .compose(iso)
            };
            push(*ns, *s, iso);
        }
    }
    raw.sort_by_key(|p| (p.ns, p.seq));
    let poses = raw.into_iter().map(|p| (p.ns, p.seq, p.pose)).collect();
    Ok((poses, bad))
}

/// Sets the gait of each pose (in (stamp, seq) order, stamps relative to `start`): the latest
/// of `gaits` (log time, seq, gait) before it in (stamp, file) order, `default` before the
/// first.
pub(super) fn assign_gaits(
    poses: &mut [TimedPose],
    gaits: &mut [(i64, u64, GaitId)],
    start: i64,
    default: GaitId,
) {
    gaits.sort_by_key(|g| (g.0, g.1));
    let mut k = 0;
    let mut gait = default;
    for (ns, seq, pose) in poses {
        while k < gaits.len() && (gaits[k].0.saturating_sub(start), gaits[k].1) < (*ns, *seq) {
            gait = gaits[k].2;
            k += 1;
        }
        pose.gait = gait;
    }
}
