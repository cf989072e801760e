//! The shape of the code, checked: no import circles between modules, and no command-line crate in the
//! library's dependency tree.
//!
//! A circle is two sibling modules (at any depth: `calibrate::discover` and `calibrate::select`, or
//! `input` and `calibrate`) each of which names the other through `crate::…` or `super::…` paths. The
//! edges come from the source text, so the test needs no compiler support and lists every circle it finds.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The crates whose modules must form no circle: (source root, crate root file).
const CRATES: [&str; 5] = [
    "crates/cam/src",
    "crates/model/src",
    "crates/geometry/src",
    "crates/nest/src",
    "src",
];

/// A module's path from its crate root, e.g. `["calibrate", "select", "joint"]`.
type ModPath = Vec<String>;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `.rs` file under `dir`, with the module path it defines.
fn module_files(dir: &Path) -> Vec<(ModPath, PathBuf)> {
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}

fn walk(base: &Path, dir: &Path, out: &mut Vec<(ModPath, PathBuf)>) {
    let mut entries: Vec<_> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            walk(base, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let rel = path.strip_prefix(base).unwrap();
            let mut parts: Vec<String> = rel
                .iter()
                .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
                .collect();
            let last = parts.last().cloned().unwrap_or_default();
            if last == "mod" || last == "lib" || last == "main" {
                parts.pop();
            }
            out.push((parts, path));
        }
    }
}

/// Strip `//` comments (doc comments included): a path named in prose is not an import.
fn code_lines(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The module paths a file names: `crate::a::b` and `super::…::a` (resolved from `from`), each as the
/// list of identifiers after the prefix. Brace groups `crate::a::{b, c}` yield `a` (enough for siblings).
fn named_paths(code: &str, from: &ModPath) -> Vec<ModPath> {
    let bytes = code.as_bytes();
    let ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if i > 0 && (ident(bytes[i - 1]) || bytes[i - 1] == b':') {
            i += 1;
            continue;
        }
        let rest = &bytes[i..];
        let (mut base, mut j) = if rest.starts_with(b"crate::") {
            (Vec::new(), i + "crate::".len())
        } else if rest.starts_with(b"super::") {
            // In `a/b.rs` (module a::b) super is `a`; in `a/b/mod.rs` (also a::b) super is `a` too.
            let mut base = from.clone();
            base.pop();
            let mut j = i + "super::".len();
            while bytes[j..].starts_with(b"super::") {
                base.pop();
                j += "super::".len();
            }
            (base, j)
        } else {
            i += 1;
            continue;
        };
        loop {
            let start = j;
            while j < bytes.len() && ident(bytes[j]) {
                j += 1;
            }
            if start == j {
                break;
            }
            base.push(code[start..j].to_string());
            if bytes[j..].starts_with(b"::") {
                j += 2;
            } else {
                break;
            }
        }
        out.push(base);
        i = j.max(i + 1);
    }
    out
}

/// A sibling-module edge: (parent, from child, to child).
type Edge = (ModPath, String, String);

/// Sibling-module edges at every level, each with one witness: the file and the path it names.
fn sibling_edges(files: &[(ModPath, PathBuf)]) -> BTreeMap<Edge, String> {
    let modules: BTreeSet<ModPath> = files.iter().map(|(m, _)| m.clone()).collect();
    let mut edges = BTreeMap::new();
    for (from, path) in files {
        let text = fs::read_to_string(path).unwrap();
        for named in named_paths(&code_lines(&text), from) {
            // The longest module path that the named path starts with.
            let target = (0..=named.len())
                .rev()
                .map(|n| named[..n].to_vec())
                .find(|p| modules.contains(p))
                .unwrap_or_default();
            // The deepest common ancestor, and the two children of it on each side.
            let common = from.iter().zip(&target).take_while(|(a, b)| a == b).count();
            if common < from.len() && common < target.len() {
                let edge = (
                    from[..common].to_vec(),
                    from[common].clone(),
                    target[common].clone(),
                );
                edges
                    .entry(edge)
                    .or_insert_with(|| format!("{} names {}", path.display(), named.join("::")));
            }
        }
    }
    edges
}

