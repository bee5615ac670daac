"""Seed 002 (spur, z 13/35, m 3.8 mm): load sharing and loaded TE over the
mesh cycle from flank.ltca, plotted with matplotlib.

    python examples/python/seed002_ltca.py [OUT]

The compliance mesh is the coarse one of the tests (flank 1.5 mm, base
3 mm, K = 10 points per contact line: a few seconds); drop the three
options for the scene's own mesh. Writes the files of `flank ltca` and
load_sharing_te.png into OUT (default out/seed002_ltca_py).
"""

# %% [markdown]
# Open as a notebook (Jupyter/VS Code read the `# %%` cells), or run as a script.

# %% setup
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt

import flank

ROOT = Path(__file__).resolve().parents[2]
out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "out/seed002_ltca_py"

# %% the LTCA over the mesh cycle
scene = flank.load_scene(ROOT / "papers/seed002-spur/scene.toml")
r = flank.ltca(scene, out=out, flank_size=1.5, base_size=3.0, points_per_line=10, quiet=True)

# %% load sharing and TE
cycle = r.cycle  # ltca_cycle.csv: one row per roll angle
shares = [c for c in cycle.columns if c.startswith("share_pair")]
fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
for c in shares:
    ax1.plot(cycle["roll_deg"], cycle[c], marker=".", label=c.replace("share_pair", "pair "))
ax1.set_ylabel("load share (fraction)")
ax1.legend()
ax2.plot(cycle["roll_deg"], cycle["te_urad"], marker=".")
ax2.set_xlabel("pinion roll angle (deg)")
ax2.set_ylabel("loaded TE (µrad, pinion)")
fig.suptitle(
    f"seed 002 LTCA: contact ratio {r.contact_ratio:.4f}, TE {r.te_peak_to_peak_urad:.2f} µrad peak-to-peak"
)
fig.tight_layout()
fig.savefig(out / "load_sharing_te.png", dpi=120)

# %% figures
print(f"contact ratio {r.contact_ratio:.4f}; TE peak-to-peak {r.te_peak_to_peak_urad:.3f} µrad "
      f"({r.te_peak_to_peak_arcsec:.3f} arcsec at the gear); {r.positions} positions")
print(f"wrote {out}")
