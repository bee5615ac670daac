"""Seed 003 (hypoid, the eased pinion): the unloaded contact pattern on the
pinion flank and the TE curves from flank.tca, plotted with matplotlib.

    python examples/python/seed003_tca_pattern.py [OUT]

The pattern is the path of the contact point in the pinion's axial
projection (`pinion_face_mm` along the face, `pinion_profile_mm` height
above the pitch cone), marked by the size of the curvature contact
ellipse at the elastic approach δ = 6.35 µm. Writes the files of
`flank tca --search-directions 0` and contact_pattern.png into OUT
(default out/seed003_tca_py).
"""

# %% [markdown]
# Open as a notebook (Jupyter/VS Code read the `# %%` cells), or run as a script.

# %% setup
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import flank

ROOT = Path(__file__).resolve().parents[2]
out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "out/seed003_tca_py"

# %% the unloaded TCA
scene = flank.load_scene(ROOT / "papers/seed003-hypoid/scene_eased.toml")
r = flank.tca(scene, out=out, search_directions=0, quiet=True)

# %% contact pattern and TE
t = r.with_edges  # tca_with_edges.csv: per position and tooth pair
mid = t[(t["pair"] == 0) & (t["system"] == "flank")]
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
ax1.plot(mid["pinion_face_mm"], mid["pinion_profile_mm"], "k.-", label="contact path (middle pair)")
# the curvature ellipse's size at δ: marker area ∝ semi-major axis a (mm)
ellipse = mid.dropna(subset=["semi_major_mm"])
ax1.scatter(ellipse["pinion_face_mm"], ellipse["pinion_profile_mm"], s=20 * ellipse["semi_major_mm"],
            alpha=0.3, color="tab:blue", label="ellipse semi-major (marker area)")
ax1.set_xlabel("pinion face (mm, toward the heel)")
ax1.set_ylabel("height above the pitch cone (mm)")
ax1.set_title("pinion contact pattern (unloaded)")
ax1.legend()
for variant, table in [("with edges", r.with_edges), ("without edges", r.without_edges)]:
    te = table.groupby("roll_deg")["te_arcsec"].first()
    ax2.plot(te.index, te.values, ".-", label=variant)
ax2.set_xlabel("pinion roll (deg)")
ax2.set_ylabel("unloaded TE (arcsec, gear)")
ax2.legend()
fig.tight_layout()
fig.savefig(out / "contact_pattern.png", dpi=120)

# %% figures
w = r.summary["with_edges"]
print(f"contact ratio {w['contact_ratio']:.3f}; TE peak-to-peak {w['te_peak_to_peak_arcsec']:.2f} arcsec; "
      f"{len(mid)} flank contacts of the middle pair")
print(f"wrote {out}")
