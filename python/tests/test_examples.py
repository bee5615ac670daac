"""The Python examples run, and their results are the CLI's for the same
inputs."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from conftest import ROOT
from test_ltca import without_times

pytest.importorskip("matplotlib")


def run_example(name: str, *args: str) -> str:
    env = dict(os.environ, MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, str(ROOT / "examples/python" / name), *args],
                       cwd=ROOT, env=env, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return p.stdout


def test_seed002_ltca_example_is_the_clis(seed002_ltca, tmp_path):
    cli, _ = seed002_ltca
    out = tmp_path / "example"
    text = run_example("seed002_ltca.py", str(out))
    assert "contact ratio" in text
    assert (out / "load_sharing_te.png").stat().st_size > 10_000
    got = json.loads((out / "summary.json").read_text())
    expected = json.loads((cli / "summary.json").read_text())
    assert without_times(got) == without_times(expected)


def test_seed003_contact_pattern_example_is_the_clis(tmp_path):
    from conftest import SEED003, run_cli
    from test_ltca import csv_rows

    cli = tmp_path / "cli"
    run_cli("tca", str(SEED003), "--search-directions", "0", "--out", str(cli))
    out = tmp_path / "example"
    text = run_example("seed003_tca_pattern.py", str(out))
    assert "contact ratio" in text
    assert (out / "contact_pattern.png").stat().st_size > 10_000
    got = json.loads((out / "summary.json").read_text())
    expected = json.loads((cli / "summary.json").read_text())
    assert without_times(got) == without_times(expected)
    assert csv_rows(out / "tca_with_edges.csv") == csv_rows(cli / "tca_with_edges.csv")
