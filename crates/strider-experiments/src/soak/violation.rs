//! What an invariant violation is: which invariant, how often, and the first time it broke.

use serde::Serialize;

/// The invariants the soak checks, one kind of violation each.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// The robot's true centre left the world, or stood in a cell the simulator's own rule
    /// forbids (a wall or obstacle step from the ground the body stands on, or a cell that
    /// rule never lets the robot reach from the start).
    Pose,
    /// A commanded path, goal or tour site, or gait that cannot be: not finite, a waypoint
    /// outside the world, a tour site outside the exploration bounds, a gait the robot does
    /// not have.
    Plan,
    /// The mission did not end within its simulated time limit plus one control step, or did
    /// not return within its wall-clock bound.
    Termination,
    /// The mission's report does not serialise to JSON and parse back to the same value, holds
    /// a number that is not finite, or has counts that contradict each other.
    Report,
    /// The mission returned an error or panicked.
    Crash,
}

impl Kind {
    /// Every kind, in table order.
    pub const ALL: [Kind; 5] = [
        Kind::Pose,
        Kind::Plan,
        Kind::Termination,
        Kind::Report,
        Kind::Crash,
    ];

    /// Its name in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Pose => "pose",
            Kind::Plan => "plan",
            Kind::Termination => "termination",
            Kind::Report => "report",
            Kind::Crash => "crash",
        }
    }
}

/// Occurrences of a kind of violation described in full; the others are only counted.
pub const MAX_EXAMPLES: usize = 3;

/// One invariant broken in one mission: how many times, and the first occurrences.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Violation {
    /// Which invariant.
    pub kind: Kind,
    /// Times it broke (e.g. pose samples inside a wall).
    pub count: u64,
    /// The first occurrences (at most [`MAX_EXAMPLES`]), each with what was seen.
    pub examples: Vec<String>,
}

/// The violations found in one mission, one entry per kind.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Findings {
    list: Vec<Violation>,
}

impl Findings {
    /// Records one more violation of `kind`; `detail` is only formatted for the first
    /// [`MAX_EXAMPLES`] of its kind (a robot inside a wall breaks the invariant at every step).
    pub fn add(&mut self, kind: Kind, detail: impl FnOnce() -> String) {
        match self.list.iter_mut().find(|v| v.kind == kind) {
            Some(v) => {
                v.count += 1;
                if v.examples.len() < MAX_EXAMPLES {
                    v.examples.push(detail());
                }
            }
            None => self.list.push(Violation {
                kind,
                count: 1,
                examples: vec![detail()],
            }),
        }
    }

    /// Records `r`'s error, if any, as a violation of `kind`.
    pub fn check(&mut self, kind: Kind, r: Result<(), String>) {
        if let Err(e) = r {
            self.add(kind, || e);
        }
    }

    /// Adds `other`'s violations (counts of a kind add up; the examples already here come
    /// first).
    pub fn merge(&mut self, other: Findings) {
        for v in other.list {
            match self.list.iter_mut().find(|w| w.kind == v.kind) {
                Some(w) => {
                    w.count += v.count;
                    let room = MAX_EXAMPLES.saturating_sub(w.examples.len());
                    w.examples.extend(v.examples.into_iter().take(room));
                }
                None => self.list.push(v),
            }
        }
    }

    /// The examples of `kind` so far.
    pub fn examples(&self, kind: Kind) -> &[String] {
        self.list
            .iter()
            .find(|v| v.kind == kind)
            .map_or(&[], |v| &v.examples)
    }

    /// No violation.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The violations, by kind in table order.
    pub fn into_sorted(mut self) -> Vec<Violation> {
        self.list.sort_by_key(|v| v.kind);
        self.list
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_add_up_and_the_first_occurrences_stay() {
        let mut a = Findings::default();
        a.add(Kind::Report, || "first".into());
        a.add(Kind::Report, || "second".into());
        let mut b = Findings::default();
        b.add(Kind::Report, || "third".into());
        b.add(Kind::Report, || "fourth".into());
        b.add(Kind::Pose, || "in a wall".into());
        a.merge(b);
        a.add(Kind::Report, || {
            unreachable!("only the first details are formatted")
        });
        assert_eq!(
            a.into_sorted(),
            vec![
                Violation {
                    kind: Kind::Pose,
                    count: 1,
                    examples: vec!["in a wall".into()]
                },
                Violation {
                    kind: Kind::Report,
                    count: 5,
                    examples: vec!["first".into(), "second".into(), "third".into()]
                },
            ]
        );
    }
}
