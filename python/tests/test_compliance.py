"""Compliance tensors as numpy arrays: the CLI's values, the matrix handed
over without a copy."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

import flank
from conftest import SEED002, run_cli


def test_seed002_tensor_is_the_clis_and_not_copied(tmp_path):
    cli = tmp_path / "cli"
    args = ["--flank-size", "1.5", "--base-size", "3", "--bodies", "pinion"]
    run_cli("compliance", str(SEED002), *args, "--quiet", "--out", str(cli))
    r = flank.compliance(SEED002, out=tmp_path / "py", flank_size=1.5, base_size=3.0, bodies=["pinion"])
    t = r.tensor("pinion")
    # the CLI's file (.h5 with the feature hdf5, else .bin), by its summary
    cli_summary = json.loads((cli / "summary.json").read_text())
    c = flank.read_compliance_tensor(cli / Path(cli_summary["bodies"]["pinion"]["file"]).name)
    n = t.nodes
    assert n == r.summary["bodies"]["pinion"]["flank_nodes"]
    assert t.matrix.shape == (3 * n, 3 * n) and t.matrix.dtype == np.float64
    assert t.positions.shape == (n, 3) and t.normals.shape == (n, 3) and t.uv.shape == (n, 2)
    assert np.array_equal(t.matrix, c.matrix)
    assert np.array_equal(t.positions, c.positions)
    # C is symmetric and positive on its diagonal (a compliance)
    assert np.array_equal(t.matrix, t.matrix.T)
    assert (np.diag(t.matrix) > 0).all()
    # unit normals
    assert np.allclose(np.linalg.norm(t.normals, axis=1), 1.0)
    # no copy: the 2-D array is a view of the buffer Rust read
    assert not t.matrix.flags.owndata and t.matrix.base is not None
    assert t.matrix.flags.c_contiguous
