"""Ctrl-C during a long call: KeyboardInterrupt at the library's next safe
point (an LTCA position boundary), no result file half-written."""

from __future__ import annotations

import os
import signal
import threading
import time

import pytest

import flank
from conftest import SEED002

# Finer than the other tests' LTCA_KW: its tensors take about 2.7 s on a
# 2-core machine, so a SIGINT at 0.3 s lands in them with seconds to spare
# (with LTCA_KW the whole call took 0.7–0.9 s, and a CI dry run on a loaded
# machine once saw the call end before the signal was handled)
SLOW_LTCA_KW = dict(flank_size=1.0, base_size=2.0, points_per_line=10)


@pytest.mark.skipif(not hasattr(signal, "SIGINT") or os.name != "posix", reason="POSIX signals")
def test_ctrl_c_raises_keyboard_interrupt_and_writes_no_summary(tmp_path):
    # SIGINT to this process while the LTCA builds its tensors: the run
    # stops before its first position, so the cycle's files never appear
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            flank.ltca(SEED002, out=tmp_path, quiet=True, **SLOW_LTCA_KW)
    finally:
        timer.cancel()
    elapsed = time.monotonic() - t0
    assert elapsed >= 0.3
    assert not (tmp_path / "summary.json").exists()
    assert not (tmp_path / "ltca_cycle.csv").exists()
    # whatever was written is whole: no temporary file of an atomic write left
    leftovers = [p.name for p in tmp_path.rglob("*") if ".tmp" in p.name]
    assert leftovers == []
    # the stop request was cleared: the next call runs to its end
    assert flank.check(SEED002).contact_ratio > 1.0
