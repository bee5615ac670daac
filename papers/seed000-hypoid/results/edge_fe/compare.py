#!/usr/bin/env python3
"""Edge-loaded LTCA against FE contact on seed 000 (tilted, 5-tooth sectors).

usage: compare.py LTCA_OUT FE_OUT[:label] ... > comparison.csv
LTCA_OUT: `flank ltca ... --out` (with_edges/, without_edges/ inside);
FE_OUT: `flank run ... --out` (positions.csv inside). Prints one row per
(roll, pair, FE run): LTCA shares/forces/line kind with and without edges,
FE share/force/p_max/tip-edge flag/closed nodes, TE of each.
"""
import csv, sys

ANGLES = [-9.0, -4.5, 0.0, 3.0, 13.5]

def key(r):
    return (round(float(r["roll_deg"]), 6), int(r["pinion_tooth"]))

def ltca(d, variant):
    pos = {key(r): r for r in csv.DictReader(open(f"{d}/{variant}/ltca_positions.csv"))}
    kinds = {}
    for r in csv.DictReader(open(f"{d}/{variant}/ltca_points.csv")):
        if float(r["force_n"]) > 0:
            kinds.setdefault(key(r), set()).add(r["kind"])
    return pos, kinds

wpos, wkind = ltca(sys.argv[1], "with_edges")
npos, nkind = ltca(sys.argv[1], "without_edges")
out = csv.writer(sys.stdout)
out.writerow(["fe_run", "roll_deg", "pinion_tooth", "ltca_edges_share", "ltca_edges_force_n",
              "ltca_edges_kind", "ltca_noedges_share", "fe_share", "fe_force_n", "fe_pmax_mpa",
              "fe_tip_edge", "fe_closed_nodes", "share_diff_edges_vs_fe",
              "ltca_edges_te_arcsec", "ltca_noedges_te_arcsec", "fe_te_arcsec", "te_rel_diff_edges_vs_fe"])
for arg in sys.argv[2:]:
    path, _, label = arg.partition(":")
    label = label or path
    fe = {key(r): r for r in csv.DictReader(open(f"{path}/positions.csv"))}
    for a in ANGLES:
        for t in range(1, 6):
            k = (round(a, 6), t)
            w = wpos[k]; f = fe[k]; n = npos.get(k)
            ws, fs = float(w["load_share"]), float(f["load_share"])
            ns = float(n["load_share"]) if n else float("nan")
            nte = float(n["te_arcsec"]) if n else float("nan")
            if ws == 0 and fs == 0 and not ns > 0:
                continue
            wte, fte = float(w["te_arcsec"]), float(f["te_arcsec"])
            out.writerow([label, a, t, f"{ws:.4f}", f"{float(w['force_n']):.0f}",
                          "+".join(sorted(wkind.get(k, []))) or "-", f"{ns:.4f}",
                          f"{fs:.4f}", f"{float(f['force_n']):.0f}", f"{float(f['max_pressure_mpa']):.0f}",
                          f["pinion_tip_edge"], f["closed_nodes"], f"{abs(ws - fs):.4f}",
                          f"{wte:.2f}", f"{nte:.2f}", f"{fte:.2f}", f"{(wte - fte) / abs(fte):+.4f}"])
