//! The README's command reference agrees with clap's help, so the two cannot drift apart.
//!
//! For every subcommand `actuator-cam --help` lists, the README has a section headed
//! `### actuator-cam <cmd>`, and every long flag `actuator-cam <cmd> --help` lists appears in that
//! section as `--flag`. Values a flag's help enumerates (clap's possible values, or the models
//! `--model` names) appear where the README documents that flag. The help is the source: a flag
//! added to a command without a line in the README fails here, naming the flag and the command.

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

/// One option of a subcommand's help: its long flag and the text that describes it.
struct Opt {
    flag: String,
    description: String,
}

/// Whether `line` starts an option: `  -o, --output <DIR>  …` or `      --force  …`. Option lines are
/// indented by at most six spaces; description lines of the long help (indented further) and the
/// `- value: …` lines of a possible-values list are not.
fn long_flag_of(line: &str) -> Option<String> {
    let indent = line.len() - line.trim_start().len();
    let rest = line.trim_start();
    if indent > 6 {
        return None;
    }
    let rest = match rest.as_bytes() {
        [b'-', c, b',', b' ', ..] if c.is_ascii_alphanumeric() => &rest[4..],
        _ => rest,
    };
    let name: String = rest
        .strip_prefix("--")?
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
        .collect();
    (!name.is_empty()).then(|| format!("--{name}"))
}

/// The options `help` lists (both clap's short and long help layouts), without --help and --version.
fn options(help: &str) -> Vec<Opt> {
    let mut opts: Vec<Opt> = Vec::new();
    for line in help.lines() {
        if let Some(flag) = long_flag_of(line) {
            let description = line.trim_start().to_string();
            opts.push(Opt { flag, description });
        } else if let Some(last) = opts.last_mut() {
            if line.trim().is_empty() || !line.starts_with(' ') {
                continue;
            }
            last.description.push('\n');
            last.description.push_str(line.trim());
        }
    }
    opts.retain(|o| o.flag != "--help" && o.flag != "--version");
    opts
}

/// The values an option's help enumerates: clap's `[possible values: a, b]` (short help) or its
/// `Possible values:` list of `- a: …` lines (long help); for `--model`, whose value may also be a
/// file, the names in its `Model: a, b, c, or a calibrated-model.toml …` description.
fn listed_values(opt: &Opt) -> Vec<String> {
    let mut values = Vec::new();
    if let Some(i) = opt.description.find("[possible values: ") {
        let rest = &opt.description[i + "[possible values: ".len()..];
        let list = &rest[..rest.find(']').unwrap_or(rest.len())];
        values.extend(list.split(',').map(|v| v.trim().to_string()));
    }
    let mut in_list = false;
    for line in opt.description.lines() {
        if line == "Possible values:" {
            in_list = true;
        } else if in_list {
            match line.strip_prefix("- ") {
                Some(item) => {
                    values.push(item.split(':').next().unwrap_or(item).trim().to_string())
                }
                None => in_list = false,
            }
        }
    }
    if opt.flag == "--model" {
        if let Some(i) = opt.description.find("Model: ") {
            let rest = &opt.description[i + "Model: ".len()..];
            let prose = &rest[..rest.find('[').unwrap_or(rest.len())];
            for item in prose.split(',') {
                let item = item.trim().trim_start_matches("or ").trim();
                if !item.is_empty()
                    && item
                        .chars()
                        .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
                {
                    values.push(item.to_string());
                }
            }
            if prose.contains("calibrated-model.toml") {
                values.push("calibrated-model.toml".to_string());
            }
        }
    }
    values.retain(|v| !v.is_empty());
    values
}

/// The README's section for `cmd`: from the heading `### actuator-cam <cmd>` to the next heading of
/// level 1 to 3 (headings inside fenced code blocks do not count). None if there is no such heading.
fn section(readme: &str, cmd: &str) -> Option<String> {
    let heading = format!("### actuator-cam {cmd}");
    let mut lines = readme.lines();
    lines.find(|l| l.trim_end() == heading)?;
    let mut body = String::new();
    let mut fenced = false;
    for line in lines {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        let level = line.chars().take_while(|&c| c == '#').count();
        if !fenced && (1..=3).contains(&level) && line[level..].starts_with(' ') {
            break;
        }
        body.push_str(line);
        body.push('\n');
    }
    Some(body)
}

