"""Seed 002: the LTCA against FE contact at three roll angles, load shares
and loaded TE side by side in a pandas table.

    python examples/python/seed002_ltca_vs_fe.py [OUT]

Both on the coarse mesh of the tests (flank 1.5 mm, base 3 mm; LTCA with
K = 10), at −6°, 0° and 6° of pinion roll; the files of `flank ltca` and
`flank run` go to OUT/ltca and OUT/fe (default out/seed002_ltca_vs_fe_py),
the table to OUT/ltca_vs_fe.csv. For the converged comparison with its
error-against-time plot, `flank.compare`.
"""

# %% [markdown]
# Open as a notebook (Jupyter/VS Code read the `# %%` cells), or run as a script.

# %% setup
import sys
from pathlib import Path

import pandas as pd

import flank

ROOT = Path(__file__).resolve().parents[2]
out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "out/seed002_ltca_vs_fe_py"
rolls = [-6.0, 0.0, 6.0]
mesh = dict(flank_size=1.5, base_size=3.0)

# %% the LTCA and FE contact at the same positions
scene = flank.load_scene(ROOT / "papers/seed002-spur/scene.toml")
ltca = flank.ltca(scene, out=out / "ltca", roll_angles=rolls, points_per_line=10, quiet=True, **mesh)
fe = flank.fe_run(scene, out=out / "fe", roll_angles=rolls, quiet=True, **mesh)

# %% side by side
# one row per roll angle in both, in roll order (the LTCA's roll_deg carries
# the round trip through radians in its last digit: rows, not values, match)
a = ltca.cycle.sort_values("roll_deg").reset_index(drop=True)
b = fe.cycle.sort_values("roll_deg").reset_index(drop=True)
assert len(a) == len(b) == len(rolls)
shares = sorted(c for c in a.columns if c.startswith("share_pair") and c in b.columns)
table = pd.DataFrame({"roll_deg": sorted(rolls)})
for c in shares:
    table[f"{c}_ltca"] = a[c]
    table[f"{c}_fe"] = b[c]
table["te_urad_ltca"] = a["te_urad"]
table["te_urad_fe"] = b["te_urad"]
table["te_rel_diff"] = (table["te_urad_ltca"] - table["te_urad_fe"]) / table["te_urad_fe"].abs()
out.mkdir(parents=True, exist_ok=True)
table.to_csv(out / "ltca_vs_fe.csv", index=False)
with pd.option_context("display.width", 160, "display.max_columns", 20):
    print(table.to_string(index=False))
print(f"wrote {out}")
