#!/usr/bin/env python3
"""Reference implementation of occsweep's Eq. 16 split, written from docs/grids.md alone.

Usage: shard_reference.py N SEED GROUPS  -> the same JSON lines as `occsweep grid shards GRID --groups GROUPS --seed SEED`
for a grid of N combinations.
"""
import json
import sys

MASK = (1 << 64) - 1


class SplitMix64:
    def __init__(self, seed):
        self.state = seed & MASK

    def next(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        return z ^ (z >> 31)

    def below(self, bound):
        limit = MASK - (MASK % bound)  # reject r >= limit, where MASK = 2^64 - 1
        while True:
            r = self.next()
            if r < limit:
                return r % bound


def permutation(n, seed):
    p = list(range(n))
    rng = SplitMix64(seed)
    for i in range(n, 1, -1):  # Fisher-Yates from the last element down
        j = rng.below(i)
        p[i - 1], p[j] = p[j], p[i - 1]
    return p


def main():
    n, seed, groups = (int(a) for a in sys.argv[1:4])
    p = permutation(n, seed)
    base, extra = divmod(n, groups)
    begin = 0
    for g in range(groups):
        size = base + (1 if g < extra else 0)
        ids = p[begin:begin + size]
        begin += size
        print(json.dumps({"group": g, "count": len(ids), "ids": ids}, separators=(",", ":"), sort_keys=True))


if __name__ == "__main__":
    main()
