"""Shared fixtures: the repository, the `flank` binary the CLI comparisons
run, and the seed 002 coarse LTCA run once by the CLI and once from Python
with the same options (the options tests/cli_ltca.rs uses to keep it cheap)."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SEED002 = ROOT / "papers/seed002-spur/scene.toml"
SEED003 = ROOT / "papers/seed003-hypoid/scene_eased.toml"

#: seed 002's coarse LTCA (tests/cli_ltca.rs): flank 1.5 mm, base 3 mm, K = 10
LTCA_CLI = ["--flank-size", "1.5", "--base-size", "3", "--points-per-line", "10"]
LTCA_KW = dict(flank_size=1.5, base_size=3.0, points_per_line=10)


def flank_binary() -> Path:
    """The CLI to compare with: $FLANK_BIN, else target/release/flank (the
    build of `cargo test --release`); the comparisons skip without it,
    unless $FLANK_REQUIRE_CLI=1 (.ci/run) makes that a failure."""
    exe = Path(os.environ.get("FLANK_BIN", ROOT / "target/release/flank"))
    if not exe.is_file():
        reason = f"no flank binary at {exe} (cargo build --release, or set FLANK_BIN)"
        if os.environ.get("FLANK_REQUIRE_CLI") == "1":
            pytest.fail(reason)
        pytest.skip(reason)
    return exe


def run_cli(*args: str) -> subprocess.CompletedProcess:
    """Runs `flank ARGS…` from the repository root; fails the test on a non-zero exit."""
    p = subprocess.run([str(flank_binary()), *args], cwd=ROOT, capture_output=True, text=True)
    assert p.returncode == 0, f"flank {' '.join(args)}: exit {p.returncode}\n{p.stderr}"
    return p


@pytest.fixture(scope="session")
def seed002_ltca(tmp_path_factory):
    """(CLI folder, Python result) of seed 002's coarse LTCA."""
    import flank

    cli = tmp_path_factory.mktemp("ltca_cli")
    run_cli("ltca", str(SEED002), *LTCA_CLI, "--quiet", "--out", str(cli))
    py = tmp_path_factory.mktemp("ltca_py")
    result = flank.ltca(flank.load_scene(SEED002), out=py, quiet=True, **LTCA_KW)
    return cli, result
