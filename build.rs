//! Build script of the lab. `embed_git_commit` bakes sphlab's own commit and a dirty flag into
//! the binary (`SPHLAB_BUILD_COMMIT`, `SPHLAB_BUILD_DIRTY`), so outputs name the code that
//! produced them whatever directory the program runs from. (The core's build script embeds the
//! shaders.)

use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    embed_git_commit();
}

/// Runs git in the crate's directory and returns its trimmed stdout on success.
fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let o = Command::new("git").arg("-C").arg(dir).args(args).output().ok()?;
    if !o.status.success() {
        return None;
    }
    Some(String::from_utf8_lossy(&o.stdout).trim().to_string())
}

/// Sets `SPHLAB_BUILD_COMMIT` (short hash, or "unknown" outside a repository) and
/// `SPHLAB_BUILD_DIRTY` ("true" when tracked files differ from the commit), and asks cargo to
/// rerun when HEAD, the branch ref, the index or any source moves.
fn embed_git_commit() {
    let dir = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap_or_else(|_| ".".into()));
    let commit = git(&dir, &["rev-parse", "--short=10", "HEAD"]).filter(|s| !s.is_empty());
    let dirty = commit.is_some()
        && git(&dir, &["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
    println!("cargo:rustc-env=SPHLAB_BUILD_COMMIT={}", commit.as_deref().unwrap_or("unknown"));
    println!("cargo:rustc-env=SPHLAB_BUILD_DIRTY={dirty}");
    for rel in ["build.rs", "Cargo.toml", "Cargo.lock", "src", "core", "shaders", "kernels-variants"] {
        if dir.join(rel).exists() {
            println!("cargo:rerun-if-changed={rel}");
        }
    }
    let abs = |p: String| {
        let p = PathBuf::from(p);
        if p.is_absolute() {
            p
        } else {
            dir.join(p)
        }
    };
    if let Some(git_dir) = git(&dir, &["rev-parse", "--git-dir"]).map(abs) {
        for f in ["HEAD", "index"] {
            rerun_if_exists(&git_dir.join(f));
        }
    }
    if let (Some(common), Some(head_ref)) =
        (git(&dir, &["rev-parse", "--git-common-dir"]).map(abs), git(&dir, &["symbolic-ref", "-q", "HEAD"]))
    {
        rerun_if_exists(&common.join(&head_ref));
        rerun_if_exists(&common.join("packed-refs"));
    }
}

/// A missing path would make cargo rerun the script (and rebuild the crate) on every build.
fn rerun_if_exists(p: &Path) {
    if p.exists() {
        println!("cargo:rerun-if-changed={}", p.display());
    }
}
