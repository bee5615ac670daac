"""flank.fe_run against `flank run` on seed 002 (coarse, two positions as
tests/cli_run.rs): the same numbers to the last digit, the same files."""

from __future__ import annotations

import json

import numpy as np
import pytest

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


def test_a_scene_without_the_contact_analysis_is_refused_as_by_the_cli(tmp_path):
    from conftest import flank_binary
    import subprocess

    text = "\n".join(l for l in SEED002.read_text().splitlines() if not l.startswith("contact ="))
    path = tmp_path / "no_contact.toml"
    path.write_text(text)
    scene = flank.load_scene(path)
    with pytest.raises(flank.FlankError, match=r"add `contact = \{\}` under \[analyses\]"):
        flank.fe_run(scene, out=tmp_path / "py", flank_size=1.5, base_size=3.0, roll_angles=[0], quiet=True)
    assert not (tmp_path / "py" / "summary.json").exists()
    p = subprocess.run([str(flank_binary()), "run", str(path), "--out", str(tmp_path / "cli")], capture_output=True, text=True)
    assert p.returncode != 0 and "add `contact = {}` under [analyses]" in p.stderr
