"""flank.tca against `flank tca` on seed 003 (the eased hypoid pinion):
the same numbers to the last digit and the same tables."""

from __future__ import annotations

import json

import numpy as np

import flank
from conftest import SEED003, run_cli
from test_ltca import csv_rows, without_times


def test_seed003_tca_is_the_clis(tmp_path):
    cli = tmp_path / "cli"
    # as tests/cli_tca.rs: no numerical ellipse search (the cheap run)
    run_cli("tca", str(SEED003), "--search-directions", "0", "--out", str(cli))
    r = flank.tca(flank.load_scene(SEED003), out=tmp_path / "py", search_directions=0, quiet=True)
    expected = json.loads((cli / "summary.json").read_text())
    assert without_times(r.summary) == without_times(expected)
    cli_files = sorted(p.relative_to(cli) for p in cli.rglob("*") if p.is_file())
    assert r.files == cli_files
    for name in ["tca_with_edges.csv", "tca_without_edges.csv", "transitions.csv"]:
        assert csv_rows(r.folder / name) == csv_rows(cli / name), name
    t = r.with_edges
    assert list(t.columns) == (cli / "tca_with_edges.csv").read_text().splitlines()[0].split(",")
    assert t["te_arcsec"].dtype == np.float64
    # the eased set bears as a hypoid set should (tests/cli_tca.rs)
    w = r.summary["with_edges"]
    assert w["crossing"] is None
    assert 2.0 < w["te_peak_to_peak_arcsec"] < 30.0
    assert np.isfinite(t["te_arcsec"]).any()
