#!/usr/bin/env python3
"""Tables and figures of docs/fidelity.md from the experiments of tools/fidelity/experiments.sh.

usage: summarize.py OUT    (reads OUT/NAME/experiment.tsv and OUT/NAME/repro/comparison.json of every experiment,
                            writes OUT/summary.md, OUT/summary.json, OUT/fidelity_findings.png, OUT/fidelity_noise.png)

For each experiment and each truth (full, observable) it measures the paper's three findings that do not hold on
our default data (docs/fidelity.md):
  1. the headline: k-NN's improvement over the optimal OctoMap, in % of OctoMap's AUC, over the 60 sets (mean with a
     seeded 95 % percentile bootstrap interval over sets, range, sets where k-NN is better) and its trend against
     OctoMap's AUC (the paper: negative, the gain grows where OctoMap is weak) with the controls of
     docs/statistics.md, "Correlation": Pearson r and Spearman rho with permutation p-values, and both within each
     texture and each environment, since a correlation over all sets can come from the groups alone;
  2. Voronoi against plain boxes: mean best OctoMap AUC of each texture (the paper: Voronoi higher);
  3. buildings against the parking lot: mean best OctoMap AUC of each environment (the paper: buildings higher).
Every number comes from the comparison files; nothing is typed in.
"""
import csv
import glob
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy import stats  # noqa: E402

TRUTHS = ("full", "observable")
BOOTSTRAP_RESAMPLES = 10000
BOOTSTRAP_SEED = 1
PERMUTATIONS = 10000
PERMUTATION_SEED = 1
TREND_LEVEL = 0.05


def best_octomap_and_gain(row, truth):
    """OctoMap's best AUC and k-NN's improvement over it in % (as `reproduce` recorded it), under one truth."""
    part = row["truths"][truth]
    return part["octomap"]["auc"], part["improvement_percent"]


def bootstrap_mean_interval(values):
    """95 % percentile interval of the mean over resampled sets (seeded: the same numbers every run)."""
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    values = np.asarray(values)
    means = values[rng.integers(0, len(values), size=(BOOTSTRAP_RESAMPLES, len(values)))].mean(axis=1)
    return float(np.percentile(means, 2.5)), float(np.percentile(means, 97.5))


def permutation_p(x, y):
    """Two-sided permutation p of a correlation: |r| of permuted y against x, as occsweep's
    correlationPermutationTest (docs/statistics.md, "Correlation"); x and y are values or mid-ranks."""
    x = np.asarray(x, dtype=float)
    xm = x - x.mean()

    def statistic(yy, axis=-1):
        ym = yy - yy.mean(axis=-1, keepdims=True)
        return np.abs((ym @ xm) / np.sqrt((xm @ xm) * (ym * ym).sum(axis=-1)))

    return float(stats.permutation_test((np.asarray(y, dtype=float),), statistic, permutation_type="pairings",
                                        vectorized=True, n_resamples=PERMUTATIONS, alternative="greater",
                                        random_state=np.random.default_rng(PERMUTATION_SEED)).pvalue)


def correlations(x, y):
    """Pearson r and Spearman rho; None where x or y is constant or fewer than 3 values."""
    if len(x) < 3 or np.ptp(x) == 0 or np.ptp(y) == 0:
        return None, None
    return float(stats.pearsonr(x, y)[0]), float(stats.spearmanr(x, y).correlation)


def trend(rows, octomap, gain):
    """The paper's trend with its controls; it holds when rho < 0 with p < 0.05 and rho < 0 within each texture."""
    r, rho = correlations(octomap, gain)
    t = {"pearson": r, "spearman": rho, "pearson_p": None, "spearman_p": None, "within": {}}
    if r is not None:
        t["pearson_p"] = permutation_p(octomap, gain)
        t["spearman_p"] = permutation_p(stats.rankdata(octomap), stats.rankdata(gain))
    for key in ("texture", "environment"):
        for value in sorted({row[key] for row in rows}):
            member = np.array([row[key] == value for row in rows])
            gr, grho = correlations(octomap[member], gain[member])
            t["within"][value] = {"n": int(member.sum()), "pearson": gr, "spearman": grho}
    textures = [t["within"][v]["spearman"] for v in sorted({row["texture"] for row in rows})]
    t["holds"] = (rho is not None and rho < 0 and t["spearman_p"] < TREND_LEVEL and
                  all(v is not None and v < 0 for v in textures))
    return t


