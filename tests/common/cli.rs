//! Running the `flank` binary from the integration tests.

use std::path::PathBuf;
use std::process::Command;

/// `flank ARGS` run in the crate's folder: (success, stdout, stderr).
pub fn flank(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("flank runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `<prefix>_<name>` under the tests' target folder, removed if it was there.
pub fn scratch_dir(prefix: &str, name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{prefix}_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    d
}
