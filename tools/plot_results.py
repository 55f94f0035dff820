#!/usr/bin/env python3
"""Figures of `occsweep plot` (docs/statistics.md, "Figures"): draws DATA.json, which the command computed from
results files, into FIG in DATA.json's "figure_format" (png, pdf or svg). Every number drawn comes from DATA.json.

usage: plot_results.py DATA.json FIG
"""
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

plt.rcParams.update({"font.size": 10, "axes.titlesize": 10, "legend.fontsize": 8})
AUC = "AUC (area under the TPR-FDR curve, anchored)"


# The mark occsweep checks to know the script drew (PNG: its Software chunk; PDF and SVG: their Creator).
MARK = {"png": {"Software": "occsweep plot"}, "pdf": {"Creator": "occsweep plot"}, "svg": {"Creator": "occsweep plot"}}


def save(fig, path, figure_format):
    # `path` is occsweep's temporary for the figure: occsweep renames it into place once this script succeeded.
    fig.savefig(path, format=figure_format, dpi=150, bbox_inches="tight", metadata=MARK[figure_format])
    plt.close(fig)


def legend_below(fig, ax_or_axes, ncol=3):
    axes = ax_or_axes if isinstance(ax_or_axes, list) else [ax_or_axes]
    handles, labels = [], []
    for ax in axes:
        for h, l in zip(*ax.get_legend_handles_labels()):
            if l not in labels:
                handles.append(h)
                labels.append(l)
    # About 0.8 inch for the axis labels and the legend, whatever the figure's height.
    bottom = min(0.2, 0.8 / fig.get_figheight())
    fig.subplots_adjust(bottom=bottom)
    fig.legend(handles, labels, loc="lower center", ncol=ncol, bbox_to_anchor=(0.5, 0.0), frameon=False)


# One colour, marker and line style per method in every figure (docs/statistics.md, "Figures"): Okabe and Ito's
# palette, which readers with any common colour-vision deficiency tell apart. The shipped methods keep theirs; any
# other method takes one by its name, so that it too keeps it from figure to figure.
OKABE_ITO = ["#000000", "#D55E00", "#0072B2", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442"]
SHIPPED = {"octomap": 0, "knn": 1, "sor-octomap": 2, "ror-octomap": 3, "range-octomap": 4}
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]
LINES = ["-", "--", "-.", ":", (0, (5, 1)), (0, (3, 1, 1, 1, 1, 1)), (0, (1, 1)), (0, (8, 2))]


def style_index(method):
    if method in SHIPPED:
        return SHIPPED[method]
    return 5 + sum(method.encode()) % (len(OKABE_ITO) - 5)


def colours(methods):
    return {m: OKABE_ITO[style_index(m)] for m in methods}


def marker(method):
    return MARKERS[style_index(method)]


def line(method):
    return LINES[style_index(method)]


def curves(d):
    sets = d["sets"]
    cols = min(3, len(sets))
    rows = math.ceil(len(sets) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.6 * rows), squeeze=False)
    col = colours({m["method"] for s in sets for m in s["methods"]})
    for ax, s in zip(axes.flat, sets):
        for m in s["methods"]:
            xs, ys = zip(*m["points"]) if m["points"] else ([], [])
            # Each its own line style and marker, hollow markers and thin lines: a curve under another shows.
            ax.plot(xs, ys, linestyle=line(m["method"]), marker=marker(m["method"]), ms=4, mfc="none", lw=1.2,
                    color=col[m["method"]], label=m["method"])
            ax.annotate(f"{m['method']}: AUC {m['auc']:.4f}" if m["auc"] is not None else m["method"],
                        xy=(0.98, 0.03 + 0.08 * s["methods"].index(m)), xycoords="axes fraction", ha="right",
                        fontsize=7, color=col[m["method"]])
        ax.set_title(s["set"], fontsize=9)
        ax.set_xlabel("FDR (false discovery rate)")
        ax.set_ylabel("TPR (true positive rate)")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(sets):]:
        ax.axis("off")
    shown = f"{len(sets)} of {d['sets_given']} sets" if d["sets_given"] > len(sets) else f"{len(sets)} sets"
    fig.suptitle(f"Best map of each method: TPR against FDR over p_t ({shown})")
    fig.tight_layout()
    legend_below(fig, list(axes.flat), ncol=len(col))
    return fig


