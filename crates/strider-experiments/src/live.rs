//! Watching a mission while it runs, besides its progress: recorded to an MCAP file
//! (`--mcap`), served to Foxglove (`--live`, [`LiveServer`]), paced to the wall clock
//! (`--rate`, [`crate::pace`]) and stopped early on Ctrl-C ([`Cancel`]). [`Watch::run`] wires
//! these around the robot for `strider run` (the simulator) and `strider replay` (a log) alike.
//!
//! The recording and the live view are one [`Recorder`] writing to one sink or both
//! ([`strider_log::sink::Fanout`]): they carry the same channels and messages. The live server
//! itself belongs to the command (it serves until the command ends); a mission only publishes
//! on it.

use std::cell::RefCell;
use std::path::Path;
use std::rc::Rc;

use anyhow::Result;
use strider_core::interface::Robot;
use strider_explore::{Mission, MissionProgress, MissionStrategy};
use strider_log::recorder::{Recorder, RecorderOptions, Recording};
use strider_log::sink::{Fanout, MessageSink};
use strider_log::writer::{McapFile, WriteSummary};

pub use strider_log::live::{DEFAULT_ADDR, LiveError, LiveServer};

use crate::cancel::Cancel;
use crate::io::{finish_part, part_path};
use crate::pace::{Paced, Pacer, Rate};

/// How a mission is watched: where it is recorded and shown, its pace, its cancellation flag.
#[derive(Clone, Copy, Debug)]
pub struct Watch<'a> {
    /// The MCAP file to record to (written as `<file>.part`, renamed once finished).
    pub mcap: Option<&'a Path>,
    /// The live view to publish on.
    pub live: Option<&'a LiveServer>,
    /// Pacing to the wall clock; none runs as fast as it can.
    pub rate: Option<Rate>,
    /// Stops the mission at its next control tick once requested.
    pub cancel: &'a Cancel,
}

impl<'a> From<(Option<&'a Path>, &'a Cancel)> for Watch<'a> {
    fn from((mcap, cancel): (Option<&'a Path>, &'a Cancel)) -> Self {
        Self {
            mcap,
            live: None,
            rate: None,
            cancel,
        }
    }
}

impl<'a> From<&'a Cancel> for Watch<'a> {
    fn from(cancel: &'a Cancel) -> Self {
        (None, cancel).into()
    }
}

/// Which loop of the mission runs: exploring (commands the robot) or ingesting a log.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Loop {
    /// [`Mission::run_watched`].
    Explore,
    /// [`Mission::ingest`].
    Ingest,
}

impl Watch<'_> {
    /// Runs `mission` on `robot` (whose gaits are named `gaits`) in `how` until it ends or the
    /// cancellation flag is requested, calling `observe` about once per robot second; records
    /// and publishes the robot's stream and the mission's snapshots as asked, and returns what
    /// was written to the MCAP file.
    ///
    /// The MCAP file is finished (summary and footer) and renamed also when the mission is
    /// interrupted or fails, so that what was recorded stays readable.
    pub fn run<S: MissionStrategy, R: Robot>(
        &self,
        mission: &mut Mission<S>,
        robot: &mut R,
        (gaits, how): (Vec<String>, Loop),
        mut observe: impl FnMut(&Mission<S>, &MissionProgress),
    ) -> Result<Option<WriteSummary>> {
        self.cancel.watch(mission);
        let pacer = self.rate.map(|r| Pacer::new(r, self.cancel.clone()));
        let mut robot = Paced::new(robot, pacer);
        let part = self.mcap.map(part_path);
        let Some(rec) = self.recorder(part.as_deref(), gaits)? else {
            run_loop(mission, &mut robot, how, observe)?;
            return Ok(None);
        };
        let rec = Rc::new(RefCell::new(rec));
        let mut robot = Recording::new(robot, rec.clone());
        let ran = run_loop(mission, &mut robot, how, |m, p| {
            observe(m, p);
            let layers = rec.borrow().grid_due();
            rec.borrow_mut().snapshot(&m.snapshot(layers));
        });
        if ran.is_ok() {
            rec.borrow_mut().snapshot(&mission.snapshot(true));
        }
        drop(robot);
        let rec = Rc::try_unwrap(rec)
            .map_err(|_| anyhow::anyhow!("the recorder is still shared"))?
            .into_inner();
        let finished = rec.finish().map_err(anyhow::Error::from);
        let written = match (part, self.mcap) {
            (Some(part), Some(file)) => {
                finished.and_then(|w| finish_part(&part, file).map(|()| Some(w)))
            }
            _ => finished.map(|_| None),
        };
        ran?;
        written
    }

    /// The recorder into the MCAP file `part` and the live view, whichever are asked for.
    fn recorder(&self, part: Option<&Path>, gaits: Vec<String>) -> Result<Option<Recorder>> {
        let mut sinks: Vec<Box<dyn MessageSink>> = Vec::new();
        if let Some(p) = part {
            sinks.push(Box::new(McapFile::create(p)?));
        }
        if let Some(l) = self.live {
            sinks.push(Box::new(l.sink()));
        }
        let sink: Box<dyn MessageSink> = match sinks.len() {
            0 => return Ok(None),
            1 => sinks.remove(0),
            _ => Box::new(Fanout(sinks)),
        };
        Ok(Some(Recorder::new(sink, RecorderOptions::new(gaits))?))
    }
}

fn run_loop<S: MissionStrategy, R: Robot>(
    mission: &mut Mission<S>,
    robot: &mut R,
    how: Loop,
    observe: impl FnMut(&Mission<S>, &MissionProgress),
) -> Result<()> {
    match how {
        Loop::Explore => mission.run_watched(robot, observe)?,
        Loop::Ingest => mission.ingest(robot, observe)?,
    };
    Ok(())
}
