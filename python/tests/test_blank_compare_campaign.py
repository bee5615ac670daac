"""flank.blank, flank.compare and flank.campaign against the CLI: the same
outputs to the last digit (times aside), bad inputs as exceptions."""

from __future__ import annotations

import json

import pytest

import flank
from conftest import ROOT, SEED002, flank_binary, run_cli
from test_ltca import without_times

ANNEX_F = ROOT.parent / "shared/reference/iso23509_annexF.json"


def f2_inputs():
    if not ANNEX_F.is_file():
        pytest.skip(f"no {ANNEX_F} (../shared beside the checkout)")
    return json.loads(ANNEX_F.read_text())["F2_spiral_bevel_method0_face_milling"]["inputs"]


def test_blank_is_the_clis(tmp_path):
    inputs = f2_inputs()
    path = tmp_path / "inputs.json"
    path.write_text(json.dumps(inputs))
    cli = json.loads(run_cli("blank", str(path)).stdout)
    assert flank.blank(inputs) == cli
    assert flank.blank(path) == cli
    assert flank.blank(json.dumps(inputs)) == cli
    # ISO 23509 Annex F, sample F2: the printed pitch cone angle and mean cone distance
    assert abs(cli["delta1_deg"] - 19.747) < 0.0005
    assert abs(cli["Rm_mm"] - 81.273) < 0.0005


def test_blank_names_a_bad_key():
    inputs = dict(f2_inputs())
    inputs["z3"] = 7
    with pytest.raises(flank.FlankError, match="z3"):
        flank.blank(inputs)


#: tests/cli_ltca.rs's compare, at one position
COMPARE_CLI = [
    "--fe-flank-sizes", "1.5", "--fe-base-size", "3", "--points-per-line", "5,10",
    "--roll-angles=-8,5", "--flank-size", "1.5", "--base-size", "3",
]


def test_compare_is_the_clis(tmp_path):
    cli = tmp_path / "cli"
    run_cli("compare", str(SEED002), *COMPARE_CLI, "--quiet", "--out", str(cli))
    r = flank.compare(
        SEED002,
        out=tmp_path / "py",
        fe_flank_sizes=[1.5],
        fe_base_size=3.0,
        points_per_line=[5, 10],
        roll_angles=[-8.0, 5.0],
        flank_size=1.5,
        base_size=3.0,
        quiet=True,
        progress=False,
    )
    expected = json.loads((cli / "compare.json").read_text())
    # `speedup` is FE time over LTCA time: a measurement of the run, as the times
    assert isinstance(expected.pop("speedup"), float) and isinstance(r.summary["speedup"], float)
    got = {k: v for k, v in r.summary.items() if k != "speedup"}
    assert without_times(got) == without_times(expected)
    # one FE run and the two LTCA runs (K = 5, 10)
    assert r.positions == 2 and [run["method"] for run in r.runs] == ["fe_contact", "ltca", "ltca"]


def test_campaign_runs_and_collects_as_the_cli(tmp_path):
    exe = flank_binary()
    text = (
        "[campaign]\n"
        f'scene = "{SEED002}"\n'
        'analyses = ["ltca"]\n\n[args]\n'
        'ltca = ["--no-condition", "--roll-angles", "-5,5", "--flank-size", "2", "--base-size", "3", '
        '"--points-per-line", "10"]\n\n[grid]\n"load.torque_nm" = [150.0, 300.0]\n'
    )
    path = tmp_path / "campaign.toml"
    path.write_text(text)
    cli = tmp_path / "cli"
    run_cli("campaign", "run", str(path), "--out", str(cli), "--quiet")
    events = []
    r = flank.campaign(
        path,
        exe=exe,
        out=tmp_path / "py",
        quiet=True,
        progress=lambda task, done, total: events.append((task, done, total)),
    )
    assert r.report["jobs"] == 2 and r.report["finished"] == 2 and not r.report["failed"]
    t = r.table
    assert len(t) == 2 and list(t["status"]) == ["done", "done"]
    cli_table = flank.read_table(cli / "table.csv")
    py_table = flank.read_table(tmp_path / "py" / "table.csv")
    # run times and memory are measurements of the run (flank::campaign::collect::is_time_column)
    figures = [
        c
        for c in cli_table.columns
        if not (c == "seconds" or c.rsplit(".", 1)[-1].endswith("_s") or "time" in c or "memory" in c)
    ]
    assert list(py_table.columns) == list(cli_table.columns)
    assert py_table[figures].equals(cli_table[figures])
    # the TE grows with the torque
    te = [c for c in figures if c.endswith("te_peak_to_peak_urad")]
    assert te, list(cli_table.columns)
    assert py_table[te[0]].iloc[1] > py_table[te[0]].iloc[0]
    assert ("campaign jobs", 2, 2) in events
    # collected again, nothing run: the same table
    again = flank.campaign_collect(path, out=tmp_path / "py")
    assert again.report == {} and again.table[figures].equals(r.table[figures])


def test_campaign_refuses_a_flank_of_another_build(tmp_path):
    fake = tmp_path / "flank"
    fake.write_text("#!/bin/sh\necho 'flank 0.0.0+000000000000'\n")
    fake.chmod(0o755)
    path = tmp_path / "campaign.toml"
    path.write_text(
        f'[campaign]\nscene = "{SEED002}"\nanalyses = ["ltca"]\n\n[grid]\n"load.torque_nm" = [150.0]\n'
    )
    with pytest.raises(flank.FlankError, match="this library is flank"):
        flank.campaign(path, exe=fake, out=tmp_path / "out", quiet=True)
    assert not (tmp_path / "out" / "jobs").exists()
