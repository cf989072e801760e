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
    // Rust ignores SIGPIPE, so a closed stdout (`| head -1`) makes every print panic. The default
    // action ends the process quietly, with the status a shell expects of a pipe's writer.
    // SAFETY: setting a signal's disposition to SIG_DFL before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // An interrupted run removes its staging folder, so it leaves nothing half-written behind; once its
    // files are all in place, it ends as if nothing had come. If the handler cannot be set, the next run
    // into the same place removes the leftover instead. The first interrupt of a nest's search only ends
    // the search, so that the best layout so far is written; a second aborts as above.
    let _ = ctrlc::set_handler(|| {
        if commands::interrupt::end_search() {
            eprintln!("interrupted: ending the search, writing the best layout so far (interrupt again to abort)");
            return;
        }
        if actuator_cam::remove_after_interrupt() {
            return;
        }
        eprintln!("error: interrupted");
        std::process::exit(130);
    });
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match value_error(&e) {
            Some(line) => return fail(&line),
            None if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
                e.exit()
            }
            None if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => e.exit(),
            None => return usage_error(&e),
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

/// A usage error (an unknown flag, a missing value, `--kerf-mm -1` read as a flag) in one line, with
/// where to look, exit status 2 as clap gives.
fn usage_error(e: &clap::Error) -> ExitCode {
    let text = e.to_string();
    // The message is its first paragraph: one line, or a line and the list it introduces (the missing
    // arguments), which stays with it. Usage and tips follow an empty line.
    let first = text
        .lines()
        .map(str::trim)
        .skip_while(|l| l.is_empty())
        .take_while(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    let first = if first.is_empty() {
        "invalid arguments"
    } else {
        first.as_str()
    };
    let first = first.strip_prefix("error: ").unwrap_or(first);
    // clap suggests `-- ARG` for any unknown argument; only a number wants `--flag=-1`.
    let negative = matches!(
        e.get(ContextKind::InvalidArg),
        Some(ContextValue::String(arg))
            if arg.strip_prefix('-').is_some_and(|r| r.starts_with(|c: char| c.is_ascii_digit() || c == '.'))
    );
    let hint = if negative && text.contains("tip: to pass") {
        " (a negative number goes after `=`: --flag=-1)"
    } else {
        ""
    };
    eprintln!("error: {first}{hint}; see actuator-cam --help");
    ExitCode::from(2)
}
