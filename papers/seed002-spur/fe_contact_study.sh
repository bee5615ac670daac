#!/bin/sh
# Seed 002 FE contact study: the mesh cycle at one mesh size and the mesh
# sensitivity (papers/seed002-spur/mesh_study.toml) at the paper's four roll angles (18°, 25°, 36°, 48° of its
# cycle, mapped with reference_single_contact_start_deg = 25 in scene.toml).
# Usage (from the repository root): sh papers/seed002-spur/fe_contact_study.sh [OUT]
# Needs ≈ 16 GB of memory for the 0.1 mm mesh; about an hour on 2 cores.
set -e
OUT=${1:-out/seed002-fe}
SCENE=papers/seed002-spur/scene.toml
FLANK="cargo run --release --quiet --"
mkdir -p "$OUT"
# the mesh cycle: 1° steps over the middle pair's engagement, contact limits bisected
$FLANK run $SCENE --flank-size 0.5 --no-vtu --out "$OUT/cycle-0.5" -q
# the calibrated variant (tips shortened to the paper's loaded contact ratio)
$FLANK run papers/seed002-spur/scene_contact_ratio.toml --flank-size 0.5 --no-vtu \
  --out "$OUT/contact-ratio-0.5" -q
# mesh sensitivity (paper's Figure 6): now a campaign, with GCI and the
# extrapolated values (see README.md, "Mesh sensitivity")
$FLANK campaign run papers/seed002-spur/mesh_study.toml --out "$OUT/mesh-study" -q
