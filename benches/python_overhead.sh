#!/usr/bin/env bash
# The seed 002 LTCA cycle from Python against `flank ltca` (issue: "through
# Python within 5 % of the CLI's time"): both as whole processes, in turn
# (A B A B …), on the same cached compliance tensors, so that what differs
# is the binding (argument conversion, the worker thread, the summary handed
# back as JSON, the interpreter and numpy/pandas import), not the tensors.
#
#   benches/python_overhead.sh [RUNS]        (default 5; after one warm-up each)
#
# Needs target/release/flank (cargo build --release) and the extension in
# target/ci-venv (.ci/run, or maturin develop --release there). Prints each
# run's wall time (s) and peak RSS (MB), then the medians and their ratio.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5}
exe=${FLANK_BIN:-target/release/flank}
py=${PYTHON:-target/ci-venv/bin/python}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scene=papers/seed002-spur/scene.toml
cache=$work/cache
cli=("$exe" ltca "$scene" --cache "$cache" --quiet --out "$work/cli")
pycode="import flank; flank.ltca('$scene', cache='$cache', quiet=True, progress=False, out='$work/py')"

one() { # label, command…: appends "label wall_s rss_mb"
    local label=$1
    shift
    /usr/bin/time -f "$label %e %M" -a -o "$work/times" "$@" > /dev/null
}
# warm-up: fills the tensor cache (not counted)
one warm "${cli[@]}"
one warm "$py" -c "$pycode"
for _ in $(seq "$runs"); do
    one cli "${cli[@]}"
    one python "$py" -c "$pycode"
done
grep -v '^warm' "$work/times" | awk '{printf "%-6s %8.2f s %8.0f MB\n", $1, $2, $3 / 1024}'
"$py" - "$work/times" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1]) if not l.startswith("warm")]
med = {k: statistics.median(float(r[1]) for r in rows if r[0] == k) for k in ("cli", "python")}
rss = {k: statistics.median(float(r[2]) / 1024 for r in rows if r[0] == k) for k in ("cli", "python")}
print(f"median wall: CLI {med['cli']:.2f} s, Python {med['python']:.2f} s, ratio {med['python'] / med['cli']:.3f}")
print(f"median peak RSS: CLI {rss['cli']:.0f} MB, Python {rss['python']:.0f} MB")
PY
