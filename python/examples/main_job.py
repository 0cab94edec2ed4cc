"""The main job from Python: the paper's nine tilting-table tests (groups CBL, SBL, SBR) as
ensembles of generated walls, the table of the README (measured against simulated collapse
angles), and the fragility curve of each group (the probability that a wall has collapsed
by a tilt α: the fitted lognormal beside the realizations' empirical CDF).

    python python/examples/main_job.py                 # 12 realizations per group, ~20 s on 2 cores
    python python/examples/main_job.py --realizations 4 --out out/py_main_job

Needs matplotlib for the plot (`pip install matplotlib`); run from the repository root.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import polars as pl

import drystone


def lognormal_cdf(alpha_deg: float, median_deg: float, beta: float) -> float:
    """P(collapse angle ≤ α) of a lognormal fragility with median and log-σ β."""
    return 0.5 * (1.0 + math.erf(math.log(alpha_deg / median_deg) / (beta * math.sqrt(2.0))))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--realizations", type=int, default=None, help="per group (default: the study's 12)")
    ap.add_argument("--out", default="out/py_main_job", help="run directory")
    args = ap.parse_args()

    study = drystone.run_study(
        "studies/tilting_table.toml", realizations=args.realizations, out=args.out, progress=_progress()
    )
    measured = pl.read_csv("data/paper/tilting_table_collapse.csv")
    m = measured.group_by("group").agg(
        pl.col("collapse_angle_deg").mean().alias("mean"), pl.col("collapse_angle_deg").std().alias("sd")
    )
    measured_by_group = {r["group"]: r for r in m.iter_rows(named=True)}
    s = study.summary.filter(pl.col("point") == 0)
    print(f"\nmain job, seed {study.seed}, {study.realizations_per_group} realizations per group -> {study.out}\n")
    print("| group | measured (3 specimens) | simulated | inside the simulated 95 % band |")
    print("| --- | --- | --- | --- |")
    for r in s.iter_rows(named=True):
        g = r["group"]
        meas = measured_by_group[g]
        lo, hi = r["collapse_angle_deg_pred95_lo"], r["collapse_angle_deg_pred95_hi"]
        if lo is None or hi is None or lo != lo or hi != hi:
            inside = "n/a (too few realizations for a band)"
        elif lo <= meas["mean"] <= hi:
            inside = "yes"
        else:
            inside = f"no ({r['collapse_angle_deg_mean'] - meas['mean']:+.2f}°)"
        sd = r["collapse_angle_deg_sd"]
        sd = f"{sd:.2f}" if sd is not None and sd == sd else "n/a"
        print(f"| {g} | {meas['mean']:.2f} ± {meas['sd']:.2f}° | {r['collapse_angle_deg_mean']:.2f} ± {sd}° | {inside} |")
    _plot(study, s, Path(args.out) / "fragility_py.png")


def _progress():
    try:
        import tqdm  # noqa: F401

        return True
    except ImportError:
        return lambda done, total, row: print(f"\r{done}/{total} realizations", end="", flush=True)


def _plot(study: drystone.StudyResult, summary: pl.DataFrame, path: Path) -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (pip install matplotlib)")
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    df = study.realizations.filter(pl.col("status") == "collapsed")
    alphas = [10.0 + 0.05 * i for i in range(300)]
    for r in summary.iter_rows(named=True):
        g = r["group"]
        angles = sorted(df.filter(pl.col("group") == g)["collapse_angle_deg"].to_list())
        n = len(angles)
        line = ax.step(angles, [(i + 1) / n for i in range(n)], where="post", label=f"{g} realizations")[0]
        med, beta = r["fragility_median_deg"], r["fragility_beta"]
        if med == med and beta == beta and beta > 0:  # not NaN: a lognormal was fitted
            ax.plot(alphas, [lognormal_cdf(a, med, beta) for a in alphas], color=line.get_color(), ls="--",
                    label=f"{g} lognormal (median {med:.2f}°, β {beta:.3f})")
    ax.set_xlabel("tilt α (degrees)")
    ax.set_ylabel("P(collapsed by α)")
    ax.set_title("Fragility on the tilting table (main job)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    print(f"fragility curves: {path}")


if __name__ == "__main__":
    main()
