//! The `actuator-cam` command line: parses arguments and hands them to a subcommand in [`commands`], which
//! calls the `actuator_cam` library. clap, anyhow and indicatif live here only; the library knows nothing of
//! the command line.

mod commands;

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::Parser;
use commands::Cli;
use std::error::Error;
use std::process::ExitCode;

fn main() -> ExitCode {
    // An interrupted run removes its staging folder, so it leaves nothing half-written behind; once its
    // files are all in place, it ends as if nothing had come. If the handler cannot be set, the next run
    // into the same place removes the leftover instead.
    let _ = ctrlc::set_handler(|| {
        if actuator_cam::output::remove_after_interrupt() {
            return;
        }
        eprintln!("error: interrupted");
        std::process::exit(130);
    });
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match value_error(&e) {
            Some(line) => return fail(&line),
            None => e.exit(),
        },
    };
    match cli.command.run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(&format!("{e:#}")),
    }
}

/// Every error is one line on stderr and exit status 1.
fn fail(message: &str) -> ExitCode {
    eprintln!("error: {}", message.replace('\n', " "));
    ExitCode::FAILURE
}

/// A value our own parsers refused (`--model`, `--format`, `--stroke-mm`, …) reads like every other error
/// of the tool, `--flag "value": reason`, rather than as a usage error.
fn value_error(e: &clap::Error) -> Option<String> {
    if e.kind() != ErrorKind::ValueValidation {
        return None;
    }
    let flag = match e.get(ContextKind::InvalidArg)? {
        ContextValue::String(s) => s.split(' ').next().unwrap_or(s).to_string(),
        _ => return None,
    };
    let value = match e.get(ContextKind::InvalidValue)? {
        ContextValue::String(s) => s.clone(),
        _ => return None,
    };
    let reason = e.source()?.to_string();
    Some(format!("{flag} {value:?}: {reason}"))
}
