#!/usr/bin/env python3
"""Check docs/outputs.md against a snapshot of flank's outputs.

    scripts/acceptance/outputs_check.py SNAPSHOT_DIR [--doc docs/outputs.md] [--global]

SNAPSHOT_DIR is a snapshot as scripts/acceptance/snapshot.sh writes it:
SNAPSHOT_DIR/<label>/<command>/... (`_snapshot/` is skipped). Checked:

* every column of every CSV file, and every top-level key of every JSON
  file (summary.json, compare.json, fe_runs/*.json; the variant objects
  `with_edges` / `without_edges` of a summary.json too), must be written
  as `name` (in backticks) in the doc's section of that file: the `###`
  heading under `## `flank <command>`` that names the file in backticks,
  of the snapshot's pair kind where the heading says one ("spur" /
  "helical" or "bevel" / "hypoid" in the heading; none: either kind).
  Numbered per-pair names (`force_pair2_n`) are also found as their
  pattern (`force_pair<k>_n`);
* every file of the snapshot (plots, tensors, decks, VTU included; the
  snapshot's own stdout.txt, stderr.txt, exit_code.txt excepted) must be
  named in backticks in its command's `##` section (`a.{svg,png}` and
  `a.svg/.png` spellings expand; `roll_+012.000deg.vtu` is found as
  `roll_<angle>deg.vtu`, `fe_flank_2_<hex>.json` as
  `fe_flank_<size>_<hash>.json`).

`--global` relaxes the first check to "named anywhere in the doc".
Prints what is missing and the coverage; exit code 0 when nothing is
missing, 1 otherwise, 2 on a usage error. Python 3 standard library only.
"""

import argparse
import csv
import json
import os
import re
import sys

SNAPSHOT_OWN = {"stdout.txt", "stderr.txt", "exit_code.txt"}
CYL = "spur/helical"
BEV = "bevel/hypoid"


def brace_expand(s):
    """`a{b,c}d{e,f}` -> abde, abdf, acde, acdf (no nesting)."""
    m = re.search(r"\{([^{}]*)\}", s)
    if not m:
        return [s]
    out = []
    for alt in m.group(1).split(","):
        out.extend(brace_expand(s[: m.start()] + alt + s[m.end():]))
    return out


def spans(text):
    """Every backtick span of `text`, with its spelling variants."""
    names = set()
    for raw in re.findall(r"`([^`\n]+)`", text):
        raw = raw.strip()
        for s in brace_expand(raw):
            names.add(s)
            # `a.svg/.png`: both extensions
            m = re.match(r"^(.*)\.([A-Za-z0-9]+)((?:/\.[A-Za-z0-9]+)+)$", s)
            if m:
                names.add(f"{m.group(1)}.{m.group(2)}")
                for ext in m.group(3).split("/.")[1:]:
                    names.add(f"{m.group(1)}.{ext}")
            # `fe_runs/fe_flank_<size>_<hash>.json`, `ltca_bodies/` ...
            if "/" in s:
                names.add(s.rsplit("/", 1)[-1])
    return names


def kind_of_heading(h):
    h = h.lower()
    cyl = "spur" in h or "helical" in h
    bev = "bevel" in h or "hypoid" in h
    if cyl and not bev:
        return CYL
    if bev and not cyl:
        return BEV
    return None


def parse_doc(path):
    """{command: {"text": section text, "files": [(heading, kind, text)]}}"""
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    doc = {}
    cmd = None
    sub = None
    for line in lines:
        m = re.match(r"^## `flank ([a-z-]+)`", line)
        if m:
            cmd = m.group(1)
            doc[cmd] = {"text": [], "files": []}
            sub = None
            continue
        if line.startswith("## "):
            cmd, sub = None, None
            continue
        if cmd is None:
            continue
        doc[cmd]["text"].append(line)
        if line.startswith("### "):
            sub = [line[4:], kind_of_heading(line[4:]), []]
            doc[cmd]["files"].append(sub)
        elif sub is not None:
            sub[2].append(line)
    for c in doc.values():
        c["text"] = "\n".join(c["text"])
        c["files"] = [(h, k, h + "\n" + "\n".join(t)) for h, k, t in c["files"]]
    return doc


def file_key(name):
    """The name a snapshot file is documented under."""
    name = re.sub(r"^roll_[+-]\d+\.\d+deg\.(vtu|inp)$", r"roll_<angle>deg.\1", name)
    name = re.sub(r"^fe_flank_.*\.json$", "fe_flank_<size>_<hash>.json", name)
    return name


def pattern(name):
    """`force_pair2_n` -> `force_pair<k>_n`."""
    return re.sub(r"pair\d+", "pair<k>", name)


def pair_kind(label):
    return CYL if re.search(r"spur|helical", label) else BEV


