#!/usr/bin/env python3
"""A sweep of the fine fraction Fa of a coarse/fine blend, each bed carried to its whole grading.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/sweep_fa.py --fa 20 30 40 50 --out out/py_sweep

Deposits examples/table2_mix3.toml (the paper's Table 2 grading) at each Fa (percent fine by
volume), measures the bed, which holds the sand down to the scenario's cut-off only, and carries
it to the whole grading as aggpack's whole-grading estimate does: the bed's density plus CPM's
increment from the simulated sizes to the whole grading (summary.json's predictions). Plots
both against Fa and prints the densest blend. `aggpack sweep` does this from the command line.
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import aggpack  # noqa: E402

EXAMPLES = pathlib.Path(__file__).resolve().parents[1]


def carried(report):
    """The bed's density carried to its whole grading by CPM's increment."""
    cpm = report.predictions
    return report.density + cpm["whole_grading"]["cpm"]["density"] - cpm["simulated"]["cpm"]["density"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fa", type=float, nargs="+", default=[20, 25, 30, 35, 40, 45, 50])
    parser.add_argument("--scenario", type=pathlib.Path, default=EXAMPLES / "table2_mix3.toml")
    parser.add_argument("--set", action="append", default=[], help="more --set assignments, as the CLI's")
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/py_sweep"))
    parser.add_argument("--threads", type=int, default=0)
    args = parser.parse_args()

    base = aggpack.Scenario.from_file(args.scenario, set=args.set)
    rows = []
    for fa in args.fa:
        # particles.ca_fa is coarse over fine by volume.
        report = aggpack.run(base.with_overrides([f"particles.ca_fa={(100 - fa) / fa}"]), threads=args.threads)
        rows.append((fa, report.density, carried(report)))
        print(f"Fa {fa:5.1f} %: bed {report.density:.4f}, whole grading {rows[-1][2]:.4f}")

    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / "sweep.csv", "w") as f:
        f.write("fa_percent,density_at_cut,density_whole_grading\n")
        for row in rows:
            f.write("{},{:.6f},{:.6f}\n".format(*row))
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot([r[0] for r in rows], [r[1] for r in rows], "o-", label="the simulated bed (at the cut-off)")
    ax.plot([r[0] for r in rows], [r[2] for r in rows], "s-", label="carried to the whole grading (CPM)")
    ax.set_xlabel("Fa, % fine by volume")
    ax.set_ylabel("packing density")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out / "sweep.png", dpi=120)
    best = max(rows, key=lambda r: r[2])
    print(f"densest: Fa {best[0]:.1f} % ({best[2]:.4f}); {args.out / 'sweep.csv'}, {args.out / 'sweep.png'}")


if __name__ == "__main__":
    main()
