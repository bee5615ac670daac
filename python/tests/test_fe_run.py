"""flank.fe_run against `flank run` on seed 002 (coarse, two positions as
tests/cli_run.rs): the same numbers to the last digit, the same files."""

from __future__ import annotations

import json

import numpy as np

import flank
from conftest import SEED002, run_cli
from test_ltca import csv_rows, without_times


def test_seed002_fe_run_is_the_clis(tmp_path):
    args = ["--flank-size", "1.5", "--base-size", "3", "--roll-angles=-6,6"]
    cli = tmp_path / "cli"
    run_cli("run", str(SEED002), *args, "--quiet", "--out", str(cli))
    r = flank.fe_run(SEED002, out=tmp_path / "py", flank_size=1.5, base_size=3.0, roll_angles=[-6, 6], quiet=True)
    expected = json.loads((cli / "summary.json").read_text())
    assert without_times(r.summary) == without_times(expected)
    assert r.positions == 2
    cli_files = sorted(p.relative_to(cli) for p in cli.rglob("*") if p.is_file())
    assert r.files == cli_files
    assert csv_rows(r.folder / "mesh_cycle.csv") == csv_rows(cli / "mesh_cycle.csv")
    c = r.cycle
    assert list(c.columns) == (cli / "mesh_cycle.csv").read_text().splitlines()[0].split(",")
    assert c["te_urad"].dtype == np.float64 and len(c) == 2
