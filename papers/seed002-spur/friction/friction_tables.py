#!/usr/bin/env python3
"""Seed 002, μ = 0.05: the LTCA's friction models against FE contact with
friction over the mesh cycle (issue 19 point 6).

Reads FE `mesh_cycle.csv` with and without friction (`flank run
--friction-mu 0.05 / 0`) and LTCA `ltca_cycle.csv` (standstill, sliding,
incremental and frictionless runs of `flank ltca`) at the same roll angles
and prints, per position, the friction force per pair, friction's change
of the pair normal forces and of the TE, and the worst differences.

usage: friction_tables.py FE_MU FE_0 LTCA_STANDSTILL LTCA_0 [LTCA_SLIDING] > table.md
"""
import csv
import sys

MU = 0.05


def read(path):
    return {round(float(r["roll_deg"]), 3): r for r in csv.DictReader(open(path))}


def pairs(row):
    return sorted(int(k[len("force_pair"):-2]) for k in row if k.startswith("force_pair"))


def main():
    fe1, fe0, l1, l0 = (read(p) for p in sys.argv[1:5])
    sl = read(sys.argv[5]) if len(sys.argv) > 5 else None
    angles = sorted(set(fe1) & set(fe0) & set(l1) & set(l0))
    f_nom = 312000.0 / 23.2104  # T / r_b1 (N)
    scale = MU * f_nom
    print("| roll (°) | pair | FE F_t (N) | LTCA standstill \\|F_t\\| | FE ΔF_n | LTCA ΔF_n | "
          + ("LTCA sliding F_t | " if sl else "") + "FE ΔTE (µrad) | LTCA ΔTE |")
    print("|---|---|---|---|---|---|" + ("---|" if sl else "") + "---|---|")
    worst = {"ft": (0, None), "dfn": (0, None), "dte": (0, None)}
    for a in angles:
        ps = pairs(fe1[a])
        dte_fe = float(fe1[a]["te_urad"]) - float(fe0[a]["te_urad"])
        dte_l = float(l1[a]["te_urad"]) - float(l0[a]["te_urad"])
        first = True
        for p in ps:
            ffe = float(fe1[a][f"force_pair{p}_n"])
            fl = float(l1[a][f"force_pair{p}_n"])
            if ffe <= 0 and fl <= 0:
                continue
            tfe = float(fe1[a][f"friction_pair{p}_n"])
            tl = abs(float(l1[a][f"friction_pair{p}_n"]))
            dfe = ffe - float(fe0[a][f"force_pair{p}_n"])
            dl = fl - float(l0[a][f"force_pair{p}_n"])
            cells = [f"{a:.0f}", str(p), f"{tfe:.0f}", f"{tl:.0f}", f"{dfe:.0f}", f"{dl:.0f}"]
            if sl:
                cells.append(f"{float(sl[a][f'friction_pair{p}_n']):.0f}")
            cells += [f"{dte_fe:.1f}" if first else "", f"{dte_l:.1f}" if first else ""]
            print("| " + " | ".join(cells) + " |")
            first = False
            for k, e in (("ft", abs(tl - tfe) / scale), ("dfn", abs(dl - dfe) / scale)):
                if e > worst[k][0]:
                    worst[k] = (e, (a, p))
        e = abs(dte_l - dte_fe)
        if e > worst["dte"][0]:
            worst["dte"] = (e, a)
    te_err = max(abs(float(l1[a]["te_urad"]) / float(fe1[a]["te_urad"]) - 1) for a in angles)
    print()
    print(f"{len(angles)} positions; worst friction force difference {worst['ft'][0]:.3f} μF_nom "
          f"(roll, pair {worst['ft'][1]}), worst normal-force change difference "
          f"{worst['dfn'][0]:.3f} μF_nom ({worst['dfn'][1]}), worst TE-change difference "
          f"{worst['dte'][0]:.1f} µrad (roll {worst['dte'][1]}); TE with friction, LTCA vs FE, "
          f"worst {100 * te_err:.2f} %; μF_nom = {scale:.1f} N")


if __name__ == "__main__":
    main()