def findings(rows, truth):
    pairs = [best_octomap_and_gain(r, truth) for r in rows]
    octomap = np.array([p[0] for p in pairs])
    gain = np.array([p[1] for p in pairs])
    low, high = bootstrap_mean_interval(gain)

    def group_mean(key, value):
        return float(np.mean([o for r, o in zip(rows, octomap) if r[key] == value]))

    return {
        "sets": len(rows),
        "improvement_mean": float(gain.mean()), "improvement_ci95": [low, high],
        "improvement_min": float(gain.min()), "improvement_max": float(gain.max()),
        "knn_better": int((gain > 0).sum()),
        "trend": trend(rows, octomap, gain),
        "octomap_mean": float(octomap.mean()),
        "voronoi": group_mean("texture", "voronoi"), "plain": group_mean("texture", "plain"),
        "building": group_mean("environment", "building"), "parking": group_mean("environment", "parking"),
    }


def load_experiments(out):
    experiments = []
    for tsv in sorted(glob.glob(os.path.join(out, "*", "experiment.tsv"))):
        with open(tsv) as f:
            name, options, question, seconds = next(csv.reader(f, delimiter="\t"))
        with open(os.path.join(os.path.dirname(tsv), "repro", "comparison.json")) as f:
            rows = json.load(f)["rows"]
        experiments.append({"name": name, "options": options, "question": question, "seconds": int(seconds),
                            "truths": {t: findings(rows, t) for t in TRUTHS}})
    order = [line.split("\t")[0] for line in open(os.path.join(os.path.dirname(__file__), "experiments.txt"))
             if line.strip() and not line.startswith("#")]
    experiments.sort(key=lambda e: order.index(e["name"]) if e["name"] in order else len(order))
    return experiments


def fmt_signed(v, digits=2):
    return "n/a" if v is None else f"{v:+.{digits}f}"


def table(experiments):
    lines = ["| experiment | truth | improvement % mean [95 % CI] | range % | k-NN better | "
             "OctoMap AUC Voronoi / plain | building / parking |",
             "|---|---|---|---|---|---|---|"]
    for e in experiments:
        for t in TRUTHS:
            f = e["truths"][t]
            lo, hi = f["improvement_ci95"]
            lines.append(
                f"| {e['name']} | {t} | {fmt_signed(f['improvement_mean'])} [{fmt_signed(lo)}, {fmt_signed(hi)}] | "
                f"{fmt_signed(f['improvement_min'])} to {fmt_signed(f['improvement_max'])} | "
                f"{f['knn_better']} of {f['sets']} | "
                f"{f['voronoi']:.3f} / {f['plain']:.3f} | {f['building']:.3f} / {f['parking']:.3f} |")
    return "\n".join(lines)


def fmt_p(p):
    return "n/a" if p is None else f"{p:.2g}"


def trend_table(experiments):
    groups = ("plain", "voronoi", "building", "parking")
    lines = ["| experiment | truth | Pearson r (p) | Spearman rho (p) | " +
             " | ".join(f"r / rho {g}" for g in groups) + " | trend |",
             "|---|---|---|---|" + "---|" * len(groups) + "---|"]
    for e in experiments:
        for t in TRUTHS:
            tr = e["truths"][t]["trend"]
            within = [tr["within"].get(g, {"pearson": None, "spearman": None}) for g in groups]
            lines.append(
                f"| {e['name']} | {t} | {fmt_signed(tr['pearson'], 3)} ({fmt_p(tr['pearson_p'])}) | "
                f"{fmt_signed(tr['spearman'], 3)} ({fmt_p(tr['spearman_p'])}) | " +
                " | ".join(f"{fmt_signed(w['pearson'], 3)} / {fmt_signed(w['spearman'], 3)}" for w in within) +
                f" | {'holds' if tr['holds'] else 'does not hold'} |")
    return "\n".join(lines)


