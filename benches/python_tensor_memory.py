"""Memory of a compliance tensor handed to Python: the peak resident set of
a process that reads one tensor file with flank.read_compliance_tensor,
against the tensor's own size (issue: "memory of a compliance tensor
returned to Python not doubled").

    target/ci-venv/bin/python benches/python_tensor_memory.py [FLANK_SIZE_MM]

Writes seed 002's tensors at the given flank size (default 0.75 mm, base
3 mm) into a temporary folder, then reads the pinion's in a fresh process
and prints: the matrix's bytes, the process's peak RSS before and after the
read (ru_maxrss, MB) and their difference over the matrix's size (1.0 = one
copy; 2.0 = a copy made on the way)."""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

READ = """
import resource, sys, json
import numpy, pandas, flank  # imported before the baseline
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
t = flank.read_compliance_tensor(sys.argv[1])
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({"matrix_mb": t.matrix.nbytes / 2**20, "shape": list(t.matrix.shape),
                  "owns_data": bool(t.matrix.base is None), "before_mb": before, "after_mb": after}))
"""


def main() -> int:
    import flank

    flank_size = float(sys.argv[1]) if len(sys.argv) > 1 else 0.75
    with tempfile.TemporaryDirectory() as tmp:
        r = flank.compliance(
            ROOT / "papers/seed002-spur/scene.toml",
            out=tmp,
            flank_size=flank_size,
            base_size=3.0,
            bodies=["pinion"],
            format="native",
            no_condition=True,
        )
        path = Path(r.summary["bodies"]["pinion"]["file"])
        if not path.is_absolute() and not path.exists():
            path = Path(tmp) / path.name
        p = subprocess.run([sys.executable, "-c", READ, str(path)], capture_output=True, text=True, check=True)
        m = json.loads(p.stdout)
    grew = m["after_mb"] - m["before_mb"]
    print(
        f"tensor {m['shape'][0]} x {m['shape'][1]} ({m['matrix_mb']:.1f} MB); peak RSS {m['before_mb']:.1f} -> "
        f"{m['after_mb']:.1f} MB: +{grew:.1f} MB = {grew / m['matrix_mb']:.2f} x the matrix"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
