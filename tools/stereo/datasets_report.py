#!/usr/bin/python3
"""docs/datasets.md helper: the table over data sets and the cloud PNGs, from `occsweep dataset generate --all`.

Usage: tools/stereo/datasets_report.py OUT DOCS_IMG_DIR > table.md
OUT is the --out folder (OUT/summary.json, OUT/NAME/pcs-*/). For each environment-texture pair, the L layout's
median-ranked set is drawn: points within 3 m of the targets and above the ground layer (z > 0.1 m), blue inside a truly occupied voxel, red elsewhere.
"""
import json, os, shutil, sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

out, img = sys.argv[1], sys.argv[2]
summary = json.load(open(os.path.join(out, "summary.json")))
rows = summary["datasets"] if isinstance(summary, dict) else summary  # older occsweep wrote the list alone

def fmt(v, d=3):
    return "n/a" if v is None else f"{v:.{d}f}"

print("| data set | sets | points (median set) | valid on targets | off-surface within 4 m | naive TPR | naive FDR | FDR 1st / last |")
print("|---|---|---|---|---|---|---|---|")
for r in rows:
    m = r["median"]
    print(f"| {r['dataset']} | {r['sets']} | {m['points']:,} | {fmt(m['target_valid_fraction'])} | "
          f"{fmt(m['off_surface_fraction'])} | {fmt(m['naive']['tpr'])} | {fmt(m['naive']['fdr'])} | "
          f"{fmt(r['best']['naive']['fdr'])} / {fmt(r['worst']['naive']['fdr'])} |")

def mean(key, pred):
    vals = [key(r) for r in rows if pred(r["dataset"])]
    return sum(vals) / len(vals)
print()
print("| group | mean naive FDR (median set) | mean off-surface within 4 m | mean valid on targets |")
print("|---|---|---|---|")
for g in ["building-plain", "building-voronoi", "parking-plain", "parking-voronoi", "plain", "voronoi", "building", "parking"]:
    p = lambda n: g in n
    print(f"| {g} | {mean(lambda r: r['median']['naive']['fdr'], p):.3f} | "
          f"{mean(lambda r: r['median']['off_surface_fraction'], p):.3f} | {mean(lambda r: r['median']['target_valid_fraction'], p):.3f} |")

def occupied(c, boxes):
    occ = np.zeros(len(c), bool)
    for lo, hi in boxes:
        occ |= np.all((c - 0.05 < hi) & (c + 0.05 > lo), axis=1)
    return occ

for pair in ["building-plain", "building-voronoi", "parking-plain", "parking-voronoi"]:
    name = pair + "-L"
    r = next(x for x in rows if x["dataset"] == name)
    d = os.path.join(out, name, r["median"]["folder"])
    m = json.load(open(os.path.join(d, "manifest.json")))
    pts = np.concatenate([np.fromfile(os.path.join(d, s["file"]), dtype="<f4").reshape(-1, 3) for s in m["scans"]])
    boxes = [(np.array(b["min"]), np.array(b["max"])) for b in m["truth"]["boxes"]]
    centre = (boxes[0][0] + boxes[0][1]) / 2
    near = np.linalg.norm(pts[:, :2] - centre[:2], axis=1) < 3.0
    pts = pts[near & (pts[:, 2] > 0.1) & (pts[:, 2] < 2.0)]  # above the ground layer, as the region
    keys = (np.floor(pts / 0.1) + 0.5) * 0.1
    occ = occupied(keys, boxes)
    fig = plt.figure(figsize=(6, 4.5), dpi=100)
    ax = fig.add_subplot(projection="3d")
    ax.scatter(*pts[~occ].T, s=0.3, c="tab:red", alpha=0.25, label="not in a box voxel")
    ax.scatter(*pts[occ].T, s=0.5, c="tab:blue", alpha=0.6, label="in a box voxel")
    ax.set_xlim(centre[0] - 3, centre[0] + 3); ax.set_ylim(centre[1] - 3, centre[1] + 3); ax.set_zlim(0.0, 2.0)
    ax.view_init(elev=35, azim=-60)
    ax.set_title(f"{name} {r['median']['folder']} (median rank), points within 3 m above 0.1 m", fontsize=9)
    ax.legend(loc="upper left", fontsize=7, markerscale=10)
    fig.tight_layout()
    fig.savefig(os.path.join(img, f"dataset-{pair}-cloud.png"))
    plt.close(fig)
    shutil.copy(os.path.join(out, name, "preview", "left.png"), os.path.join(img, f"dataset-{pair}-left.png"))
    shutil.copy(os.path.join(out, name, "preview", f"disparity-{r['median']['folder']}.png"),
                os.path.join(img, f"dataset-{pair}-disparity.png"))
