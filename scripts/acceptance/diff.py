#!/usr/bin/env python3
"""Diff two acceptance snapshots (scripts/acceptance/snapshot.sh) value by value.

    scripts/acceptance/diff.py BEFORE AFTER [--map columns.toml] [--rtol 0] [--atol 0]

Walks both trees and compares every file present on both sides:

* CSV (.csv, .tsv): header-aware, cell by cell (columns matched by name,
  rows by index); numeric cells as numbers, text cells exactly;
* JSON (.json; also stdout.txt when it is one JSON document): every value,
  recursively (objects by key, arrays by index);
* everything else that is text (stdout.txt, the messages of stderr.txt,
  exit_code.txt, .md, .inp, ...): line by line (aligned on the lines' text
  with the numbers blanked), the non-numeric text exactly and every number
  as a number; markdown tables cell by cell with their header names.

Numbers are equal when |a - b| <= atol + rtol * max(|a|, |b|); with the
defaults (0, 0) that is equality of the parsed floats ("1.50" = "1.5",
NaN = NaN). Time-like values are not compared: columns and keys whose name
contains time/timing/seconds/elapsed/speedup/threads, has a word
wall/cpu/date/version/commit/host/hostname/rss/memory, starts with the word
build, or ends in a unit of time or memory (_s, _ms, _us, _mb, _gb, _kb,
also gflop_per_s; not velocities such as _m_s, _mm_s, _rad_s); in text, numbers followed by a unit of time or memory
(s, ms, µs, min, h, kB, MB, GB) or by × (a speed-up), and the numbers of
`key: value` / `key = value` lines whose key is time-like. Binary files
(.vtu, .h5, .png, .svg, .parquet, .bin, ...) are not compared, only listed
when present on one side. The snapshots' own root paths (and the OUTDIR
snapshot.sh recorded, for a moved or copied snapshot) are replaced by
<ROOT> in all text before comparing. OUTDIR/_snapshot/ (timings, checksums)
is skipped.

--map FILE (TOML) maps renamed files, columns and keys; see README.md.

Exit code: 0 when equal (no differences, no file on one side only), 1 when
not, 2 on a usage error.
"""

from __future__ import annotations

import argparse
import csv
import difflib
import fnmatch
import hashlib
import io
import json
import math
import os
import re
import sys
import tomllib

BINARY_EXT = {
    ".vtu", ".vtk", ".vtp", ".pvd", ".h5", ".hdf5", ".png", ".svg", ".parquet",
    ".bin", ".pdf", ".jpg", ".jpeg", ".gif", ".npy", ".npz", ".gz", ".zip",
    ".xz", ".zst", ".frd", ".dat", ".sta", ".cvg", ".rout",
}
SKIP_DIRS = {"_snapshot"}

# --------------------------------------------------------------------------
# time-like names

_SUBSTRINGS = ("time", "timing", "seconds", "elapsed", "speedup", "threads")
_WORDS = {"wall", "cpu", "date", "version", "commit", "host",
          "hostname", "rss", "memory", "runtime", "walltime"}
_TIME_UNITS = {"s", "ms", "us", "µs", "ns", "min", "mb", "gb", "kb", "mib",
               "gib", "kib"}
# a unit of time after a length or angle is a rate (mm_s = mm/s), not a time
# (but gflop_per_s, a throughput, is a time)
_RATE_BEFORE = {"m", "mm", "um", "µm", "rad", "deg", "rev"}


def name_tokens(name: str) -> list[str]:
    return [t for t in re.split(r"[^0-9A-Za-zµ]+", name.lower()) if t]


