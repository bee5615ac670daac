"""Progress of long calls: the library's events reach a callback (every
position of an LTCA cycle counted once, ending at the total), an exception
in the callback stops the run and is raised, and the tqdm adapter draws
one bar per stage."""

from __future__ import annotations

import pytest

import flank
from conftest import LTCA_KW, SEED002
from flank._progress import TqdmProgress, resolve


def test_an_ltca_reports_every_position_once(tmp_path):
    events = []
    rolls = [-6.0, -3.0, 0.0, 3.0, 6.0]
    r = flank.ltca(
        SEED002,
        out=tmp_path,
        roll_angles=rolls,
        quiet=True,
        progress=lambda task, done, total: events.append((task, done, total)),
        **LTCA_KW,
    )
    assert r.positions == len(rolls)
    stages = [e for e in events if e[0] == "ltca positions"]
    assert stages, events
    assert stages[0] == ("ltca positions", 0, len(rolls))
    # the positions run side by side: their counts arrive in any order, each once
    assert sorted(e[1] for e in stages[1:]) == list(range(1, len(rolls) + 1))
    assert all(e[2] == len(rolls) for e in stages)


def test_an_exception_in_the_callback_stops_the_run(tmp_path):
    class Stop(Exception):
        pass

    def callback(task, done, total):
        if done >= 1:
            raise Stop(f"{task} {done}/{total}")

    with pytest.raises(Stop):
        flank.ltca(
            SEED002,
            out=tmp_path,
            roll_angles=[-8.0 + 0.5 * k for k in range(40)],
            threads=1,
            quiet=True,
            progress=callback,
            **LTCA_KW,
        )
    # stopped before the cycle's summary
    assert not (tmp_path / "summary.json").exists()


def test_progress_choices():
    assert resolve(False, quiet=False) is None
    assert resolve(None, quiet=True) is None
    f = lambda task, done, total: None  # noqa: E731
    assert resolve(f, quiet=True) is f
    with pytest.raises(TypeError):
        resolve(3, quiet=False)


def test_tqdm_bars_per_stage():
    pytest.importorskip("tqdm")
    import io

    sink = io.StringIO()
    bars = TqdmProgress(file=sink)
    bars("ltca positions", 0, 3)
    bars("ltca positions", 2, 3)
    bars("ltca positions", 1, 3)  # out of order: the bar does not go back
    assert bars._bar.n == 2
    bars("ltca positions", 3, 3)
    assert bars._bar is None  # closed at its total
    bars("fe positions", 0, 2)
    bars("fe positions", 1, 3)  # the total grew
    assert bars._bar.total == 3 and bars._task == "fe positions"
    bars.close()
    assert "ltca positions" in sink.getvalue() and "fe positions" in sink.getvalue()
