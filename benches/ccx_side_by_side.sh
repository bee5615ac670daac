#!/usr/bin/env bash
# Side-by-side run of flank and CalculiX (ccx) on the same C3D20 cantilever
# deck (default 100×10×10 elements, 46 541 nodes, 138 600 free DOFs).
# Needs: ccx (calculix-ccx) and /usr/bin/time (Debian package `time`).
# flank with its default precision (mixed: f32 factor + CG refinement on the
# f64 matrix, falls back to double; with 2+ threads the two-domain
# factorization), with --substructure off (one factorization) and with
# --precision double, against ccx
# (OMP_NUM_THREADS and CCX_NPROC_EQUATION_SOLVER set to the same threads),
# runs alternating, for each thread count of the list (default 1,2).
# Usage: benches/ccx_side_by_side.sh [runs] [nx,ny,nz] [threads,...]
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${1:-3}
CELLS=${2:-100,10,10}
THREADS=${3:-1,2}
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

uptime | tee "$WORK/load.txt"
{
for i in $(seq "$RUNS"); do
    for t in ${THREADS//,/ }; do
        (cd "$WORK" && OMP_NUM_THREADS=$t CCX_NPROC_EQUATION_SOLVER=$t measure "ccx_t$t" ccx -i job)
        measure "flank_default_t$t" $FLANK solve "$WORK/cantilever.inp" --out "$WORK/out_default_t$t" --quiet --threads "$t"
        measure "flank_plain_t$t" $FLANK solve "$WORK/cantilever.inp" --out "$WORK/out_plain_t$t" --quiet --threads "$t" --substructure off
        measure "flank_double_t$t" $FLANK solve "$WORK/cantilever.inp" --out "$WORK/out_double_t$t" --quiet --threads "$t" --precision double
    done
done
} | tee "$WORK/runs.txt"
uptime | tee -a "$WORK/load.txt"

python3 - "$WORK" <<'PY'
import json, statistics, sys, collections
work = sys.argv[1]
rows = collections.defaultdict(list)
for line in open(f"{work}/runs.txt"):
    label, wall, mb = line.split()
    rows[label].append((float(wall), float(mb)))
med = {k: (statistics.median(w for w, _ in v), statistics.median(m for _, m in v)) for k, v in rows.items()}
print(f"\n{'program':<20} {'wall s (median)':>16} {'peak MB (median)':>17} {'speed-up ccx/x':>15} {'memory x/ccx':>13}")
for k, (w, m) in med.items():
    t = k.rsplit("_t", 1)[1]
    c = med[f"ccx_t{t}"]
    print(f"{k:<20} {w:>16.2f} {m:>17.0f} {c[0] / w:>15.2f} {m / c[1]:>13.2f}")
outs = [k[len("flank_"):] for k in med if k.startswith("flank_")]
for p in outs:
    s = json.load(open(f"{work}/out_{p}/summary.json"))
    print(f"flank {p}: {s['precision']}, dofs {s['dofs']}, nnz(L) {s['nnz_factor']}, factorization {s['factorization_s']:.2f} s "
          f"({s['factorization_gflop']:.0f} GFLOP, {s['factorization_gflops']:.1f} GFLOP/s), ordering {s['ordering_s']:.2f} s, "
          f"symbolic assembly {s['symbolic_assembly_s']:.2f} s, assembly {s['assembly_s']:.2f} s, solve {s['solve_s']:.2f} s "
          f"({s['refinement_steps']} CG steps), total {s['total_s']:.2f} s, backward error {s['backward_error']:.1e}")
    sub = s.get('substructure')
    if sub:
        h = sub['halves']
        print(f"  two-domain: separator {sub['separator_dofs']} DOFs, halves {h[0]['dofs']} / {h[1]['dofs']} DOFs, "
              f"nnz(L) {h[0]['nnz_factor']} / {h[1]['nnz_factor']}, {h[0]['gflop']:.0f} / {h[1]['gflop']:.0f} GFLOP, "
              f"{h[0]['factorization_s']:.2f} / {h[1]['factorization_s']:.2f} s (wall {sub['factorization_s']:.2f} s), Schur {sub['schur_s']:.3f} s")
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
for p in outs:
    f = {int(r["node"]): [float(r["ux"]), float(r["uy"]), float(r["uz"])] for r in csv.DictReader(open(f"{work}/out_{p}/displacements.csv"))}
    d = max(sum((a - b) ** 2 for a, b in zip(f[n], c[n])) ** 0.5 for n in c)
    m = max(sum(a * a for a in c[n]) ** 0.5 for n in c)
    print(f"flank {p} vs ccx: max|du|/max|u| = {d / m:.2e}")
PY
