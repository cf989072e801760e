//! The README's command reference is the help, word for word, so the two cannot drift apart.
//!
//! For every subcommand `actuator-cam --help` lists, the README has a section headed
//! `### actuator-cam <cmd>` holding the table of its arguments and flags that `actuator-cam <cmd> -h`
//! gives; the flags' clap attributes (src/commands/flags.rs and each command's arguments) are the one
//! definition, and `README_UPDATE=1` regenerates the tables from them. The README's worked examples
//! print what they show.

use std::path::Path;
use std::process::Command;

fn readme() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()))
}

/// The binary's help text for `args` (e.g. `["nest", "--help"]`).
fn help(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_actuator-cam"))
        .args(args)
        .output()
        .expect("run actuator-cam");
    assert!(
        out.status.success(),
        "actuator-cam {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("help is UTF-8")
}

/// The subcommands `actuator-cam --help` lists under "Commands:", without clap's own `help`.
fn subcommands() -> Vec<String> {
    let top = help(&["--help"]);
    let commands: Vec<String> = top
        .lines()
        .skip_while(|l| l.trim() != "Commands:")
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|c| c != "help")
        .collect();
    assert!(
        commands.len() >= 8,
        "found only {commands:?} under Commands: in\n{top}"
    );
    commands
}

/// One row of a subcommand's reference: an argument or a flag as `-h` shows it (`-o, --output <DIR>`)
/// and its help text.
struct Row {
    usage: String,
    help: String,
}

/// The rows `-h` lists under "Arguments:" and "Options:", without --help and --version. Each item is
/// one line, its usage and its help apart by two or more spaces (or the help alone on the lines that
/// follow, when the usage is too long to share one).
fn rows(help: &str) -> Vec<Row> {
    let mut rows: Vec<Row> = Vec::new();
    let mut in_list = false;
    for line in help.lines() {
        if line == "Arguments:" || line == "Options:" {
            in_list = true;
            continue;
        }
        if !in_list || line.trim().is_empty() {
            continue;
        }
        let indent = line.len() - line.trim_start().len();
        if indent > 6 {
            // The help of the row above, on its own line.
            if let Some(last) = rows.last_mut() {
                if !last.help.is_empty() {
                    last.help.push(' ');
                }
                last.help.push_str(line.trim());
            }
            continue;
        }
        let item = line.trim();
        let (usage, help) = match item.find("  ") {
            Some(i) => (item[..i].trim(), item[i..].trim()),
            None => (item, ""),
        };
        rows.push(Row {
            usage: usage.to_string(),
            help: help.to_string(),
        });
    }
    rows.retain(|r| !r.usage.contains("--help") && !r.usage.contains("--version"));
    rows
}

/// The reference section of `cmd` as the README must hold it: a table of every argument and flag
/// with its help, word for word as `actuator-cam <cmd> -h` prints it.
fn reference(cmd: &str) -> String {
    let mut out = String::from("\n| argument or flag | meaning |\n|---|---|\n");
    for r in rows(&help(&[cmd, "-h"])) {
        out.push_str(&format!(
            "| `{}` | {} |\n",
            r.usage,
            r.help.replace('|', "\\|")
        ));
    }
    out.push('\n');
    out
}

/// The README's section for `cmd`: from the heading `### actuator-cam <cmd>` to the next heading of
/// level 1 to 3. None if there is no such heading.
fn section(readme: &str, cmd: &str) -> Option<(usize, usize)> {
    let heading = format!("### actuator-cam {cmd}\n");
    let start = readme.find(&heading)? + heading.len();
    let end = readme[start..]
        .find("\n#")
        .map_or(readme.len(), |i| start + i + 1);
    Some((start, end))
}