def time_like(name: str, extra: list[re.Pattern] | None = None) -> bool:
    """A column or key name of a time, a memory figure or the build."""
    low = name.lower()
    if any(s in low for s in _SUBSTRINGS):
        return True
    toks = name_tokens(name)
    if any(t in _WORDS for t in toks):
        return True
    # build, build_id, build_info (not panel_build, the compressed tensors'
    # figures)
    if toks and toks[0] == "build":
        return True
    # cycle_s, setup_s, peak_memory_mb, "cycle (s)"; not sliding_mm_s
    if len(toks) >= 2 and toks[-1] in _TIME_UNITS and toks[-2] not in _RATE_BEFORE:
        return True
    if len(toks) == 1 and toks[0] in _TIME_UNITS - {"s", "h"}:
        return True
    if extra and any(p.search(name) for p in extra):
        return True
    return False


# --------------------------------------------------------------------------
# numbers in text

NUM = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:inf|NaN|nan)\b"
NUM_RE = re.compile(NUM)
# a number then a unit of time or memory, or "×" (speed-up)
UNIT_AFTER = re.compile(r"\s?(?:s|ms|µs|us|ns|min|kB|KB|MB|GB|MiB|GiB|KiB)(?![A-Za-z0-9µ])|\s?×")
KEY_LINE = re.compile(r'^\s*"?([A-Za-z_][A-Za-z0-9_ ().µ/-]*?)"?\s*[:=]\s')
PLACE = "\x00"


def parse_float(s: str):
    s = s.strip()
    if not s:
        return None
    try:
        return float(s)
    except ValueError:
        return None


def split_numbers(line: str, mask_all: bool = False):
    """(skeleton, numbers): the line with numbers replaced by PLACE, and the
    numbers; time-like numbers are masked as <t> and not returned."""
    out = []
    nums = []
    pos = 0
    for m in NUM_RE.finditer(line):
        a, b = m.span()
        # a number glued to a word (seed000, x1, C3D20) is part of the word
        if a > 0 and (line[a - 1].isalnum() or line[a - 1] == "_") and line[a] not in "+-":
            continue
        out.append(line[pos:a])
        if mask_all or UNIT_AFTER.match(line, b):
            out.append("<t>")
        else:
            out.append(PLACE)
            nums.append(m.group())
        pos = b
    out.append(line[pos:])
    return "".join(out), nums


# --------------------------------------------------------------------------
# mapping file


class Mapping:
    def __init__(self, path: str | None):
        d = {}
        if path:
            with open(path, "rb") as f:
                d = tomllib.load(f)
        unknown = set(d) - {"files", "columns", "keys", "strings", "ignore"}
        if unknown:
            raise SystemExit(f"diff.py: {path}: unknown tables {sorted(unknown)}")
        self.files: dict[str, str] = d.get("files", {})
        self.columns: dict[str, dict[str, str]] = d.get("columns", {})
        self.keys: dict[str, dict[str, str]] = d.get("keys", {})
        # text replaced in the BEFORE side's strings, lines and cells
        self.strings: dict[str, str] = d.get("strings", {})
        ign = d.get("ignore", {})
        self.ignore_files: list[str] = ign.get("files", [])
        self.ignore_names = [re.compile(p) for p in ign.get("names", [])]
        self.ignore_lines = [re.compile(p) for p in ign.get("lines", [])]

    @staticmethod
    def _matches(pattern: str, rel: str) -> bool:
        if pattern == "*":
            return True
        if "/" not in pattern:
            return fnmatch.fnmatchcase(os.path.basename(rel), pattern)
        return fnmatch.fnmatchcase(rel, pattern)

    def after_path(self, rel: str) -> str:
        """The AFTER path of BEFORE file rel ([files])."""
        for old, new in self.files.items():
            if "/" in old:
                if rel == old:
                    return new
                if rel.startswith(old.rstrip("/") + "/"):
                    return new.rstrip("/") + rel[len(old.rstrip("/")):]
            elif os.path.basename(rel) == old:
                return os.path.join(os.path.dirname(rel), new) if "/" not in new else new
        return rel

    def table_for(self, table: dict[str, dict[str, str]], rel: str) -> dict[str, str]:
        out: dict[str, str] = {}
        # "*" first, then file names, then paths: the more specific wins
        for rank in (0, 1, 2):
            for pat, m in table.items():
                r = 0 if pat == "*" else (1 if "/" not in pat else 2)
                if r == rank and self._matches(pat, rel):
                    out.update(m)
        return out

    def ignored_file(self, rel: str) -> bool:
        return any(self._matches(p, rel) for p in self.ignore_files)


