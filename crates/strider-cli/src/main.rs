//! # strider
//!
//! The command-line entry point: it parses the arguments ([`args`]), calls the experiments of
//! `strider_experiments` (or the solver and GP tools) and prints what they return. Errors end in
//! one line on stderr and exit code 1.

mod args;
mod cmd_bench;
mod cmd_gp;
mod cmd_gtsp;
mod cmd_learn;
mod cmd_run;
mod cmd_scenario;
mod cmd_strategies;
mod progress;
mod ranges;

use std::process::ExitCode;

use anyhow::Result;
use clap::Parser;

use args::{
    BenchCommand, Cli, Command, GpCommand, GtspCommand, LearnCommand, MapCommand, ScenarioCommand,
};

fn main() -> ExitCode {
    match dispatch(Cli::parse().command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            ExitCode::FAILURE
        }
    }
}

/// Runs the subcommand.
fn dispatch(command: Command) -> Result<()> {
    match command {
        Command::Run(a) => cmd_run::run(&a),
        Command::Strategies => cmd_strategies::list(),
        Command::Replay(a) => cmd_run::replay(&a),
        Command::Tours(a) => cmd_bench::tours(&a),
        Command::Navigate(a) => cmd_bench::navigate(&a),
        Command::Learn(LearnCommand::Bench(a)) => cmd_learn::bench(&a),
        Command::Learn(LearnCommand::C4Vegetation(a)) => cmd_learn::vegetation(&a),
        Command::Bench(BenchCommand::Table5(a)) => cmd_bench::table5(&a),
        Command::Bench(BenchCommand::Compare(a)) => cmd_bench::compare(&a),
        Command::Bench(BenchCommand::Soak(a)) => cmd_bench::soak(&a),
        Command::Scenario(ScenarioCommand::List) => cmd_scenario::list(),
        Command::Scenario(ScenarioCommand::Render(a)) => cmd_scenario::render(&a),
        Command::Scenario(ScenarioCommand::Export(a)) => cmd_scenario::export(&a),
        Command::Map(MapCommand::Build(a)) => cmd_scenario::map_build(&a),
        Command::Gtsp(GtspCommand::Solve(a)) => cmd_gtsp::solve(&a),
        Command::Gtsp(GtspCommand::Bench(a)) => cmd_gtsp::bench(&a),
        Command::Gp(GpCommand::Predict(a)) => cmd_gp::predict(&a),
    }
}

/// The error and its causes on one line, joined by ": ". A cause whose text the line already
/// holds is skipped (library errors often embed their source in their own message). Line breaks
/// and control characters quoted from the input are flattened and escaped.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !line.contains(&c) {
            line.push_str(": ");
            line.push_str(&c);
        }
    }
    strider_core::text::one_line(&line)
}

#[cfg(test)]
mod tests {
    use super::one_line;
    use anyhow::Context;

    #[test]
    fn causes_already_in_the_message_are_not_repeated() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let e = anyhow::Error::new(io).context("cannot read a.gtsp: no such file");
        assert_eq!(one_line(&e), "cannot read a.gtsp: no such file");
        let r: Result<(), _> = Err(anyhow::anyhow!("line 3: bad value")).context("a.gtsp");
        assert_eq!(one_line(&r.unwrap_err()), "a.gtsp: line 3: bad value");
    }
}
