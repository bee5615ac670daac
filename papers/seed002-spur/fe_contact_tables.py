#!/usr/bin/env python3
"""Markdown tables of the seed 002 FE contact study (fe_contact_study.sh).

Usage: python3 papers/seed002-spur/fe_contact_tables.py [OUT [PLOTS]]   (default out/seed002-fe)
Reads OUT/cycle-*/, OUT/contact-ratio-*/ and OUT/sensitivity-*/summary.json.
"""
import glob
import json
import os
import sys

out = sys.argv[1] if len(sys.argv) > 1 else "out/seed002-fe"


def load(path):
    with open(path) as f:
        return json.load(f)


cycles = sorted(glob.glob(os.path.join(out, "cycle-*", "summary.json")))
cycles += sorted(glob.glob(os.path.join(out, "contact-ratio-*", "summary.json")))
for path in cycles:
    s = load(path)
    name = os.path.basename(os.path.dirname(path))
    print(f"### {name}\n")
    print("| quantity | value |\n|---|---|")
    rows = [
        ("positions (+ range extension, + bisection)",
         f"{s['positions']} (+{s.get('extension_positions', 0)}, +{s['refinement_positions']})"),
        ("nodes / DOFs / factor nnz", f"{s['nodes']} / {s['dofs']} / {s['nnz_factor']:.3e}"),
        ("contact ratio (loaded, middle pair)", s["contact_ratio"] and f"{s['contact_ratio']:.4f}"),
        ("contact ratio (kinematic)", f"{s['contact_ratio_kinematic']:.4f}"),
        ("middle pair loaded (deg)", s["middle_pair_loaded_deg"] and
         "{:.3f} … {:.3f}".format(*s["middle_pair_loaded_deg"])),
        ("middle pair kinematic (deg)", "{:.3f} … {:.3f}".format(*s["middle_pair_kinematic_deg"])),
        ("single-pair force (N), positions", s["single_pair_force_n"] and
         f"{s['single_pair_force_n']:.1f}, {s['single_contact_positions']}"),
        ("T/r_b1 (N), error", f"{s['nominal_force_n']:.1f}, {100 * s['single_pair_force_error']:+.2f} %"
         if s["single_pair_force_error"] is not None else "—"),
        ("TE mean, peak-to-peak (µrad; µm)",
         f"{s['te_mean_urad']:.0f}, {s['te_peak_to_peak_urad']:.0f}; {s['te_peak_to_peak_um']:.1f}"),
        ("setup (mesh, assembly, factorization) (s)", f"{s['setup_s']:.1f}"),
        ("time per position (s)", f"{s['time_per_position_s']:.1f}"),
        ("total (s)", f"{s['total_s']:.0f}"),
        ("peak memory (MB)", f"{s['peak_memory_mb']:.0f}"),
        ("max law violation (mm), complementarity (N·mm), equilibrium",
         f"{s['max_violation_mm']:.1e}, {s['max_complementarity']:.1e}, {s['max_equilibrium']:.1e}"),
        ("warnings", len(s["warnings"])),
    ]
    for k, v in rows:
        print(f"| {k} | {v} |")
    print()

sens = []
for path in glob.glob(os.path.join(out, "sensitivity-*", "summary.json")):
    s = load(path)
    h = float(os.path.basename(os.path.dirname(path)).split("-")[1])
    sens.append((h, s))
sens.sort(key=lambda x: -x[0])
if sens:
    print("### Mesh sensitivity (paper's Figure 6)\n")
    angles = [st["reference_deg"] for st in sens[0][1]["steps"]]
    head = "| flank size (mm) | nodes | DOFs | " + " | ".join(
        f"{a:.0f}° (roll {st['roll_deg']:+.2f}°): pair 2 / other (N)"
        for a, st in zip(angles, sens[0][1]["steps"])) + " | factorization (s) | time per position (s) | peak (MB) |"
    print(head)
    print("|" + "---|" * (head.count("|") - 1))
    for h, s in sens:
        cells = []
        for st in s["steps"]:
            f = st["pair_force_n"]
            other = f[0] + f[2]
            cells.append(f"{f[1]:.0f} / {other:.0f}")
        print(f"| {h} | {s['nodes']} | {s['dofs']} | " + " | ".join(cells) +
              f" | {s['factorization_s']:.1f} | {s['time_per_position_s']:.1f} | {s['peak_memory_mb']:.0f} |")
    print()
    print("TE (µrad) at the four angles:\n")
    print("| flank size (mm) | " + " | ".join(f"{a:.0f}°" for a in angles) + " |")
    print("|---|" + "---|" * len(angles))
    for h, s in sens:
        print(f"| {h} | " + " | ".join(f"{st['te_urad']:.1f}" for st in s["steps"]) + " |")

# Figure 6 analogue: force per tooth pair against node count at the four angles
if sens:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib not found: no mesh-sensitivity plot)")
        sys.exit(0)
    fig, ax = plt.subplots(figsize=(8, 5))
    nodes = [s["nodes"] for _, s in sens]
    for i, st0 in enumerate(sens[0][1]["steps"]):
        a = st0["reference_deg"]
        mid = [s["steps"][i]["pair_force_n"][1] for _, s in sens]
        other = [s["steps"][i]["pair_force_n"][0] + s["steps"][i]["pair_force_n"][2] for _, s in sens]
        line, = ax.plot(nodes, mid, "o-", label=f"{a:.0f}°: middle pair")
        if max(other) > 0:
            ax.plot(nodes, other, "s--", color=line.get_color(), label=f"{a:.0f}°: other pair")
    ax.set_xscale("log")
    ax.set_xlabel("nodes (both bodies)")
    ax.set_ylabel("normal force per tooth pair (N)")
    ax.set_title("Seed 002: mesh sensitivity at the paper's roll angles\n(flank size "
                 + ", ".join(f"{h}" for h, _ in sens) + " mm)")
    ax.legend(fontsize=8, ncol=2)
    ax.grid(True, which="both", alpha=0.3)
    dest = sys.argv[2] if len(sys.argv) > 2 else out
    for ext in ("svg", "png"):
        fig.savefig(os.path.join(dest, f"mesh_sensitivity.{ext}"), dpi=110, bbox_inches="tight")
    print(f"wrote {dest}/mesh_sensitivity.svg/.png")
