#!/usr/bin/env python3
"""Figures of `occsweep reproduce`: Fig. 3-7 of Miao et al. (Sensors 2022) from the step files.

usage: plot_reproduction.py OUT [--into DIR] [STEP...]
       (reads OUT/{fits,nca,comparison,curves,runtime}.json and OUT/maps/*.ply, writes fig3_distribution_fits.png
        ... fig7_runtime.png into DIR, default OUT; with STEPs, as `reproduce --steps`, only their figures; real-stereo
        has none. `occsweep reproduce` passes a temporary folder of its own as DIR and moves each figure into OUT
        itself, replacing only figures whose Software text chunk is "occsweep reproduce": docs/robustness.md)
Every number drawn comes from those files; nothing is typed in here except the paper's 0.1 line of Fig. 4.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(out, name):
    path = os.path.join(out, name)
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"plot_reproduction.py: {path}: {e}")


INTO = None  # where the figures go (--into), default the folder they are read from


def save(fig, out, name):
    # The Software chunk is the figure's proof of being occsweep's: a re-run replaces it, never a user's PNG.
    fig.savefig(os.path.join(INTO or out, name), format="png", dpi=110, bbox_inches="tight",
                metadata={"Software": "occsweep reproduce"})
    plt.close(fig)


def fig3(out):
    f = load(out, "fits.json")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.step(f["grid"], f["empirical_cdf"], where="post", color="0.6", lw=3, label="empirical")
    for fit in f["fits"]:
        cdf = [np.nan if v is None else v for v in fit["cdf"]]
        ax.plot(f["grid"], cdf, lw=1.4, label=f"{fit['name']} (KS to empirical {fit['ks_to_empirical']:.3f})")
    ax.set_xlabel("average distance to the k nearest neighbours s_i (m)")
    ax.set_ylabel("CDF")
    ax.set_title(f"Fig. 3: {f['dataset']} {f['point_cloud_set']} (rank {f['rank']}/{f['sets_ranked']}), "
                 f"k = {f['k']}, {f['samples']} points\nlargest KS distance between fits: {f['max_pairwise_ks']:.3f}",
                 fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save(fig, out, "fig3_distribution_fits.png")


def fig4(out):
    n = load(out, "nca.json")
    features = n["features"]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5), sharey=True)
    for ax, resp, title in zip(axes, ["tpr", "fdr"], ["(a) TPR", "(b) FDR"]):
        rows = [d[resp]["normalized"] for d in n["datasets"] if resp in d]
        w = np.array(rows)
        x = np.arange(len(features))
        width = 0.8 / max(len(rows), 1)
        for i, d in enumerate(n["datasets"]):
            ax.bar(x - 0.4 + (i + 0.5) * width, w[i], width, label=d["dataset"] if resp == "tpr" else None)
        ax.plot(x, w.mean(axis=0), "k_", ms=30, mew=2, label="mean" if resp == "tpr" else None)
        ax.axhline(0.1, color="r", ls="--", lw=1)
        ax.set_xticks(x)
        ax.set_xticklabels(features)
        ax.set_title(f"{title}: normalised NCA weights, {len(rows)} data sets", fontsize=10)
        ax.grid(axis="y", alpha=0.3)
    axes[0].set_ylabel("weight / sum of weights")
    fig.legend(loc="center right", fontsize=6, ncol=1, bbox_to_anchor=(1.08, 0.5))
    fig.suptitle(f"Fig. 4: grid {n['grid']} (Eq. 16 group per data set), red line: the paper's 0.1", fontsize=10)
    save(fig, out, "fig4_nca_weights.png")


def fig5(out):
    c = load(out, "comparison.json")
    rows = [r for r in c["rows"] if r["improvement_percent"] is not None]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5), sharey=True)
    colours = {"1st": "tab:blue", "median": "tab:orange", "last": "tab:red"}
    markers = {"plain": "o", "voronoi": "^"}
    for ax, env, title in zip(axes, ["building", "parking"], ["(a) Building", "(b) Parking lot"]):
        for r in rows:
            if r["environment"] != env:
                continue
            ax.scatter(r["octomap"]["auc"], r["improvement_percent"], c=colours[r["rank_label"]],
                       marker=markers.get(r["texture"], "s"), s=36, edgecolors="k", linewidths=0.4)
            ax.annotate(r["layout"], (r["octomap"]["auc"], r["improvement_percent"]), fontsize=6,
                        xytext=(3, 2), textcoords="offset points")
        ax.axhline(0, color="k", lw=0.8)
        ax.set_xlabel("optimal AUC of OctoMap (octomap-opt)")
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("k-NN improvement over optimal OctoMap (%)")
    handles = [plt.Line2D([], [], ls="", marker="o", color=v, label=f"{k} ranked set") for k, v in colours.items()]
    handles += [plt.Line2D([], [], ls="", marker=v, color="0.4", label=k) for k, v in markers.items()]
    axes[1].legend(handles=handles, fontsize=8)
    fig.suptitle("Fig. 5: improvement by k-NN (knn-opt) over the optimal AUC of OctoMap (octomap-opt)", fontsize=10)
    save(fig, out, "fig5_improvement.png")


def read_ply(path):
    with open(path) as f:
        lines = f.read().splitlines()
    body = lines[lines.index("end_header") + 1:]
    if not body:
        return np.zeros((0, 3)), np.zeros((0, 3))
    a = np.array([list(map(float, line.split())) for line in body])
    return a[:, :3], a[:, 3:6] / 255.0


def fig6(out):
    cv = load(out, "curves.json")
    fig = plt.figure(figsize=(15, 4.8))
    ax = fig.add_subplot(1, 3, 1)
    # The two methods' colours of every occsweep figure (docs/statistics.md, "Figures": Okabe and Ito's palette).
    for key, label, colour in [("octomap", "OctoMap", "#000000"), ("knn", "k-NN", "#D55E00")]:
        m = cv[key]
        ax.plot([p["fdr"] for p in m["curve"]], [p["tpr"] for p in m["curve"]], "o-", color=colour, ms=4,
                label=f"{label} best, AUC {m['auc']:.3f}")
        mc = m["map_counts"]
        ax.plot(mc["fdr"], mc["tpr"], "s", mfc="none", mec=colour, ms=12, mew=2)
    ax.set_xlabel("FDR")
    ax.set_ylabel("TPR")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_title(f"(a) TPR-FDR, {cv['dataset']} {cv['point_cloud_set']}\n(squares: the maps shown)", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    for i, (key, label) in enumerate([("octomap", "(b) OctoMap"), ("knn", "(c) k-NN")]):
        xyz, rgb = read_ply(os.path.join(out, cv[key]["map"]))
        a3 = fig.add_subplot(1, 3, i + 2, projection="3d")
        if len(xyz):
            a3.scatter(xyz[:, 0], xyz[:, 1], xyz[:, 2], c=rgb, marker="s", s=6, depthshade=False)
            span = (xyz.max(axis=0) - xyz.min(axis=0)).max() / 2 + 0.05
            centre = (xyz.max(axis=0) + xyz.min(axis=0)) / 2
            for setter, c0 in zip([a3.set_xlim, a3.set_ylim, a3.set_zlim], centre):
                setter(c0 - span, c0 + span)
        a3.view_init(elev=35, azim=-60)
        mc = cv[key]["map_counts"]
        a3.set_title(f"{label}, p_t {cv[key]['chosen_p_t']:.2f}: TP {mc['tp']} FP {mc['fp']} FN {mc['fn']}\n"
                     "blue TP, red FP, yellow FN", fontsize=9)
    save(fig, out, "fig6_curves_maps.png")


def fig7(out):
    rt = load(out, "runtime.json")
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    om = rt["octomap"]
    n = np.array([s["points"] for s in om["samples"]])
    f = om["fit"]
    xs = np.linspace(0, n.max() * 1.05, 50)
    shapes = dict(zip(sorted({s["dataset"] for s in om["samples"]}), "os^vDP*X"))
    for name, shape in shapes.items():
        pts = [s for s in om["samples"] if s["dataset"] == name]
        axes[0].plot([s["points"] for s in pts], [s["seconds"] for s in pts], shape + "-", lw=0.6, label=name)
    axes[0].plot(xs, f["a"] * xs + f["b"], "k-", label=f"Eq. 17 pooled: a={f['a']:.3e}, b={f['b']:.3e}, R²={f['r_squared']:.3f}")
    axes[0].set_title("(a) OctoMap", fontsize=10)
    kn = rt["knn"]
    f = kn["fit"]
    ks = sorted({s["k"] for s in kn["samples"]})
    for k in ks:
        pts = [s for s in kn["samples"] if s["k"] == k]
        line, = axes[1].plot([], [], "o", label=f"k = {k:g}")
        for s in pts:
            axes[1].plot(s["points"], s["seconds"], shapes.get(s["dataset"], "o"), color=line.get_color(), ms=5)
        axes[1].plot(xs, (f["a"] * k + f["b"]) * xs + f["c"], "-", color=line.get_color())
    axes[1].set_title(f"(b) k-NN (markers: the data sets of (a))\nEq. 18 pooled: a={f['a']:.3e}, b={f['b']:.3e}, c={f['c']:.3e}, R²={f['r_squared']:.3f}",
                      fontsize=10)
    for ax in axes:
        ax.set_xlabel("points processed N")
        ax.set_ylabel("build time, 1 thread (s)")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle("Fig. 7: run time", fontsize=10)
    save(fig, out, "fig7_runtime.png")


FIGURES = {"fits": fig3, "nca": fig4, "comparison": fig5, "curves": fig6, "runtime": fig7}
# Steps whose results are a report.md section only (docs/reproduction.md): accepted, nothing drawn.
TABLE_ONLY = {"real-stereo"}


def main():
    global INTO
    args = sys.argv[2:]
    if len(args) >= 2 and args[0] == "--into":
        INTO, args = args[1], args[2:]
    if len(sys.argv) < 2 or any(step not in FIGURES and step not in TABLE_ONLY for step in args):
        sys.exit(__doc__)
    out = sys.argv[1]
    for step in args or FIGURES:
        if step in FIGURES:
            FIGURES[step](out)


if __name__ == "__main__":
    main()
