//! The bad-input corpus (`tests/bad_inputs/`, issue 22 point 1): every case
//! runs through the `flank` binary in a fresh temporary folder and must
//! - exit with flank's error code (1; 2 for a case marked as a command-line
//!   usage error, which clap reports), never 0 and never a panic's 101;
//! - print, on stderr, the expected message fragment and the location (the
//!   `file:line` or the key/option it must name);
//! - write no file (the temporary folder holds exactly the inputs afterwards,
//!   unchanged);
//! - print no NaN or inf anywhere (unless the input itself says `nan`/`inf`
//!   and the message quotes it).
//!
//! Layout and how to add a case: `tests/bad_inputs/README.md`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Folder {
    /// Default command line; `{input}` = the case file, `{out}` = an output
    /// folder inside the temporary folder.
    args: Vec<String>,
    /// Copy the case file under this name (a fixed name another input refers to).
    input_name: Option<String>,
    cases: BTreeMap<String, Case>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    /// Fragment the message must contain.
    message: String,
    /// `file:line`, key or option the message must name.
    location: String,
    /// Command line of this case instead of the folder's.
    args: Option<Vec<String>>,
    /// Expected exit code (default 1, flank's error code).
    exit: Option<i32>,
}

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs")
}

/// All files below `dir` with their contents (relative paths).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().to_path_buf();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let target = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_dir(&p, &target);
        } else {
            std::fs::copy(&p, &target).unwrap();
        }
    }
}

/// A whole-word NaN or inf (any case) in `s`: "infinite" or "information" do not count.
fn non_finite_word(s: &str) -> Option<String> {
    s.split(|c: char| !(c.is_ascii_alphanumeric()))
        .find(|w| {
            let w = w.to_ascii_lowercase();
            w == "nan" || w == "inf" || w == "infinity"
        })
        .map(str::to_string)
}

/// Runs one case; `Err` says what is wrong.
fn run_case(kind: &str, folder: &Folder, name: &str, case: &Case) -> Result<(), String> {
    let src = corpus().join(kind);
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("bad_inputs")
        .join(kind)
        .join(name);
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp).unwrap();
    if src.join("include").is_dir() {
        copy_dir(&src.join("include"), &tmp.join("include"));
    }
    let input_name = folder
        .input_name
        .clone()
        .unwrap_or_else(|| name.to_string());
    std::fs::copy(src.join(name), tmp.join(&input_name)).unwrap();
    let before = snapshot(&tmp);
    // a `.args` case is a command line, one argument per line
    let from_file: Option<Vec<String>> = name.ends_with(".args").then(|| {
        std::fs::read_to_string(src.join(name))
            .unwrap()
            .lines()
            .map(str::to_string)
            .collect()
    });
    let args: Vec<String> = from_file
        .as_ref()
        .or(case.args.as_ref())
        .unwrap_or(&folder.args)
        .iter()
        .map(|a| a.replace("{input}", &input_name).replace("{out}", "out"))
        .collect();
    let out = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(&args)
        .current_dir(&tmp)
        .output()
        .map_err(|e| format!("cannot run flank: {e}"))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let shown = format!(
        "flank {}\nstderr: {stderr}\nstdout: {stdout}",
        args.join(" ")
    );
    let code = out.status.code();
    let expected = case.exit.unwrap_or(1);
    if code != Some(expected) {
        return Err(format!(
            "exit code {code:?}, expected {expected} (101 = panic, 0 = accepted)\n{shown}"
        ));
    }
    if stderr.contains("panicked") {
        return Err(format!("panic\n{shown}"));
    }
    if !stderr.contains(&case.message) {
        return Err(format!("message lacks '{}'\n{shown}", case.message));
    }
    if !stderr.contains(&case.location) {
        return Err(format!(
            "message does not name '{}'\n{shown}",
            case.location
        ));
    }
    // a NaN or inf flank computed; echoing the input's own `nan`/`inf` is fine
    let input_text = String::from_utf8_lossy(&std::fs::read(src.join(name)).unwrap()).to_string();
    if let Some(w) = non_finite_word(&stdout).or_else(|| non_finite_word(&stderr)) {
        if non_finite_word(&input_text).map(|i| i.to_lowercase()) != Some(w.to_lowercase()) {
            return Err(format!("'{w}' in the output\n{shown}"));
        }
    }
    let after = snapshot(&tmp);
    if after != before {
        let written: Vec<_> = after
            .iter()
            .filter(|(k, v)| before.get(*k) != Some(*v))
            .map(|(k, _)| k.display().to_string())
            .collect();
        return Err(format!("files written or changed: {written:?}\n{shown}"));
    }
    Ok(())
}

#[test]
fn every_bad_input_is_a_clear_error() {
    let start = Instant::now();
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build_global();
    let mut kinds: Vec<String> = std::fs::read_dir(corpus())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .map(|p| p.file_name().unwrap().to_string_lossy().to_string())
        .collect();
    kinds.sort();
    let (mut count, mut failures) = (0, Vec::<String>::new());
    for kind in &kinds {
        let dir = corpus().join(kind);
        let text = std::fs::read_to_string(dir.join("expected.toml"))
            .unwrap_or_else(|e| panic!("{kind}/expected.toml: {e}"));
        let folder: Folder =
            toml::from_str(&text).unwrap_or_else(|e| panic!("{kind}/expected.toml: {e}"));
        // every file is a case with an expectation, and every expectation a file
        let mut files: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_file())
            .map(|p| p.file_name().unwrap().to_string_lossy().to_string())
            .filter(|n| n != "expected.toml")
            .collect();
        files.sort();
        for f in &files {
            assert!(
                folder.cases.contains_key(f),
                "{kind}/{f}: no [cases.\"{f}\"] in expected.toml"
            );
        }
        for name in folder.cases.keys() {
            assert!(
                files.contains(name),
                "{kind}/expected.toml names {name}, which is not a file"
            );
        }
        count += folder.cases.len();
        // the cases are independent processes in their own folders: 4 at a time
        use rayon::prelude::*;
        let list: Vec<(&String, &Case)> = folder.cases.iter().collect();
        let found: Vec<String> = list
            .par_iter()
            .with_max_len(1)
            .filter_map(|&(name, case)| {
                run_case(kind, &folder, name, case)
                    .err()
                    .map(|e| format!("{kind}/{name}: {e}"))
            })
            .collect();
        failures.extend(found);
    }
    println!(
        "{count} bad inputs in {} kinds, {} failures, {:.1} s",
        kinds.len(),
        failures.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
    assert!(count >= 60, "the corpus has {count} cases, fewer than 60");
}

#[test]
fn non_finite_words_are_found() {
    assert_eq!(non_finite_word("x = NaN mm").as_deref(), Some("NaN"));
    assert_eq!(non_finite_word("got -inf").as_deref(), Some("inf"));
    assert_eq!(
        non_finite_word("must be positive and finite, information"),
        None
    );
}