# --------------------------------------------------------------------------
# comparison state


def recorded_roots(tree: str) -> list[str]:
    """The directories a snapshot was written to: the tree itself, and the
    OUTDIR that snapshot.sh recorded (meta.txt "outdir:", else the --out of
    log.tsv's command lines), so that a moved or copied snapshot compares as
    its original."""
    roots = {os.path.realpath(tree)}
    meta = os.path.join(tree, "_snapshot")
    try:
        with open(os.path.join(meta, "meta.txt"), encoding="utf-8") as f:
            for line in f:
                if line.startswith("outdir: "):
                    roots.add(line[len("outdir: "):].strip())
    except OSError:
        pass
    try:
        with open(os.path.join(meta, "log.tsv"), encoding="utf-8") as f:
            rows = list(csv.reader(f, delimiter="\t"))
        for r in rows[1:]:
            if len(r) >= 6:
                m = re.search(r"--out (\S+)/" + re.escape(r[0]) + "/" + re.escape(r[1]) + r"$", r[5])
                if m:
                    roots.add(m.group(1))
    except OSError:
        pass
    # the longest first: a root inside another is replaced before it
    return sorted((r for r in roots if r and r != "/"), key=len, reverse=True)


class Report:
    def __init__(self, rtol: float, atol: float, max_print: int, roots: tuple[list[str], list[str]]):
        self.rtol = rtol
        self.atol = atol
        self.max_print = max_print
        self.roots = roots
        self.strings: dict[str, str] = {}
        self.values = {"csv": 0, "json": 0, "text": 0}
        self.ignored = 0
        self.diffs = 0
        self.diff_files: dict[str, int] = {}
        self.printed = 0
        self.files = {"csv": 0, "json": 0, "text": 0}
        # the BEFORE path of the file being compared (for the [columns] and
        # [keys] tables)
        self.cur_rel = ""

    def norm(self, s: str, side: int) -> str:
        for r in self.roots[side]:
            if r in s:
                s = s.replace(r, "<ROOT>")
        if side == 0:
            for old, new in self.strings.items():
                if old in s:
                    s = s.replace(old, new)
        return s

    def num_equal(self, a: float, b: float) -> bool:
        if math.isnan(a) and math.isnan(b):
            return True
        if a == b:
            return True
        if math.isinf(a) or math.isinf(b) or math.isnan(a) or math.isnan(b):
            return False
        return abs(a - b) <= self.atol + self.rtol * max(abs(a), abs(b))

    def diff(self, rel: str, where: str, before, after):
        self.diffs += 1
        self.diff_files[rel] = self.diff_files.get(rel, 0) + 1
        if self.diff_files[rel] <= self.max_print:
            print(f"DIFF {rel}: {where}: {before!s} | {after!s}")
        elif self.diff_files[rel] == self.max_print + 1:
            print(f"DIFF {rel}: ... (more differences in this file not printed)")

    def scalar(self, kind: str, rel: str, where: str, a: str, b: str):
        """Compares two text values: as numbers when both parse."""
        self.values[kind] += 1
        x, y = parse_float(a), parse_float(b)
        if x is not None and y is not None:
            if not self.num_equal(x, y):
                self.diff(rel, where, a, b)
        elif a != b:
            self.diff(rel, where, repr(a), repr(b))


# --------------------------------------------------------------------------
# CSV


