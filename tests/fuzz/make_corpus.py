#!/usr/bin/env python3
"""Writes the fuzz seed corpus (tests/fuzz/corpus/NAME/): small valid files of every format, so that libFuzzer
starts from inputs that reach deep into each reader. Standard library only. Run from anywhere; rewrites the corpus."""
import json, math, os, shutil, struct, zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
OUT = os.path.join(HERE, "corpus")


def put(target, name, data):
    d = os.path.join(OUT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def png(w, h, depth, pixels, interlace=0):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    fmt = ">H" if depth == 16 else ">B"
    passes = [(0, 0, 1, 1)] if not interlace else [  # Adam7: x0, y0, dx, dy of each pass
        (0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]
    raw = b""
    for x0, y0, dx, dy in passes:
        for y in range(y0, h, dy):
            row = [pixels[y * w + x] for x in range(x0, w, dx)]
            if row:
                raw += b"\0" + b"".join(struct.pack(fmt, v) for v in row)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, 0, 0, 0, interlace)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def graph(nodes, edges):
    s = struct.pack("<I", len(nodes))
    for i, (pts, t, q) in enumerate(nodes):
        s += struct.pack("<I", len(pts))
        for p in pts:
            s += struct.pack("<i3d", 3, *p)
        s += struct.pack("<i3d", 3, *t) + struct.pack("<i4d", 4, *q) + struct.pack("<I", i)
    s += struct.pack("<I", len(edges))
    for a, b in edges:
        s += struct.pack("<II", a, b) + struct.pack("<i3d", 3, 1, 0, 0) + struct.pack("<i4d", 4, 1, 0, 0, 0)
        s += struct.pack("<d", 1.0)
    return s


def ply(enc, verts, faces):
    h = f"ply\nformat {enc} 1.0\ncomment seed\nelement vertex {len(verts)}\nproperty float x\nproperty float y\n"
    h += f"property float z\nproperty uchar red\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    if enc == "ascii":
        body = "".join(f"{x} {y} {z} 200\n" for x, y, z in verts) + "".join(
            f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in faces)
        return (h + body).encode()
    e = "<" if enc == "binary_little_endian" else ">"
    body = b"".join(struct.pack(e + "fffB", x, y, z, 200) for x, y, z in verts)
    body += b"".join(struct.pack(e + "B" + "i" * len(f), len(f), *f) for f in faces)
    return h.encode() + body


def pcd(data, pts):
    h = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\n"
         f"WIDTH {len(pts)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(pts)}\nDATA {data}\n")
    if data == "ascii":
        return (h + "".join(f"{x} {y} {z} 7\n" for x, y, z in pts)).encode()
    return h.encode() + b"".join(struct.pack("<fffI", x, y, z, 7) for x, y, z in pts)


def ot(nodes):
    """An OctoMap .ot file: liboctomap's header, then (log-odds float, child bits byte) per node in pre-order."""
    h = (f"# Octomap OcTree file\n# (feel free to add / change comments, but leave the first line as it is!)\n#\n"
         f"id OcTree\nsize {len(nodes)}\nres 0.1\ndata\n")
    return h.encode() + b"".join(struct.pack("<fB", v, c) for v, c in nodes)


