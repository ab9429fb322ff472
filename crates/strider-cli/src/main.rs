//! # strider
//!
//! The command-line entry point: it parses the arguments ([`args`], ranges in [`flags`]), calls
//! the experiments of `strider_experiments` (or the solver and GP tools) and prints what they
//! return. Errors, bad flags included, end in one line on stderr and exit code 1; a command
//! that created its output directory and fails before writing anything there removes it.
//!
//! Ctrl-C (or SIGTERM) during `run`, `replay` or `bench` winds the work down ([`interrupt`]):
//! what was finished is kept, one line on stderr says what and how to continue, and the exit
//! code is 130. Other commands, and a second Ctrl-C, stop at once.

mod args;
mod cmd_bench;
mod cmd_gp;
mod cmd_gtsp;
mod cmd_learn;
mod cmd_run;
mod cmd_scenario;
mod cmd_strategies;
mod flags;
mod interrupt;
mod out_dir;
mod progress;
mod ranges;

use std::process::ExitCode;

use anyhow::Result;
use clap::Parser;
use clap::error::ErrorKind;
use strider_experiments::cancel::Interrupted;

use args::{
    BenchCommand, Cli, Command, GpCommand, GtspCommand, LearnCommand, MapCommand, ScenarioCommand,
};

fn main() -> ExitCode {
    let command = match Cli::try_parse() {
        Ok(cli) => cli.command,
        Err(e) => return usage_error(&e),
    };
    interrupt::install();
    let fresh = out_dir::Fresh::before(&out_dir::of(&command));
    let result = dispatch(command);
    if result.is_err() {
        fresh.remove_if_empty();
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => match e.downcast_ref::<Interrupted>() {
            Some(i) => {
                eprintln!("{i}");
                ExitCode::from(interrupt::EXIT_CODE)
            }
            None => {
                eprintln!("error: {}", one_line(&e));
                ExitCode::FAILURE
            }
        },
    }
}

/// A command line clap refused: help and version are printed as clap prints them; anything
/// else is the first line of clap's message (`invalid value '-1' for '--time-limit
/// <SECONDS>': must be …`), exit code 1.
fn usage_error(e: &clap::Error) -> ExitCode {
    match e.kind() {
        ErrorKind::DisplayHelp
        | ErrorKind::DisplayVersion
        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            if e.use_stderr() {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            }
        }
        _ => {
            let text = e.render().to_string();
            let line = text.lines().next().unwrap_or("bad command line");
            eprintln!("error: {}", line.trim_start_matches("error: "));
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
        Command::Bench(BenchCommand::Merge(a)) => cmd_bench::merge(&a),
        Command::Bench(BenchCommand::Soak(a)) => cmd_bench::soak(&a),
        Command::Bench(BenchCommand::Scale(a)) => cmd_bench::scale(&a),
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
    strider_experiments::io::error_line(e)
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