def figure_findings(experiments, out):
    names = [e["name"] for e in experiments]
    y = np.arange(len(names))
    fig, axes = plt.subplots(1, 4, figsize=(15, 0.42 * len(names) + 2.0), sharey=True)
    for offset, t, colour in ((-0.18, "full", "0.5"), (0.18, "observable", "tab:blue")):
        f = [e["truths"][t] for e in experiments]
        mean = np.array([x["improvement_mean"] for x in f])
        err = np.array([[m - x["improvement_ci95"][0], x["improvement_ci95"][1] - m] for m, x in zip(mean, f)]).T
        axes[0].errorbar(mean, y + offset, xerr=err, fmt="o", color=colour, capsize=3, label=f"{t} truth")
        axes[1].plot([x["improvement_max"] for x in f], y + offset, "^", color=colour)
        axes[2].plot([x["voronoi"] - x["plain"] for x in f], y + offset, "s", color=colour)
        axes[3].plot([x["building"] - x["parking"] for x in f], y + offset, "D", color=colour)
    panels = (("k-NN improvement over optimal OctoMap:\nmean of 60 sets, 95 % bootstrap CI", "improvement (%)"),
              ("k-NN improvement over optimal OctoMap:\nlargest of 60 sets (paper: up to 10 %)", "improvement (%)"),
              ("Voronoi minus plain boxes:\nmean best OctoMap AUC (paper: > 0)", "AUC difference"),
              ("Buildings minus parking lot:\nmean best OctoMap AUC (paper: > 0)", "AUC difference"))
    for ax, (title, label) in zip(axes, panels):
        ax.axvline(0, color="k", lw=0.8)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel(label)
        ax.grid(axis="x", alpha=0.3)
    axes[1].axvline(10, color="tab:red", lw=0.8, ls="--")
    axes[0].set_yticks(y, names)
    axes[0].invert_yaxis()
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=2, fontsize=10, bbox_to_anchor=(0.5, 1.0))
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    save(fig, out, "fidelity_findings.png")


def figure_noise(experiments, out):
    sweep = [e for e in experiments if e["name"] == "default" or e["name"].startswith("noise-")]
    if len(sweep) < 3:
        return
    scale = [1.0 if e["name"] == "default" else float(e["name"][len("noise-"):]) for e in sweep]
    order = np.argsort(scale)
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    for shift, t, colour in ((-0.04, "full", "0.45"), (0.04, "observable", "tab:blue")):
        f = [sweep[i]["truths"][t] for i in order]
        x = np.array([scale[i] for i in order]) + shift  # side by side, so that the intervals do not hide each other
        mean = np.array([v["improvement_mean"] for v in f])
        err = np.array([[m - v["improvement_ci95"][0], v["improvement_ci95"][1] - m] for m, v in zip(mean, f)]).T
        axes[0].errorbar(x, mean, yerr=err, marker="o", color=colour, capsize=3, label=f"{t} truth")
        axes[1].plot(x, [v["improvement_max"] for v in f], marker="^", color=colour, label=f"{t} truth")
        axes[2].plot(x, [v["octomap_mean"] for v in f], marker="o", color=colour, label=f"{t} truth")
    axes[0].set_ylabel("k-NN improvement (%), mean of 60 sets\n(95 % bootstrap CI)")
    axes[1].set_ylabel("k-NN improvement (%), largest of 60 sets")
    axes[2].set_ylabel("mean best OctoMap AUC")
    for ax in axes:
        ax.set_xlabel("image noise (multiple of the default sensor noise)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=9)
    axes[0].axhline(0, color="k", lw=0.8)
    fig.tight_layout()
    save(fig, out, "fidelity_noise.png")


def save(fig, out, name):
    path = os.path.join(out, name)
    tmp = f"{path}.tmp-{os.getpid()}.png"
    fig.savefig(tmp, dpi=130, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: summarize.py OUT")
    out = sys.argv[1]
    experiments = load_experiments(out)
    if not experiments:
        sys.exit(f"summarize.py: no OUT/NAME/experiment.tsv under {out}")
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(experiments, f, indent=1)
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("| experiment | `dataset generate` options | question | seconds |\n|---|---|---|---|\n")
        for e in experiments:
            f.write(f"| {e['name']} | `{e['options'] or '(defaults)'}` | {e['question']} | {e['seconds']} |\n")
        f.write("\n" + table(experiments) + "\n")
        f.write("\n" + trend_table(experiments) + "\n")
    figure_findings(experiments, out)
    figure_noise(experiments, out)
    print(open(os.path.join(out, "summary.md")).read())


if __name__ == "__main__":
    main()