def budget(d):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    col = colours({m["method"] for m in d["methods"]})
    for m in d["methods"]:
        n = list(range(1, m["maps"] + 1))
        ax.plot(n, m["curve"], color=col[m["method"]], linestyle=line(m["method"]), lw=1.4,
                label=f"{m['method']} ({m['maps']} maps)")
    if d["baseline_best"] is not None:
        ax.axhline(d["baseline_best"], color="k", ls="--", lw=1, label=f"{d['baseline']}: best of its whole grid")
    ax.set_xscale("log")
    ax.set_xlabel("maps tried at random from the method's grid (n, log scale)")
    ax.set_ylabel("expected best AUC, mean over sets")
    ax.set_title(f"Budget curves over {d['sets']} sets: the expected best of n maps (docs/statistics.md)")
    ax.grid(alpha=0.3, which="both")
    legend_below(fig, ax)
    return fig


def improvement(d):
    fig, (ax, right) = plt.subplots(1, 2, figsize=(8.5, 4.5), sharey=True, gridspec_kw={"width_ratios": [4, 1.2]})
    col = colours({m["method"] for m in d["methods"]})
    for m in d["methods"]:
        if m["points"]:
            ax.scatter([p[0] for p in m["points"]], [p[1] for p in m["points"]], s=22, color=col[m["method"]],
                       marker=marker(m["method"]), edgecolors="k", linewidths=0.3, label=m["method"], alpha=0.8)
    names = [m["method"] for m in d["methods"]]
    for i, m in enumerate(d["methods"]):  # the mean's 95 % interval, one column per method
        iv = m["interval"]
        if iv is not None:
            right.errorbar([i], [iv["mean"]], yerr=[[iv["mean"] - iv["lower"]], [iv["upper"] - iv["mean"]]],
                           fmt=marker(m["method"]), color=col[m["method"]], capsize=3, ms=5)
    for a in (ax, right):
        a.axhline(0, color="k", lw=0.8)
        a.grid(alpha=0.3)
    ax.set_xlabel(f"best AUC of {d['baseline']} on the set")
    ax.set_ylabel(f"improvement over {d['baseline']} (%)")
    ax.set_title("Per set: the best of each method against the baseline's best")
    right.set_xticks(range(len(names)))
    right.set_xticklabels(names, rotation=45, ha="right", fontsize=8)
    right.set_xlim(-0.6, len(names) - 0.4)
    right.set_title("mean, 95 % interval")
    legend_below(fig, ax, ncol=4)
    fig.subplots_adjust(bottom=0.32)
    return fig


def params(d):
    ps = d["parameters"]
    if not ps:
        sys.exit("plot_results.py: no parameter of " + d["method"] + " takes more than one value in these files")
    cols = min(3, len(ps))
    rows = math.ceil(len(ps) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False, sharey=True)
    for ax, p in zip(axes.flat, ps):
        ax.plot(p["values"], p["mean"], "-o", ms=3, color="tab:blue", label="mean over the maps with this value")
        ax.plot(p["values"], p["best"], "-s", ms=3, color="tab:red", label="best of the maps with this value")
        ax.set_xlabel(p["name"])
        ax.grid(alpha=0.3)
    for ax in axes[:, 0]:
        ax.set_ylabel("AUC")
    for ax in list(axes.flat)[len(ps):]:
        ax.axis("off")
    fig.suptitle(f"{d['method']}: AUC against each parameter, over every map and set given")
    fig.tight_layout()
    legend_below(fig, list(axes.flat), ncol=2)
    return fig


FIGURES = {"curves": curves, "budget": budget, "improvement": improvement, "params": params}


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    try:
        with open(sys.argv[1]) as f:
            d = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"plot_results.py: {sys.argv[1]}: {e}")
    if d.get("kind") not in FIGURES:
        sys.exit(f"plot_results.py: {sys.argv[1]}: unknown kind {d.get('kind')!r}")
    figure_format = d.get("figure_format", "png")
    if figure_format not in MARK:
        sys.exit(f"plot_results.py: {sys.argv[1]}: unknown figure_format {figure_format!r}")
    try:
        save(FIGURES[d["kind"]](d), sys.argv[2], figure_format)
    except Exception as e:  # one line, never a traceback: occsweep reports the failure and writes nothing
        sys.exit(f"plot_results.py: cannot draw the {d['kind']} figure: {type(e).__name__}: {e}")


if __name__ == "__main__":
    main()