#[test]
fn every_subcommand_has_a_readme_section() {
    let readme = readme();
    let missing: Vec<String> = subcommands()
        .into_iter()
        .filter(|cmd| section(&readme, cmd).is_none())
        .map(|cmd| {
            format!("README.md has no section `### actuator-cam {cmd}` for the subcommand `{cmd}`")
        })
        .collect();
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

/// The command reference is generated from the flags' one definition (their clap attributes): each
/// section is the table `-h` gives, word for word. `README_UPDATE=1` writes the tables into the README.
#[test]
fn the_command_reference_is_every_help_word_for_word() {
    let mut readme = readme();
    let mut stale = Vec::new();
    for cmd in subcommands() {
        let (start, end) = section(&readme, &cmd)
            .unwrap_or_else(|| panic!("README.md has no section `### actuator-cam {cmd}`"));
        let want = reference(&cmd);
        if readme[start..end] != want {
            stale.push(cmd.clone());
            readme.replace_range(start..end, &want);
        }
    }
    if std::env::var_os("README_UPDATE").is_some() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md");
        std::fs::write(&path, readme).unwrap();
        return;
    }
    assert!(
        stale.is_empty(),
        "README.md's command reference differs from --help for {stale:?}; regenerate it with README_UPDATE=1 cargo test --release --test tests readme"
    );
}

#[test]
fn the_reference_reads_both_help_layouts() {
    let short = "Usage: x [OPTIONS] <A>\n\nArguments:\n  <A>  The input\n\nOptions:\n  -o, --output <DIR>  Output [default: out]\n      --force          Write\n      --pzt <PZT>      PZT [possible values: a, b-c]\n  -h, --help           Print help\n";
    let r = rows(short);
    let usage: Vec<&str> = r.iter().map(|r| r.usage.as_str()).collect();
    assert_eq!(
        usage,
        ["<A>", "-o, --output <DIR>", "--force", "--pzt <PZT>"]
    );
    assert_eq!(r[3].help, "PZT [possible values: a, b-c]");
    let next_line =
        "Options:\n      --a-very-long-flag-name <A_VERY_LONG_VALUE_NAME>\n          Its help\n";
    let r = rows(next_line);
    assert_eq!(
        r[0].usage,
        "--a-very-long-flag-name <A_VERY_LONG_VALUE_NAME>"
    );
    assert_eq!(r[0].help, "Its help");
    let readme = "## A\n### actuator-cam x\n| `--a` |\n### actuator-cam y\n| `--c` |\n";
    let (s, e) = section(readme, "x").unwrap();
    assert_eq!(&readme[s..e], "| `--a` |\n");
    assert!(section(readme, "z").is_none());
}

/// Every worked example in the README (a fenced block whose first line is `$ actuator-cam …`) prints
/// what the README shows: each shown line, but those eliding with `…` or `...`, is a line of the command's
/// output. The commands run in a scratch folder that sees the repository's examples and fixtures, in
/// README order, since later examples read what earlier ones wrote (`out/cal-lib`).
#[test]
fn the_worked_examples_print_what_the_readme_shows() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scratch = tempfile::tempdir().unwrap();
    for dir in ["examples", "tests"] {
        std::os::unix::fs::symlink(root.join(dir), scratch.path().join(dir)).unwrap();
    }
    let text = readme();
    let lines: Vec<&str> = text.lines().collect();
    let mut checked = 0;
    for (i, line) in lines.iter().enumerate() {
        let Some(command) = line.strip_prefix("$ actuator-cam ") else {
            continue;
        };
        let shown: Vec<&str> = lines[i + 1..]
            .iter()
            .take_while(|l| !l.starts_with("```"))
            .map(|l| l.trim())
            .filter(|l| !l.is_empty() && !l.contains('…') && !l.contains("..."))
            .collect();
        let out = Command::new(env!("CARGO_BIN_EXE_actuator-cam"))
            .args(command.split_whitespace())
            .current_dir(scratch.path())
            .output()
            .expect("run actuator-cam");
        let printed = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        let printed: Vec<&str> = printed.lines().map(str::trim).collect();
        for want in shown {
            assert!(
                printed.contains(&want),
                "README line {}: `actuator-cam {command}` does not print\n  {want}",
                i + 1
            );
        }
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} worked examples found");
}
