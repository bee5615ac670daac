//! Build script: the git commit of the source (FLANK_GIT_HASH, 12 hex
//! digits) when built from a git checkout, for the identity of campaign jobs
//! (`flank::campaign::flank_version`). Without git, nothing is set and the
//! identity carries the package version only.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let o = Command::new("git").args(args).output().ok()?;
    if !o.status.success() {
        return None;
    }
    let s = String::from_utf8(o.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn main() {
    println!("cargo:rerun-if-env-changed=FLANK_GIT_HASH");
    if let Some(hash) = git(&["rev-parse", "HEAD"]) {
        println!(
            "cargo:rustc-env=FLANK_GIT_HASH={}",
            &hash[..hash.len().min(12)]
        );
        // rebuild when HEAD moves: HEAD itself, the branch ref it names, packed refs
        let mut watch = vec![git(&["rev-parse", "--git-path", "HEAD"])];
        if let Some(r) = git(&["symbolic-ref", "-q", "HEAD"]) {
            watch.push(git(&["rev-parse", "--git-path", &r]));
        }
        watch.push(git(&["rev-parse", "--git-path", "packed-refs"]));
        for p in watch.into_iter().flatten() {
            if std::path::Path::new(&p).exists() {
                println!("cargo:rerun-if-changed={p}");
            }
        }
    }
}
