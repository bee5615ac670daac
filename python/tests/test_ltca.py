"""flank.ltca against `flank ltca` on seed 002 (coarse): the same numbers
to the last digit, the same files, the tables as DataFrames."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

import flank
from conftest import SEED002

def is_time(key: str) -> bool:
    """A measurement of the run, not a result: wall times (`time_s`,
    `cycle_s`, `*_s`) and the process's peak memory, measured or estimated from
    the memory in use (`peak_memory_mb`, `estimated_peak_memory_mb`: a Python process
    holds numpy and pandas besides the run). Two runs of the same analysis
    differ there; every other value must be the same bit for bit."""
    return key == "time_s" or key.endswith("_s") or key.endswith("peak_memory_mb")


def without_times(v):
    if isinstance(v, dict):
        return {k: without_times(x) for k, x in v.items() if not is_time(k)}
    if isinstance(v, list):
        return [without_times(x) for x in v]
    return v


def csv_rows(path):
    """The CSV's rows as text cells, wall-time columns left out."""
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    keep = [i for i, c in enumerate(header) if not is_time(c)]
    return [[cells[i] for i in keep] for cells in (l.split(",") for l in lines)]


def test_summary_is_the_clis_to_the_last_digit(seed002_ltca):
    cli, r = seed002_ltca
    expected = json.loads((cli / "summary.json").read_text())
    assert without_times(r.summary) == without_times(expected)
    # the attributes are the summary's values
    assert r.te_peak_to_peak_urad == expected["te_peak_to_peak_urad"]
    assert r.contact_ratio == expected["contact_ratio"]
    assert r.positions == expected["positions"] == len(r.steps)
    # a cheap sanity check that the run is the physical one, not just equal
    assert 1.3 < r.contact_ratio < 1.9
    assert r.max_kkt < 1e-9


def test_the_same_files_as_the_cli(seed002_ltca, tmp_path):
    cli, r = seed002_ltca
    cli_files = sorted(p.relative_to(cli) for p in cli.rglob("*") if p.is_file())
    assert r.files == cli_files
    for name in ["ltca_cycle.csv", "ltca_positions.csv", "ltca_points.csv"]:
        assert csv_rows(r.folder / name) == csv_rows(cli / name), name
    # save() copies exactly those files
    saved = r.save(tmp_path / "saved")
    assert sorted(p.relative_to(saved) for p in saved.rglob("*") if p.is_file()) == cli_files
    assert (saved / "ltca_points.csv").read_bytes() == (r.folder / "ltca_points.csv").read_bytes()


def test_tables_are_dataframes_with_the_csv_columns(seed002_ltca):
    cli, r = seed002_ltca
    for table, name in [(r.cycle, "ltca_cycle.csv"), (r.pairs, "ltca_positions.csv"), (r.points, "ltca_points.csv")]:
        header = (cli / name).read_text().splitlines()[0].split(",")
        assert isinstance(table, pd.DataFrame)
        assert list(table.columns) == header, name
        assert len(table) == len((cli / name).read_text().splitlines()) - 1
    cycle = r.cycle
    for col in ["roll_deg", "te_urad", "te_arcsec", "force_pair1_n", "share_pair1"]:
        assert cycle[col].dtype == np.float64, col
    assert len(cycle) == r.positions
    # the cycle's TE column is the CLI's file read to the bit
    cli_te = [float(row.split(",")[list(cycle.columns).index("te_urad")])
              for row in (cli / "ltca_cycle.csv").read_text().splitlines()[1:]]
    assert cycle["te_urad"].tolist() == cli_te
    assert math.isclose(cycle["te_urad"].max() - cycle["te_urad"].min(), r.te_peak_to_peak_urad, rel_tol=1e-12)
    # load shares of the loaded positions sum to one
    shares = cycle[[c for c in cycle.columns if c.startswith("share_pair")]].sum(axis=1)
    assert np.allclose(shares, 1.0, atol=1e-9)
    assert r.tables.keys() >= {"ltca_cycle", "ltca_positions", "ltca_points"}


def test_a_temporary_folder_lives_with_the_result():
    r = flank.ltca(SEED002, quiet=True, flank_size=1.5, base_size=3.0, points_per_line=10,
                   roll_angles=[0.0])
    folder = r.folder
    assert (folder / "summary.json").is_file() and r.positions == 1
    del r
    import gc

    gc.collect()
    assert not folder.exists()


def test_bad_option_values_name_the_option():
    with pytest.raises(ValueError, match="flank_region"):
        flank.ltca(SEED002, flank_region="most", roll_angles=[0.0])
    with pytest.raises(ValueError, match="solver"):
        flank.ltca(SEED002, solver="simplex", roll_angles=[0.0])