def read_csv(path: str, rep: Report, side: int):
    with open(path, newline="", encoding="utf-8") as f:
        text = rep.norm(f.read(), side)
    lines = text.splitlines(keepends=True)
    comments = [l.rstrip("\r\n") for l in lines if l.startswith("#")]
    body = "".join(l for l in lines if not l.startswith("#"))
    delim = "\t" if path.endswith(".tsv") else ","
    rows = list(csv.reader(io.StringIO(body), delimiter=delim))
    header = rows[0] if rows else []
    # duplicate column names: name, name#2, ...
    seen: dict[str, int] = {}
    uniq = []
    for h in header:
        seen[h] = seen.get(h, 0) + 1
        uniq.append(h if seen[h] == 1 else f"{h}#{seen[h]}")
    return comments, uniq, rows[1:]


def compare_csv(rel: str, pa: str, pb: str, rep: Report, mp: Mapping):
    rep.files["csv"] += 1
    ca, ha, ra = read_csv(pa, rep, 0)
    cb, hb, rb = read_csv(pb, rep, 1)
    for i, (x, y) in enumerate(zip(ca, cb)):
        compare_line(rel, f"comment line {i + 1}", x, y, rep, mp, "csv")
    if len(ca) != len(cb):
        rep.diff(rel, "comment lines", len(ca), len(cb))
    cmap = mp.table_for(mp.columns, rep.cur_rel)
    ib = {h: j for j, h in enumerate(hb)}
    used_b = set()
    cols = []
    for j, h in enumerate(ha):
        hb_name = cmap.get(h, h)
        if hb_name == "" or time_like(h, mp.ignore_names) or time_like(hb_name, mp.ignore_names):
            used_b.update((h, hb_name))
            rep.ignored += len(ra)
            continue
        if hb_name not in ib:
            rep.diff(rel, f"column {h!r}", "present", "missing" + (f" (as {hb_name!r})" if hb_name != h else ""))
            continue
        used_b.add(hb_name)
        cols.append((h, j, ib[hb_name]))
    for h in hb:
        if h not in used_b and not time_like(h, mp.ignore_names):
            rep.diff(rel, f"column {h!r}", "missing", "present")
    if len(ra) != len(rb):
        rep.diff(rel, "rows", len(ra), len(rb))
    for i, (x, y) in enumerate(zip(ra, rb)):
        for h, ja, jb in cols:
            a = x[ja] if ja < len(x) else "<missing>"
            b = y[jb] if jb < len(y) else "<missing>"
            rep.scalar("csv", rel, f"row {i + 1} column {h!r}", a, b)


# --------------------------------------------------------------------------
# JSON


def flatten(v, path=()):
    if isinstance(v, dict):
        if not v:
            yield path, {}
        for k, x in v.items():
            yield from flatten(x, path + (k,))
    elif isinstance(v, list):
        if not v:
            yield path, []
        for i, x in enumerate(v):
            yield from flatten(x, path + (i,))
    else:
        yield path, v


def path_str(p) -> str:
    return "/".join(str(c) for c in p) or "<root>"


def map_path(p: tuple, kmap: dict[str, str]) -> tuple | None:
    """Applies the [keys] map to a BEFORE path; None: dropped."""
    # path patterns (with "/"): the first that matches a prefix
    for old, new in kmap.items():
        if "/" not in old and "/" not in new:
            continue
        pat = old.strip("/").split("/")
        if len(pat) > len(p):
            continue
        stars = []
        ok = True
        for c, q in zip(p, pat):
            if q == "*":
                stars.append(c)
            elif str(c) != q:
                ok = False
                break
        if not ok:
            continue
        if new == "":
            return None
        out = []
        it = iter(stars)
        for q in new.strip("/").split("/"):
            if q == "*":
                out.append(next(it, "*"))
            else:
                out.append(int(q) if q.isdigit() else q)
        return tuple(out) + p[len(pat):]
    # plain names: any component
    out = []
    for c in p:
        if isinstance(c, str) and c in kmap and "/" not in kmap[c]:
            if kmap[c] == "":
                return None
            out.append(kmap[c])
        else:
            out.append(c)
    return tuple(out)