def snapshot_items(root):
    """(label, command, relpath, key, kind, names, what) per CSV/JSON file,
    and (label, command, relpath, key) per file."""
    items, files = [], []
    for label in sorted(os.listdir(root)):
        ldir = os.path.join(root, label)
        if label.startswith("_") or not os.path.isdir(ldir):
            continue
        for command in sorted(os.listdir(ldir)):
            cdir = os.path.join(ldir, command)
            if not os.path.isdir(cdir):
                continue
            for dirpath, _, names in os.walk(cdir):
                for n in sorted(names):
                    rel = os.path.relpath(os.path.join(dirpath, n), cdir)
                    if rel in SNAPSHOT_OWN:
                        continue
                    key = file_key(n)
                    files.append((label, command, rel, key))
                    p = os.path.join(dirpath, n)
                    kind = pair_kind(label)
                    if n.endswith(".csv"):
                        with open(p, newline="", encoding="utf-8") as f:
                            rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
                        if rows:
                            items.append((label, command, rel, key, kind, rows[0], "column"))
                    elif n.endswith(".json"):
                        with open(p, encoding="utf-8") as f:
                            d = json.load(f)
                        if isinstance(d, dict):
                            items.append((label, command, rel, key, kind, list(d), "key"))
                            for v in ("with_edges", "without_edges"):
                                if n == "summary.json" and isinstance(d.get(v), dict):
                                    items.append(
                                        (label, command, f"{rel}:{v}", key, kind, list(d[v]), "key")
                                    )
    return items, files


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("snapshot")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--doc", default=os.path.join(here, "..", "..", "docs", "outputs.md"))
    ap.add_argument("--global", dest="everywhere", action="store_true",
                    help="a name counts wherever it is in the doc")
    a = ap.parse_args()
    if not os.path.isdir(a.snapshot) or not os.path.isfile(a.doc):
        print(f"usage: {sys.argv[0]} SNAPSHOT_DIR [--doc docs/outputs.md]", file=sys.stderr)
        return 2
    doc = parse_doc(a.doc)
    with open(a.doc, encoding="utf-8") as f:
        all_names = spans(f.read())
    items, files = snapshot_items(a.snapshot)

    missing = {}  # (command, kind, key, what) -> {name: [files]}
    no_section = {}  # (command, key, kind) -> [files]
    checked, found = set(), set()
    for label, command, rel, key, kind, names, what in items:
        where = f"{label}/{command}/{rel}"
        sec = doc.get(command)
        cands = [] if sec is None else [
            (h, k, t) for h, k, t in sec["files"] if f"`{key}`" in h or key in spans(h)
        ]
        kinded = [c for c in cands if c[1] in (None, kind)]
        if a.everywhere:
            known = all_names
        elif not kinded:
            no_section.setdefault((command, key, kind), []).append(where)
            known = set()
        else:
            known = set().union(*(spans(t) for _, _, t in kinded))
        for n in names:
            item = (command, kind, key, what, n)
            checked.add(item)
            if n in known or pattern(n) in known:
                found.add(item)
            else:
                missing.setdefault((command, kind, key, what), {}).setdefault(n, []).append(where)

    file_items, file_missing = set(), {}
    for label, command, rel, key in files:
        sec = doc.get(command)
        known = spans(sec["text"]) if sec else set()
        item = (command, key)
        file_items.add(item)
        # a file in a subfolder (ltca_bodies/…, with_edges/…) counts by its name
        if key not in known:
            file_missing.setdefault(item, []).append(f"{label}/{command}/{rel}")

    for (command, key, kind), where in sorted(no_section.items()):
        print(f"NO SECTION  flank {command}: `{key}` ({kind}) — {len(where)} file(s), e.g. {where[0]}")
    for (command, kind, key, what), names in sorted(missing.items()):
        print(f"MISSING     flank {command} {key} ({kind}): {what}s "
              + ", ".join(f"`{n}`" for n in sorted(names))
              + f"  (e.g. {next(iter(names.values()))[0]})")
    for (command, key), where in sorted(file_missing.items()):
        print(f"FILE        flank {command}: `{key}` not named in its section (e.g. {where[0]})")

    distinct = {(c, k, key, n) for c, k, key, w, n in checked}
    distinct_found = {(c, k, key, n) for c, k, key, w, n in found}
    csv_total = {i for i in checked if i[3] == "column"}
    json_total = {i for i in checked if i[3] == "key"}
    print(
        f"columns/keys: {len(distinct_found)}/{len(distinct)} (command, pair kind, file, name) "
        f"documented in their file's section "
        f"[CSV columns {len(csv_total & found)}/{len(csv_total)}, "
        f"JSON top-level keys {len(json_total & found)}/{len(json_total)}]; "
        f"distinct names {len({i[4] for i in found})}/{len({i[4] for i in checked})}; "
        f"files {len(file_items) - len(file_missing)}/{len(file_items)} (command, file name) named; "
        f"{len(items)} CSV/JSON files read"
    )
    return 0 if not (missing or no_section or file_missing) else 1


if __name__ == "__main__":
    sys.exit(main())
