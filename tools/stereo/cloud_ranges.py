#!/usr/bin/python3
"""Points of generated point cloud sets by range from their scan origin and inside the evaluation region.

Usage: cloud_ranges.py SET_DIR...   (SET_DIR = OUT/NAME/pcs-NNNN; docs/datasets.md, "Realism and experiment options")
Standard library only: the scans are little-endian float32 x y z triples (docs/dataset-format.md).
"""
import json
import math
import struct
import sys


def counts(set_dir):
    manifest = json.load(open(f"{set_dir}/manifest.json"))
    lo, hi = manifest["region"]["min"], manifest["region"]["max"]
    c = {"points": 0, "beyond_10m": 0, "beyond_14m": 0, "in_region": 0}
    for scan in manifest["scans"]:
        origin = scan["origin"]
        with open(f"{set_dir}/{scan['file']}", "rb") as f:
            for p in struct.iter_unpack("<3f", f.read()):
                r = math.dist(p, origin)
                c["points"] += 1
                c["beyond_10m"] += r > 10
                c["beyond_14m"] += r > 14
                c["in_region"] += all(lo[a] <= p[a] <= hi[a] for a in range(3))
    return c


if __name__ == "__main__":
    for d in sys.argv[1:]:
        print(d, counts(d))