/// Whether `text` holds `word` as a whole token: `--pzt` is not found in `--pzt-thickness-mm`.
fn has_token(text: &str, word: &str) -> bool {
    let part_of_word = |c: char| c.is_ascii_alphanumeric() || c == '-' || c == '_';
    text.match_indices(word).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + word.len()..].chars().next();
        !before.is_some_and(part_of_word) && !after.is_some_and(part_of_word)
    })
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

#[test]
fn every_flag_of_every_subcommand_is_in_its_readme_section() {
    let readme = readme();
    let mut missing = Vec::new();
    for cmd in subcommands() {
        let Some(body) = section(&readme, &cmd) else {
            missing.push(format!("README.md has no section `### actuator-cam {cmd}`"));
            continue;
        };
        let opts = options(&help(&[&cmd, "--help"]));
        for opt in &opts {
            if !has_token(&body, &opt.flag) {
                missing.push(format!(
                    "flag `{}` of subcommand `{cmd}` (in `actuator-cam {cmd} --help`) is missing from README.md's section `### actuator-cam {cmd}`",
                    opt.flag
                ));
            }
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

#[test]
fn values_the_help_lists_are_where_the_readme_documents_the_flag() {
    let readme = readme();
    let mut missing = Vec::new();
    let mut model_flags = 0;
    for cmd in subcommands() {
        let Some(body) = section(&readme, &cmd) else {
            continue;
        };
        for opt in options(&help(&[&cmd, "--help"])) {
            let values = listed_values(&opt);
            if opt.flag == "--model" {
                model_flags += 1;
                assert!(
                    values.iter().any(|v| v == "euler-bernoulli"),
                    "`actuator-cam {cmd} --help` no longer names euler-bernoulli for --model \
                     (found {values:?}); update this test and the README together"
                );
            }
            // The README lines that document the flag (a table row or a paragraph line).
            let documented: String = body
                .lines()
                .filter(|l| has_token(l, &opt.flag))
                .collect::<Vec<_>>()
                .join("\n");
            for value in &values {
                if !documented.contains(value.as_str()) {
                    missing.push(format!(
                        "value `{value}` of `{}` (subcommand `{cmd}`) is missing from the README line that documents `{}` in `### actuator-cam {cmd}`",
                        opt.flag, opt.flag
                    ));
                }
            }
        }
    }
    assert!(
        model_flags >= 4,
        "--model found on only {model_flags} subcommands"
    );
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

#[test]
fn the_parsers_read_both_help_layouts() {
    let short = "Options:\n  -o, --output <DIR>  Output [default: out]\n      --force          Write\n      --pzt <PZT>      PZT [possible values: a, b-c]\n  -h, --help           Print help\n";
    let flags: Vec<String> = options(short).into_iter().map(|o| o.flag).collect();
    assert_eq!(flags, ["--output", "--force", "--pzt"]);
    assert_eq!(listed_values(&options(short)[2]), ["a", "b-c"]);

    let long = "Options:\n      --objective <OBJECTIVE>\n          What to optimise\n\n          Possible values:\n          - min-mass:           Lightest\n          - max-energy-density: Highest\n          \n          [default: min-mass]\n\n      --model <MODEL>\n          Model: original, euler-bernoulli, or a calibrated-model.toml written by `calibrate`\n\n  -h, --help\n          Print help\n";
    let opts = options(long);
    let flags: Vec<&str> = opts.iter().map(|o| o.flag.as_str()).collect();
    assert_eq!(flags, ["--objective", "--model"]);
    assert_eq!(listed_values(&opts[0]), ["min-mass", "max-energy-density"]);
    assert_eq!(
        listed_values(&opts[1]),
        ["original", "euler-bernoulli", "calibrated-model.toml"]
    );

    assert!(has_token("| `--pzt NAME` |", "--pzt"));
    assert!(!has_token("| `--pzt-thickness-mm T` |", "--pzt"));
    let readme = "## A\n### actuator-cam x\n| `--a` |\n```toml\n# not a heading\n```\n| `--b` |\n### actuator-cam y\n| `--c` |\n";
    let x = section(readme, "x").unwrap();
    assert!(has_token(&x, "--a") && has_token(&x, "--b") && !has_token(&x, "--c"));
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
