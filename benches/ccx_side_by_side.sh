#!/usr/bin/env bash
# Side-by-side run of flank and CalculiX (ccx) on the same C3D20 cantilever
# deck (default 100×10×10 elements, 46 541 nodes, 138 600 free DOFs).
# Needs: ccx (calculix-ccx) and /usr/bin/time (Debian package `time`).
# Usage: benches/ccx_side_by_side.sh [runs] [nx,ny,nz] [threads]
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${1:-3}
CELLS=${2:-100,10,10}
THREADS=${3:-2}
WORK=$(realpath -m "${WORK:-target/side_by_side}")
mkdir -p "$WORK"
cargo build --release --quiet
FLANK=target/release/flank
$FLANK cantilever --cells "$CELLS" --out "$WORK/cantilever.inp"
cp "$WORK/cantilever.inp" "$WORK/job.inp"

measure() { # label, then the command; prints "label wall_s peak_mb"
    local label=$1; shift
    /usr/bin/time -f "%e %M" -o "$WORK/time.txt" "$@" > "$WORK/$label.log" 2>&1
    read -r wall kb < "$WORK/time.txt"
    echo "$label $wall $((kb / 1024))"
}

{
for i in $(seq "$RUNS"); do
    (cd "$WORK" && OMP_NUM_THREADS=$THREADS CCX_NPROC_EQUATION_SOLVER=$THREADS measure ccx ccx -i job)
    measure flank_double $FLANK solve "$WORK/cantilever.inp" --out "$WORK/out_double" --quiet --threads "$THREADS"
    measure flank_mixed $FLANK solve "$WORK/cantilever.inp" --out "$WORK/out_mixed" --quiet --threads "$THREADS" --precision mixed
done
} | tee "$WORK/runs.txt"

python3 - "$WORK" <<'PY'
import json, statistics, sys, collections
work = sys.argv[1]
rows = collections.defaultdict(list)
for line in open(f"{work}/runs.txt"):
    label, wall, mb = line.split()
    rows[label].append((float(wall), float(mb)))
med = {k: (statistics.median(w for w, _ in v), statistics.median(m for _, m in v)) for k, v in rows.items()}
print(f"\n{'program':<14} {'wall s (median)':>16} {'peak MB (median)':>17} {'wall ratio ccx/x':>17} {'memory ratio x/ccx':>19}")
for k, (w, m) in med.items():
    print(f"{k:<14} {w:>16.2f} {m:>17.0f} {med['ccx'][0] / w:>17.2f} {m / med['ccx'][1]:>19.2f}")
for p in ("double", "mixed"):
    s = json.load(open(f"{work}/out_{p}/summary.json"))
    print(f"flank {p}: dofs {s['dofs']}, nnz(L) {s['nnz_factor']}, factorization {s['factorization_s']:.2f} s "
          f"({s['factorization_gflop']:.0f} GFLOP, {s['factorization_gflops']:.1f} GFLOP/s), "
          f"backward error {s['backward_error']:.1e}")
# agreement with ccx
def dat(path):
    out, on = {}, False
    for line in open(path):
        t = line.split()
        if line.strip().startswith("displacements"):
            on = True; continue
        if on and len(t) == 4:
            out[int(t[0])] = [float(x) for x in t[1:]]
    return out
c = dat(f"{work}/job.dat")
import csv
for p in ("double", "mixed"):
    f = {int(r["node"]): [float(r["ux"]), float(r["uy"]), float(r["uz"])] for r in csv.DictReader(open(f"{work}/out_{p}/displacements.csv"))}
    d = max(sum((a - b) ** 2 for a, b in zip(f[n], c[n])) ** 0.5 for n in c)
    m = max(sum(a * a for a in c[n]) ** 0.5 for n in c)
    print(f"flank {p} vs ccx: max|du|/max|u| = {d / m:.2e}")
PY