def leaf_equal(a, b, rep: Report) -> bool:
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b if isinstance(a, bool) and isinstance(b, bool) else False
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return rep.num_equal(float(a), float(b))
    if isinstance(a, str) and isinstance(b, str):
        return a == b
    return a == b and type(a) is type(b)


def compare_json_values(rel: str, va, vb, rep: Report, mp: Mapping, kind="json"):
    kmap = mp.table_for(mp.keys, rep.cur_rel)
    fb = dict(flatten(vb))
    prefixes_b = {q[:k] for q in fb for k in range(1, len(q) + 1)}
    seen_b = set()
    missing_reported: set = set()
    for p, a in flatten(va):
        q = map_path(p, kmap)
        names = [c for c in p if isinstance(c, str)]
        if q is None or any(time_like(c, mp.ignore_names) for c in names):
            rep.ignored += 1
            if q is not None:
                seen_b.add(q)
            continue
        if any(time_like(c, mp.ignore_names) for c in q if isinstance(c, str)):
            rep.ignored += 1
            seen_b.add(q)
            continue
        seen_b.add(q)
        rep.values[kind] += 1
        if q not in fb:
            # report a missing subtree once
            top = next((q[:k] for k in range(1, len(q) + 1) if q[:k] not in prefixes_b), q)
            if top not in missing_reported:
                missing_reported.add(top)
                rep.diff(rel, path_str(top), "present", "missing")
            continue
        b = fb[q]
        if isinstance(a, str) and isinstance(b, str):
            a, b = rep.norm(a, 0), rep.norm(b, 1)
        if not leaf_equal(a, b, rep):
            rep.diff(rel, path_str(p) + (f" (as {path_str(q)})" if q != p else ""),
                     json.dumps(a, ensure_ascii=False), json.dumps(b, ensure_ascii=False))
    extra_reported: set = set()
    prefixes_seen = {q[:k] for q in seen_b for k in range(1, len(q) + 1)}
    for q in fb:
        if q in seen_b:
            continue
        if any(time_like(c, mp.ignore_names) for c in q if isinstance(c, str)):
            continue
        top = next((q[:k] for k in range(1, len(q) + 1) if q[:k] not in prefixes_seen), q)
        if top not in extra_reported:
            extra_reported.add(top)
            rep.diff(rel, path_str(top), "missing", "present")


def load_json(path: str):
    with open(path, encoding="utf-8") as f:
        text = f.read()
    # serde_json writes no NaN; Python's json accepts NaN/Infinity anyway
    return json.loads(text)


def compare_json(rel: str, pa: str, pb: str, rep: Report, mp: Mapping):
    try:
        va, vb = load_json(pa), load_json(pb)
    except (ValueError, UnicodeDecodeError):
        return compare_text(rel, pa, pb, rep, mp)
    rep.files["json"] += 1
    compare_json_values(rel, va, vb, rep, mp)


# --------------------------------------------------------------------------
# text


def md_cells(line: str) -> list[str]:
    s = line.strip()
    if s.startswith("|"):
        s = s[1:]
    if s.endswith("|"):
        s = s[:-1]
    return [c.strip() for c in s.split("|")]


def is_md_sep(line: str) -> bool:
    return bool(re.fullmatch(r"\s*\|?\s*:?-{2,}:?\s*(\|\s*:?-{2,}:?\s*)*\|?\s*", line))


def annotate(lines: list[str]):
    """Per line: the markdown table header it belongs to (None outside
    tables)."""
    out = []
    header = None
    for i, l in enumerate(lines):
        if l.lstrip().startswith("|"):
            if header is None and i + 1 < len(lines) and is_md_sep(lines[i + 1]):
                header = md_cells(l)
                out.append(("header", header))
                continue
            out.append(("row", header) if header is not None else (None, None))
        else:
            header = None
            out.append((None, None))
    return out


def skeleton(line: str) -> str:
    return split_numbers(line)[0]