/// The circles among sibling modules: every pair reachable both ways, as `parent: a <-> b`.
fn circles(edges: &BTreeMap<Edge, String>) -> Vec<String> {
    let mut by_parent: BTreeMap<&ModPath, BTreeMap<&str, BTreeSet<&str>>> = BTreeMap::new();
    for (parent, a, b) in edges.keys() {
        by_parent
            .entry(parent)
            .or_default()
            .entry(a)
            .or_default()
            .insert(b);
    }
    let mut found = Vec::new();
    for (parent, graph) in &by_parent {
        let reach = |start: &str| {
            let mut seen = BTreeSet::new();
            let mut stack = vec![start];
            while let Some(n) = stack.pop() {
                for &m in graph.get(n).into_iter().flatten() {
                    if seen.insert(m) {
                        stack.push(m);
                    }
                }
            }
            seen
        };
        let nodes: BTreeSet<&str> = graph.keys().copied().collect();
        for &a in &nodes {
            for b in reach(a) {
                if a < b && reach(b).contains(a) {
                    found.push(format!("{}: {a} <-> {b}", parent.join("::")));
                }
            }
        }
    }
    found
}

#[test]
fn no_module_imports_in_a_circle() {
    let mut all = Vec::new();
    for krate in CRATES {
        let files = module_files(&root().join(krate));
        assert!(!files.is_empty(), "{krate} has no source files");
        let edges = sibling_edges(&files);
        for circle in circles(&edges) {
            all.push(format!("{krate}: {circle}"));
        }
        if !all.is_empty() {
            // The edges behind the circles, so the message says where to cut.
            for ((parent, a, b), witness) in &edges {
                if all.iter().any(|c| {
                    c.contains(&format!("{}: {a} <-> {b}", parent.join("::")))
                        || c.contains(&format!("{}: {b} <-> {a}", parent.join("::")))
                }) {
                    all.push(format!("  {a} -> {b}: {witness}"));
                }
            }
        }
    }
    assert!(all.is_empty(), "import circles:\n{}", all.join("\n"));
}

#[test]
fn the_circle_finder_finds_a_circle() {
    // Two siblings that name each other, one through `super::`, and a third that only names one of them.
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| fs::write(dir.path().join(name), text).unwrap();
    write("lib.rs", "mod a;\nmod b;\nmod c;\n");
    write("a.rs", "use crate::b::Thing;\n");
    write(
        "b.rs",
        "use super::a::Other; // crate::c in a comment is no edge\n",
    );
    write("c.rs", "use crate::a::Other;\n");
    let found = circles(&sibling_edges(&module_files(dir.path())));
    assert_eq!(found, vec![": a <-> b".to_string()]);
}

/// The packages the library pulls in, from Cargo.lock: every dependency (normal, build or dev) of
/// `actuator-cam`, transitively. Cargo.lock does not say which kind an edge is, so this is a superset of
/// the library's normal dependency tree, and a name absent here is absent there.
fn library_closure() -> BTreeSet<String> {
    let lock: toml::Table = fs::read_to_string(root().join("Cargo.lock"))
        .unwrap()
        .parse()
        .unwrap();
    let packages = lock["package"].as_array().unwrap();
    let deps: BTreeMap<String, Vec<String>> = packages
        .iter()
        .map(|p| {
            let name = p["name"].as_str().unwrap().to_string();
            let deps = p
                .get("dependencies")
                .and_then(|d| d.as_array())
                .map(|d| {
                    d.iter()
                        .map(|s| s.as_str().unwrap().split(' ').next().unwrap().to_string())
                        .collect()
                })
                .unwrap_or_default();
            (name, deps)
        })
        .collect();
    let mut seen = BTreeSet::new();
    let mut stack = vec!["actuator-cam".to_string()];
    while let Some(n) = stack.pop() {
        for d in deps.get(&n).into_iter().flatten() {
            if seen.insert(d.clone()) {
                stack.push(d.clone());
            }
        }
    }
    seen
}

#[test]
fn the_library_pulls_in_no_command_line_crate() {
    let closure = library_closure();
    assert!(
        closure.contains("cam-nest"),
        "the closure walk found too little"
    );
    for banned in ["clap", "clap_builder", "indicatif", "ctrlc"] {
        assert!(
            !closure.contains(banned),
            "the library crate depends on {banned}"
        );
    }
    // anyhow comes in through jagua-rs; the library itself must not name it.
    let manifest = fs::read_to_string(root().join("crates/cam/Cargo.toml")).unwrap();
    assert!(!manifest.contains("anyhow"), "crates/cam names anyhow");
}

/// Most lines of code in one source file, before its `#[cfg(test)]` module: a file past it holds more
/// than one concept.
const MAX_FILE_LINES: usize = 600;
/// Most lines in one function, its signature and closing brace included.
const MAX_FUNCTION_LINES: usize = 120;

/// The lines of `text` before its test module (a `#[cfg(test)]` line followed by a `mod` line).
fn lines_before_tests(text: &str) -> usize {
    let lines: Vec<&str> = text.lines().collect();
    lines
        .windows(2)
        .position(|w| {
            w[0].trim() == "#[cfg(test)]" && {
                let next = w[1].trim_start();
                next.starts_with("mod ")
                    || next.starts_with("pub mod ")
                    || next.starts_with("pub(crate) mod ")
            }
        })
        .unwrap_or(lines.len())
}

