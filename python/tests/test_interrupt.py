"""Ctrl-C during a long call: KeyboardInterrupt at the library's next safe
point (an LTCA position boundary), no result file half-written."""

from __future__ import annotations

import os
import signal
import threading
import time

import pytest

import flank
from conftest import LTCA_KW, SEED002


@pytest.mark.skipif(not hasattr(signal, "SIGINT") or os.name != "posix", reason="POSIX signals")
def test_ctrl_c_raises_keyboard_interrupt_and_writes_no_summary(tmp_path):
    # SIGINT to this process while the LTCA builds its tensors: the run
    # stops before its first position, so the cycle's files never appear
    # a process started in the background by a non-interactive shell
    # (`cmd &`) inherits SIGINT ignored, and Python then installs no
    # KeyboardInterrupt handler: Ctrl-C is what this test sends, so it
    # takes Python's own handler for its duration
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            flank.ltca(SEED002, out=tmp_path, quiet=True, **LTCA_KW)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    elapsed = time.monotonic() - t0
    assert elapsed >= 0.3
    assert not (tmp_path / "summary.json").exists()
    assert not (tmp_path / "ltca_cycle.csv").exists()
    # whatever was written is whole: no temporary file of an atomic write left
    leftovers = [p.name for p in tmp_path.rglob("*") if ".tmp" in p.name]
    assert leftovers == []
    # the stop request was cleared: the next call runs to its end
    assert flank.check(SEED002).contact_ratio > 1.0
