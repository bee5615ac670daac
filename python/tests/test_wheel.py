"""The package built and installed from scratch: a fresh virtual
environment, `pip install .` of a clean copy of the repository, then
`import flank`. Opt-in (FLANK_TEST_WHEEL=1): it compiles the whole
library in release (about 10 minutes on 2 cores), which CI's budget does
not allow beside the Rust tests; CI builds the extension from the
release artifacts of `cargo test` instead (.ci/run)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from conftest import ROOT

pytestmark = pytest.mark.skipif(
    os.environ.get("FLANK_TEST_WHEEL") != "1",
    reason="compiles the whole library from scratch (~10 min); set FLANK_TEST_WHEEL=1",
)


def test_pip_install_in_a_fresh_venv(tmp_path):
    src = tmp_path / "src"
    src.mkdir()
    # the committed files of HEAD only: what a fresh clone has
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", "HEAD"], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(src)], input=archive, check=True)
    venv = tmp_path / "v"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    py = venv / "bin/python"
    subprocess.run([str(py), "-m", "pip", "install", "--quiet", str(src)], check=True)
    p = subprocess.run([str(py), "-c", "import flank; print(flank.__version__)"],
                       cwd=tmp_path, capture_output=True, text=True, check=True)
    version = next(l.split("=")[1].strip().strip('"') for l in (ROOT / "python/Cargo.toml").read_text().splitlines()
                   if l.startswith("version"))
    assert p.stdout.strip() == version