/// Each function of `text` longer than `most` lines: `(name, first line, lines)`. A function runs
/// from its `fn` line to the line where its braces balance, counted on code with strings, character
/// literals and comments removed.
fn long_functions(text: &str, most: usize) -> Vec<(String, usize, usize)> {
    let code: Vec<String> = text.lines().map(code_lines).collect();
    let mut long = Vec::new();
    for (i, line) in code.iter().enumerate() {
        let trimmed = line.trim_start();
        let after_qualifiers = trimmed
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub(super) ")
            .trim_start_matches("pub ")
            .trim_start_matches("const ")
            .trim_start_matches("unsafe ");
        let Some(rest) = after_qualifiers.strip_prefix("fn ") else {
            continue;
        };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let (mut depth, mut opened) = (0i64, false);
        for (j, l) in code.iter().enumerate().skip(i) {
            let stripped = without_literals(l);
            if !opened && stripped.trim_end().ends_with(';') {
                break;
            }
            for c in stripped.chars() {
                match c {
                    '{' => {
                        depth += 1;
                        opened = true;
                    }
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            if opened && depth <= 0 {
                if j - i + 1 > most {
                    long.push((name.clone(), i + 1, j - i + 1));
                }
                break;
            }
        }
    }
    long
}

/// `line` without its string and character literals, so braces inside them do not count.
fn without_literals(line: &str) -> String {
    let mut out = String::new();
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' => {
                while let Some(d) = chars.next() {
                    if d == '\\' {
                        chars.next();
                    } else if d == '"' {
                        break;
                    }
                }
            }
            '\'' if matches!(chars.clone().nth(1), Some('\'')) => {
                chars.next();
                chars.next();
            }
            '\'' if chars.peek() == Some(&'\\') => {
                for d in chars.by_ref() {
                    if d == '\'' {
                        break;
                    }
                }
            }
            c => out.push(c),
        }
    }
    out
}

/// Every source file of the workspace's crates.
/// Every Rust file of the workspace: the crates' sources, and the tests and benchmarks that drive them.
fn source_files() -> Vec<PathBuf> {
    let harnesses = [
        "tests",
        "benches",
        "crates/nest/tests",
        "crates/nest/benches",
    ];
    CRATES
        .iter()
        .chain(&harnesses)
        .filter(|dir| root().join(dir).is_dir())
        .flat_map(|c| module_files(&root().join(c)))
        .map(|(_, p)| p)
        .collect()
}

#[test]
fn no_file_or_function_is_over_the_house_size() {
    let mut over = Vec::new();
    for path in source_files() {
        let text = fs::read_to_string(&path).unwrap();
        let rel = path.strip_prefix(root()).unwrap().display().to_string();
        let n = lines_before_tests(&text);
        if n > MAX_FILE_LINES {
            over.push(format!(
                "{rel}: {n} lines of code (at most {MAX_FILE_LINES})"
            ));
        }
        for (name, line, lines) in long_functions(&text, MAX_FUNCTION_LINES) {
            over.push(format!(
                "{rel}:{line}: fn {name} is {lines} lines (at most {MAX_FUNCTION_LINES})"
            ));
        }
    }
    assert!(over.is_empty(), "{}", over.join("\n"));
}

#[test]
fn the_size_check_counts_what_it_should() {
    let text =
        "fn short() {\n    let s = \"{\";\n}\n\n#[cfg(test)]\nmod tests {\n    fn long() {}\n}\n";
    assert_eq!(lines_before_tests(text), 4);
    let body: String = (0..5).map(|_| "    x();\n").collect();
    let text = format!("pub fn five() {{\n{body}}}\nfn decl();\nfn two() {{\n}}\n");
    assert_eq!(long_functions(&text, 6), vec![("five".to_string(), 1, 7)]);
    assert!(long_functions(&text, 7).is_empty());
    assert_eq!(
        without_literals("let c = '{'; let s = \"}\\\"\";"),
        "let c = ; let s = ;"
    );
}

#[test]
fn the_library_api_is_curated_not_every_module() {
    let lib = fs::read_to_string(root().join("crates/cam/src/lib.rs")).unwrap();
    let public_modules: Vec<&str> = lib
        .lines()
        .filter(|l| l.trim_start().starts_with("pub mod "))
        .collect();
    assert!(
        public_modules.is_empty(),
        "crates/cam/src/lib.rs makes modules public: {public_modules:?}; re-export the items instead"
    );
}
