#!/usr/bin/env bash
# Acceptance snapshot (issue 49): runs every command of commands.txt with the
# flank binary BIN and keeps its output files, stdout, stderr and exit code.
#
#   scripts/acceptance/snapshot.sh BIN OUTDIR
#
# For each line `LABEL COMMAND SCENE ARGS...` of the command table it runs,
# from the repository root (so that scene paths in the outputs are the same
# relative paths before and after),
#
#   BIN COMMAND SCENE ARGS... --out OUTDIR/LABEL/COMMAND
#
# and writes OUTDIR/LABEL/COMMAND/{stdout.txt,stderr.txt,exit_code.txt}.
# A command that fails or is refused (exit code != 0) is part of the
# snapshot, not an error of this script. OUTDIR/_snapshot/ holds what is not
# compared: the command table as run, the binary's checksum and version,
# the repository revision, and log.tsv (label, command, exit code, wall
# seconds, peak RSS, the full command line).
#
# Environment:
#   COMMANDS=FILE   command table (default: commands.txt beside this script)
#   FLANK_REPO=DIR  repository whose papers/ the scene paths refer to
#                   (default: the repository holding this script)
#   ONLY=REGEX      run only the lines whose "LABEL/COMMAND" matches (grep -E);
#                   their old directories are replaced, the rest of OUTDIR is
#                   kept. Without ONLY, OUTDIR must not exist or be empty.
#   CMD_TIMEOUT=S   stop a command after S seconds (exit code 124 recorded);
#                   default 0 = no limit. Use the same value before and after.
#
# Exit code: 0 when every line was run (whatever the commands' own exit
# codes), 2 on a usage error.
set -u -o pipefail

# the whole script is one function, read before it runs: editing this file
# while a snapshot runs does not change the running snapshot
main() {

usage() {
    sed -n '2,/^set -u/p' "$0" | sed -e '$d' -e 's/^# \{0,1\}//' >&2
    exit 2
}
[ $# -eq 2 ] || usage
case "$1" in -h|--help) usage ;; esac

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
bin=$(realpath -e "$1") || { echo "snapshot: no binary $1" >&2; exit 2; }
[ -x "$bin" ] || { echo "snapshot: $bin is not executable" >&2; exit 2; }
commands=${COMMANDS:-$here/commands.txt}
commands=$(realpath -e "$commands") || { echo "snapshot: no command table" >&2; exit 2; }
repo=${FLANK_REPO:-$(cd "$here/../.." && pwd)}
repo=$(realpath -e "$repo") || { echo "snapshot: no repository $FLANK_REPO" >&2; exit 2; }
only=${ONLY:-}
timeout_s=${CMD_TIMEOUT:-0}

mkdir -p "$2" || exit 2
out=$(realpath -e "$2")
if [ -z "$only" ] && [ -n "$(ls -A "$out")" ]; then
    echo "snapshot: $out is not empty (remove it, or set ONLY=REGEX to rerun some lines)" >&2
    exit 2
fi
meta=$out/_snapshot
mkdir -p "$meta"
log=$meta/log.tsv
[ -f "$log" ] || printf 'label\tcommand\texit_code\twall_s\tmax_rss_kb\tcommand_line\n' >"$log"

# what was run, with what (not compared by diff.py)
{
    echo "outdir: $out"
    echo "binary: $bin"
    echo "sha256: $(sha256sum "$bin" | cut -d' ' -f1)"
    echo "version: $("$bin" --version 2>&1)"
    echo "repository: $repo"
    echo "revision: $(git -C "$repo" rev-parse HEAD 2>/dev/null || echo '?')"
    echo "modified files: $(git -C "$repo" status --porcelain 2>/dev/null | wc -l)"
    echo "host: $(hostname) ($(nproc) cores)"
    echo "started: $(date -Is)"
    [ -n "$only" ] && echo "only: $only"
} >>"$meta/meta.txt"
cp "$commands" "$meta/commands.txt.$(date +%Y%m%dT%H%M%S)"

have_time=0
[ -x /usr/bin/time ] && have_time=1

t_all=$(date +%s.%N)
n=0
failed=0
while read -r label cmd scene rest; do
    case "$label" in ''|'#'*) continue ;; esac
    if [ -z "$cmd" ] || [ -z "$scene" ]; then
        echo "snapshot: bad line in $commands: $label $cmd $scene $rest" >&2
        exit 2
    fi
    if [ -n "$only" ] && ! grep -Eq -- "$only" <<<"$label/$cmd"; then
        continue
    fi
    read -r -a args <<<"$rest"
    # the scene as run (provenance; not compared)
    mkdir -p "$meta/scenes/$(dirname "$scene")"
    cp -p "$repo/$scene" "$meta/scenes/$scene" 2>/dev/null || true
    dir=$out/$label/$cmd
    rm -rf "$dir"
    mkdir -p "$dir"
    argv=("$bin" "$cmd" "$scene" "${args[@]}" --out "$dir")
    wrap=()
    [ "$timeout_s" != 0 ] && wrap=(timeout --signal=INT --kill-after=60 "$timeout_s")
    timing=$meta/time.$label.$cmd
    [ $have_time = 1 ] && wrap=(/usr/bin/time -f '%e %M' -o "$timing" "${wrap[@]}")
    echo "[$(date +%T)] $label $cmd: ${argv[*]}" >&2
    t0=$(date +%s.%N)
    (cd "$repo" && exec "${wrap[@]}" "${argv[@]}") \
        </dev/null >"$dir/stdout.txt" 2>"$dir/stderr.txt"
    rc=$?
    t1=$(date +%s.%N)
    echo "$rc" >"$dir/exit_code.txt"
    wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')
    rss=-
    if [ -s "$timing" ]; then
        rss=$(tail -n 1 "$timing" | awk '{ print $2 }')
        # /usr/bin/time prepends "Command exited with non-zero status N"
    fi
    rm -f "$timing"
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$label" "$cmd" "$rc" "$wall" "$rss" "${argv[*]}" >>"$log"
    if [ "$rc" != 0 ]; then
        failed=$((failed + 1))
        echo "    exit $rc after ${wall} s: $(grep -m1 '^error:' "$dir/stderr.txt" | cut -c1-300)" >&2
    else
        echo "    ok, ${wall} s, peak ${rss} kB" >&2
    fi
    n=$((n + 1))
done <"$commands"

total=$(awk -v a="$t_all" -v b="$(date +%s.%N)" 'BEGIN { printf "%.0f", b - a }')
echo "finished: $(date -Is), $n commands, $failed with exit code != 0, ${total} s" >>"$meta/meta.txt"
echo "snapshot: $n commands in ${total} s, $failed with exit code != 0; $(du -sh "$out" | cut -f1) in $out" >&2
}

main "$@"; exit $?
