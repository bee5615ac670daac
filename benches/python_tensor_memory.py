"""Memory of a compliance tensor handed to Python: the peak resident set of
a process that reads one tensor file with flank.read_compliance_tensor,
against the tensor's own size (issue: "memory of a compliance tensor
returned to Python not doubled").

    target/ci-venv/bin/python benches/python_tensor_memory.py [FLANK_SIZE_MM [native|hdf5]]

Writes seed 002's tensors at the given flank size (default 0.75 mm, base
3 mm) into a temporary folder, then reads the pinion's in a fresh process
and prints the matrix's size and what the read adds to the resident set
(VmRSS after, and the peak VmHWM reset before the read) over it: 1.0 = the
matrix held once, 2.0 = a second copy."""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

READ = """
import sys, json
import numpy, pandas, flank  # imported before the baseline

def status(field):
    for line in open("/proc/self/status"):
        if line.startswith(field + ":"):
            return int(line.split()[1]) / 1024  # kB -> MB

# the peak so far is the imports': reset it (Linux: clear_refs 5 resets VmHWM)
with open("/proc/self/clear_refs", "w") as f:
    f.write("5")
before = status("VmRSS")
t = flank.read_compliance_tensor(sys.argv[1])
print(json.dumps({"matrix_mb": t.matrix.nbytes / 2**20, "shape": list(t.matrix.shape),
                  "before_mb": before, "after_mb": status("VmRSS"), "peak_mb": status("VmHWM")}))
"""


def main() -> int:
    import flank

    flank_size = float(sys.argv[1]) if len(sys.argv) > 1 else 0.75
    fmt = sys.argv[2] if len(sys.argv) > 2 else "native"
    with tempfile.TemporaryDirectory() as tmp:
        r = flank.compliance(
            ROOT / "papers/seed002-spur/scene.toml",
            out=tmp,
            flank_size=flank_size,
            base_size=3.0,
            bodies=["pinion"],
            format=fmt,
            no_condition=True,
        )
        path = Path(r.summary["bodies"]["pinion"]["file"])
        if not path.is_absolute() and not path.exists():
            path = Path(tmp) / path.name
        p = subprocess.run([sys.executable, "-c", READ, str(path)], capture_output=True, text=True, check=True)
        m = json.loads(p.stdout)
    held = m["after_mb"] - m["before_mb"]
    peak = m["peak_mb"] - m["before_mb"]
    print(
        f"{fmt}: tensor {m['shape'][0]} x {m['shape'][1]} ({m['matrix_mb']:.1f} MB); resident {m['before_mb']:.1f} MB before the read; "
        f"held after it +{held:.1f} MB = {held / m['matrix_mb']:.2f} x the matrix, peak during it +{peak:.1f} MB = "
        f"{peak / m['matrix_mb']:.2f} x"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