def compare_line(rel, where, a: str, b: str, rep: Report, mp: Mapping, kind="text", header=None):
    if header is not None and a.lstrip().startswith("|") and b.lstrip().startswith("|") and not is_md_sep(a):
        xa, xb = md_cells(a), md_cells(b)
        if len(xa) == len(xb):
            cmap = mp.table_for(mp.columns, rep.cur_rel)
            for j, (ca, cb) in enumerate(zip(xa, xb)):
                h = header[j] if j < len(header) else f"#{j + 1}"
                if time_like(h, mp.ignore_names) or time_like(cmap.get(h, h) or h, mp.ignore_names):
                    rep.ignored += 1
                    continue
                compare_line(rel, f"{where} column {h!r}", ca, cb, rep, mp, kind)
            return
    m = KEY_LINE.match(a)
    mask = bool(m and time_like(m.group(1), mp.ignore_names))
    sa, na = split_numbers(a, mask)
    sb, nb = split_numbers(b, mask)
    rep.values[kind] += 1
    if sa != sb or len(na) != len(nb):
        rep.diff(rel, where, repr(a), repr(b))
        return
    for x, y in zip(na, nb):
        rep.values[kind] += 1
        if not rep.num_equal(float(x), float(y)):
            rep.diff(rel, f"{where}: {x} vs {y} in", repr(a), repr(b))


STDERR_KEEP = re.compile(r"^\s*(error|warning|note|flagged|thread '.*' panicked)\b", re.I)


def read_lines(path: str, rep: Report, side: int, mp: Mapping, stderr_mode: str):
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = rep.norm(f.read(), side).splitlines()
    if os.path.basename(path) == "stderr.txt" and stderr_mode == "messages":
        lines = [l for l in lines if STDERR_KEEP.match(l)]
    return [l for l in lines if not any(p.search(l) for p in mp.ignore_lines)]


def compare_text(rel: str, pa: str, pb: str, rep: Report, mp: Mapping, stderr_mode="messages"):
    rep.files["text"] += 1
    la = read_lines(pa, rep, 0, mp, stderr_mode)
    lb = read_lines(pb, rep, 1, mp, stderr_mode)
    ann = annotate(la)
    if len(la) == len(lb) or len(la) + len(lb) > 40000:
        blocks = [("equal", 0, min(len(la), len(lb)), 0, min(len(la), len(lb)))]
        if len(la) != len(lb):
            rep.diff(rel, "lines", len(la), len(lb))
    else:
        sm = difflib.SequenceMatcher(None, [skeleton(l) for l in la], [skeleton(l) for l in lb], autojunk=False)
        blocks = sm.get_opcodes()
    for tag, i1, i2, j1, j2 in blocks:
        if tag == "equal" or (tag == "replace" and i2 - i1 == j2 - j1):
            for i, j in zip(range(i1, i2), range(j1, j2)):
                compare_line(rel, f"line {i + 1}" + (f" (after: {j + 1})" if i != j else ""),
                             la[i], lb[j], rep, mp, "text", ann[i][1] if ann[i][0] == "row" else None)
        else:
            for i in range(i1, i2):
                rep.values["text"] += 1
                rep.diff(rel, f"line {i + 1}", repr(la[i]), "<missing>")
            for j in range(j1, j2):
                rep.diff(rel, f"after line {j + 1}", "<missing>", repr(lb[j]))


def is_binary(path: str) -> bool:
    if os.path.splitext(path)[1].lower() in BINARY_EXT:
        return True
    with open(path, "rb") as f:
        head = f.read(8192)
    if b"\0" in head:
        return True
    try:
        head.decode("utf-8")
    except UnicodeDecodeError as e:
        return e.start < len(head) - 4  # not a cut multi-byte character
    return False


