//! One GTSPLIB/TSPLIB instance read and solved with the answer checked: shared by
//! `strider gtsp solve`/`bench` and the Python package, so that both give the same tour.

use std::path::Path;

use anyhow::{Context, Result, bail};
use strider_plan::tsplib::read_instance_file;
use strider_plan::{Instance, Mode, Solution, SolverParams, TsplibError};

/// A solver mode by name: `fast`, `default` or `slow`.
pub fn parse_mode(s: &str) -> Result<Mode> {
    Ok(match s {
        "fast" => Mode::Fast,
        "default" => Mode::Default,
        "slow" => Mode::Slow,
        _ => bail!("unknown mode {s:?}: use fast, default or slow"),
    })
}

/// Reads an instance; parse errors (which carry the line) are prefixed with the file.
pub fn read_instance(path: &Path) -> Result<Instance> {
    read_instance_file(path).map_err(|e| match e {
        TsplibError::Io { .. } | TsplibError::FileTooLarge { .. } => anyhow::Error::new(e),
        e => anyhow::Error::new(e).context(path.display().to_string()),
    })
}

/// Solves `inst` and checks the answer: one vertex per set, and the reported cost equal to a
/// re-evaluation of the tour. `what` names the instance in errors (its file).
pub fn solve_checked(inst: &Instance, p: &SolverParams, what: &str) -> Result<Solution> {
    let sol = strider_plan::solve(inst, p).with_context(|| format!("{what}: cannot solve"))?;
    inst.check_tour(&sol.tour)
        .with_context(|| format!("{what}: solver returned an infeasible tour"))?;
    let re = inst.tour_cost(&sol.tour);
    if re != sol.cost {
        bail!(
            "{what}: solver reported cost {} but the tour re-evaluates to {re}",
            sol.cost
        );
    }
    Ok(sol)
}
