//! What each configured topic is used for, and the check of a topic's encoding and schema
//! against it.

use crate::config::ReplayConfig;
use crate::error::LogError;
use crate::ros2::MsgType;
use std::collections::HashMap;

/// What a topic is used for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Role {
    Odometry,
    Tf,
    TfStatic,
    Gait,
    Motion,
    /// The clouds of the configured cloud of this index.
    Cloud(u8),
}

/// The role of every topic the configuration names; a topic configured for two roles is an
/// error.
pub(super) fn topic_roles(cfg: &ReplayConfig) -> Result<HashMap<String, Role>, LogError> {
    let mut roles: HashMap<String, Role> = HashMap::new();
    let mut add = |topic: &str, role: Role| -> Result<(), LogError> {
        if topic.is_empty() {
            return Ok(());
        }
        if let Some(r) = roles.insert(topic.to_string(), role)
            && r != role
        {
            return Err(LogError::Config(format!(
                "topic {topic} is configured twice ({r:?} and {role:?})"
            )));
        }
        Ok(())
    };
    if !cfg.pose.from_tf {
        add(&cfg.pose.topic, Role::Odometry)?;
    }
    add(&cfg.tf.topic, Role::Tf)?;
    add(&cfg.tf.static_topic, Role::TfStatic)?;
    add(&cfg.gait.topic, Role::Gait)?;
    add(&cfg.motion_topic, Role::Motion)?;
    for (i, c) in cfg.clouds.iter().enumerate() {
        add(&c.topic, Role::Cloud(i as u8))?;
    }
    Ok(roles)
}

/// Checks a topic's encoding and schema against its role; returns the message type (a cloud
/// topic carries PointCloud2 or LaserScan, a gait topic String or UInt8).
pub(super) fn check(
    topic: &str,
    encoding: &str,
    schema: &str,
    role: Role,
) -> Result<MsgType, LogError> {
    if encoding != "cdr" {
        return Err(LogError::Encoding {
            topic: topic.into(),
            encoding: encoding.into(),
        });
    }
    let expected: &[MsgType] = match role {
        Role::Odometry => &[MsgType::Odometry],
        Role::Tf | Role::TfStatic => &[MsgType::TfMessage],
        Role::Gait => &[MsgType::String, MsgType::UInt8],
        Role::Motion => &[MsgType::UInt8],
        Role::Cloud(_) => &[MsgType::PointCloud2, MsgType::LaserScan],
    };
    // rosbag2 also writes the ROS 1 style name without "/msg/" for some types.
    let matches = |t: &MsgType| schema == t.name() || schema == t.name().replace("/msg/", "/");
    if let Some(t) = expected.iter().find(|t| matches(t)) {
        Ok(*t)
    } else {
        Err(LogError::Schema {
            topic: topic.into(),
            schema: schema.into(),
            expected: expected
                .iter()
                .map(|t| t.name())
                .collect::<Vec<_>>()
                .join(" or "),
        })
    }
}