def ot_chain(depth=0):
    """One leaf at the finest depth (16) under a chain of inner nodes, and a pruned leaf beside it at depth 15."""
    if depth == 16:
        return [(0.85, 0)]
    if depth == 14:
        return [(0.85, 0b11)] + ot_chain(15) + [(-0.4, 0)]
    return [(0.85, 0b1)] + ot_chain(depth + 1)


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    px = [(i * 977) % 65536 for i in range(6 * 4)]
    put("png", "gray16.png", png(6, 4, 16, px))
    put("png", "gray8.png", png(5, 3, 8, [i * 13 % 256 for i in range(15)]))
    put("png", "gray16_adam7.png", png(9, 9, 16, [(i * 31) % 65536 for i in range(81)], interlace=1))
    put("pgm", "p5_16.pgm", b"P5\n# kinect\n4 3\n65535\n" + b"".join(struct.pack(">H", v) for v in px[:12]))
    put("pgm", "p5_8.pgm", b"P5 3 2 255\n" + bytes(range(10, 16)))
    put("pgm", "p2.pgm", "P2\n3 2\n65535\n0 1000 2000\n3000 0 65535\n")
    put("pose", "quaternion.txt", "\0# tx ty tz qx qy qz qw\n0.1 0.2 -2.2 -0.001 0.0005 -0.0002 0.999999\n"
                                 "-0.228993 0.00645704 0.0287837 -0.0004327 -0.113131 -0.0326832 0.993042\n")
    put("pose", "matrix.txt", "\x011 0 0 0.5\n0 1 0 0\n0 0 1 2\n0 0 0 1\n0 -1 0 0 1 0 0 0 0 0 1 0 0 0 0 1\n")
    put("pose", "tum.txt", "\x02# timestamp tx ty tz qx qy qz qw\n1305031102.175304 1 2 3 0 0 0.7071068 0.7071068\n"
                          "1305031102.211214 -1 0 0.5 0 0 0 1\n")
    put("pose", "kitti.txt", "\x031 0 0 4 0 0 -1 5 0 1 0 6\n1 0 0 0 0 1 0 0 0 0 1 0\n")
    put("intrinsics", "camera-intrinsics.txt", "5.703422241210937500e+02\t0.000000000000000000e+00\t3.2e+02\n"
                                               "0.0e+00\t5.703422241210937500e+02\t2.4e+02\n0 0 1\n")
    put("intrinsics", "cam_params.json", json.dumps({"camera": {"w": 1200, "h": 680, "fx": 600.0, "fy": 600.0,
                                                                "cx": 599.5, "cy": 339.5, "scale": 6553.5}}))
    r = 1 / math.sqrt(2)
    pts = [(1.0 + i, 0.5 * i, -0.25) for i in range(4)]
    put("graph", "two_nodes.graph", graph([(pts, (0, 0, 0), (1, 0, 0, 0)), (pts[:2], (1, 2, 3), (r, 0, 0, r))], [(0, 1)]))
    put("graph", "one_node.graph", graph([(pts, (0.5, 0, 0), (1, 0, 0, 0))], []))
    verts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0.5)]
    for enc in ("ascii", "binary_little_endian", "binary_big_endian"):
        put("ply", enc + ".ply", ply(enc, verts, [[0, 1, 2], [0, 2, 3, 1]]))
    put("pcd", "ascii.pcd", pcd("ascii", verts))
    put("pcd", "binary.pcd", pcd("binary", verts))
    put("pcd", "organised_nan.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 4\nDATA ascii\n"
                                    "1 2 3\nnan nan nan\n4 5 6\n7 8 9\n")
    put("xyz", "scan.xyz", "# x y z\n-0.0434742 -4.82982 0.499645\n0.0295245 -4.82834 0.541775\n1e-3 +2 3 17\n")
    put("truth_json", "list.json", json.dumps([{"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}]))
    put("truth_json", "object.json", json.dumps({"boxes": [{"min": [-1, -1, 0], "max": [1, 1, 2]}]}))
    put("ot", "chain.ot", ot(ot_chain()))
    put("ot", "root_leaf_pruned.ot", ot([(0.0, 0b10000001), (1.2, 0), (-2.0, 0)]))
    os.makedirs(os.path.join(OUT, "grid_json"))
    for g in sorted(os.listdir(os.path.join(ROOT, "sweeps", "grids"))):
        shutil.copy(os.path.join(ROOT, "sweeps", "grids", g), os.path.join(OUT, "grid_json", g))
    res = json.load(open(os.path.join(ROOT, "results", "builtin", "octomap-opt.json")))
    put("results_json", "octomap-opt-full.json", json.dumps(res))
    res["maps"] = res["maps"][:2]  # a small complete-looking file: short inputs fuzz faster
    put("results_json", "octomap-opt-2maps.json", json.dumps(res))
    # What `results check` verifies (docs/results-format.md): a valid incomplete file and one edit per claim.
    put("results_json", "octomap-opt-2maps-incomplete.json", json.dumps(dict(res, complete=False)))
    put("results_json", "duplicated-map.json", json.dumps(dict(res, maps=[res["maps"][0], res["maps"][0]])))
    put("results_json", "no-maps.json", json.dumps(dict(res, maps=[])))
    put("results_json", "negative-resolution.json", json.dumps(dict(res, map=dict(res["map"], resolution=-0.1))))
    put("results_json", "group.json", json.dumps(dict(res, complete=False, selection={
        "shard": {"index": 0, "count": 1}, "group": {"index": 0, "count": 18446744073709551615, "seed": 0}})))
    knn = json.load(open(os.path.join(ROOT, "results", "builtin", "knn-opt.json")))
    knn["maps"] = knn["maps"][:2]
    knn["complete"] = False
    put("results_json", "knn-opt-2maps-incomplete.json", json.dumps(knn))
    knn["maps"][0]["params"]["k"] = 2**32 + 1
    put("results_json", "knn-k-wraps.json", json.dumps(knn))


if __name__ == "__main__":
    main()