def sha256(path: str) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def walk(root: str) -> list[str]:
    out = []
    for d, dirs, files in os.walk(root):
        rel_d = os.path.relpath(d, root)
        dirs[:] = sorted(x for x in dirs if not (rel_d == "." and x in SKIP_DIRS))
        for f in sorted(files):
            out.append(os.path.normpath(os.path.join(rel_d, f)))
    return sorted(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n\n".join(__doc__.split("\n\n")[1:]))
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--map", help="TOML file of renamed files, columns and keys (README.md)")
    ap.add_argument("--rtol", type=float, default=0.0, help="relative tolerance of numbers (default 0: equal floats)")
    ap.add_argument("--atol", type=float, default=0.0, help="absolute tolerance of numbers (default 0)")
    ap.add_argument("--max-print", type=int, default=20, help="differences printed per file (default 20)")
    ap.add_argument("--stderr", choices=["messages", "all", "none"], default="messages",
                    help="stderr.txt: compare its error:/warning:/note: lines (default), all lines, or skip it")
    args = ap.parse_args(argv)
    for d in (args.before, args.after):
        if not os.path.isdir(d):
            print(f"diff.py: {d} is not a directory", file=sys.stderr)
            return 2
    mp = Mapping(args.map)
    roots = (recorded_roots(args.before), recorded_roots(args.after))
    rep = Report(args.rtol, args.atol, args.max_print, roots)
    rep.strings = mp.strings
    fa, fb = walk(args.before), walk(args.after)
    set_b = set(fb)
    matched_b = set()
    only_a, only_b = [], []
    binary_both = 0
    binary_same = 0
    for rel in fa:
        if mp.ignored_file(rel):
            matched_b.add(mp.after_path(rel))
            continue
        relb = mp.after_path(rel)
        if relb not in set_b:
            only_a.append(rel + (f" (as {relb})" if relb != rel else ""))
            continue
        matched_b.add(relb)
        pa = os.path.join(args.before, rel)
        pb = os.path.join(args.after, relb)
        if is_binary(pa) or is_binary(pb):
            binary_both += 1
            if os.path.getsize(pa) == os.path.getsize(pb) and sha256(pa) == sha256(pb):
                binary_same += 1
            continue
        base = os.path.basename(rel)
        ext = os.path.splitext(rel)[1].lower()
        label = rel if relb == rel else f"{rel} -> {relb}"
        rep.cur_rel = rel
        if base == "stderr.txt" and args.stderr == "none":
            continue
        if ext in (".csv", ".tsv"):
            compare_csv(label, pa, pb, rep, mp)
        elif ext == ".json":
            compare_json(label, pa, pb, rep, mp)
        elif base == "stdout.txt" and _is_json_file(pa) and _is_json_file(pb):
            compare_json(label, pa, pb, rep, mp)
        else:
            compare_text(label, pa, pb, rep, mp, args.stderr)
    for rel in fb:
        if rel not in matched_b and not mp.ignored_file(rel):
            only_b.append(rel)
    for rel in only_a:
        print(f"ONLY IN BEFORE {rel}")
    for rel in only_b:
        print(f"ONLY IN AFTER {rel}")
    nf = sum(rep.files.values())
    nv = sum(rep.values.values())
    print()
    print(f"before: {args.before}\nafter:  {args.after}")
    print(f"files compared: {nf} (csv {rep.files['csv']}, json {rep.files['json']}, text {rep.files['text']}); "
          f"binary on both sides, not compared: {binary_both} ({binary_same} byte-identical)")
    print(f"values compared: {nv} (csv cells {rep.values['csv']}, json values {rep.values['json']}, "
          f"text lines and numbers {rep.values['text']}); time-like values ignored: {rep.ignored}")
    tol = "exact" if args.rtol == 0 and args.atol == 0 else f"rtol {args.rtol:g}, atol {args.atol:g}"
    print(f"differences: {rep.diffs} in {len(rep.diff_files)} file(s) ({tol})")
    print(f"files only in before: {len(only_a)}; only in after: {len(only_b)}")
    return 0 if rep.diffs == 0 and not only_a and not only_b else 1


def _is_json_file(path: str) -> bool:
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        if not text.strip():
            return False
        json.loads(text)
        return True
    except (ValueError, UnicodeDecodeError):
        return False


if __name__ == "__main__":
    sys.exit(main())
