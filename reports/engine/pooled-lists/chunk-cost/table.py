#!/usr/bin/env python3
"""The chunk-cost table of commands.sh: ms/step (summary.json, the stepping's wall time per step)
per variant and cap, median of the rounds with their range, the list chunks the plan gives at
that cap, and the ratio to the one-chunk run of the same round (geometric mean, range)."""
import glob, json, math, os
here = os.path.dirname(os.path.abspath(__file__))
# Bytes per particle of the widest split array (`list_chunks::split_arrays`): the f32 cache
# 64 × 8 B; the pooled f64 cache 49 × 16 B. Chunks hold the largest multiple of 256 that fits.
WIDEST = {"cells.thread.cached.f32": 512, "cells.subgroup.cached.f32": 512,
          "cells.block-tree.fixed.cached.f32": 512, "cells.thread.cached.f64.pooled": 784}
CAP = {"none": None, "2M": 2 << 20, "256K": 256 << 10}
N = 11664

def chunks(v, cap):
    if cap is None or N * WIDEST[v] <= cap:
        return 1
    return math.ceil(N / (cap // WIDEST[v] // 256 * 256))

ms = {}
for f in glob.glob(os.path.join(here, "*-r*", "summary.json")):
    name = os.path.basename(os.path.dirname(f))
    v, c, r = name.rsplit("-", 2)
    d = json.load(open(f))
    if d["status"] == "ok":
        ms[(v, c, r)] = d["ms_per_step"]
print("| variant | cap | list chunks | ms/step (median of rounds, min–max) | ÷ one chunk, geometric mean (min–max of the rounds) |")
print("|---|---|---|---|---|")
for v in WIDEST:
    for c in CAP:
        xs = sorted(x for (a, b, _), x in ms.items() if a == v and b == c)
        if not xs:
            continue
        rs = [ms[(v, c, r)] / ms[(v, "none", r)] for (a, b, r) in ms if a == v and b == c and (v, "none", r) in ms]
        g = math.exp(sum(map(math.log, rs)) / len(rs))
        print(f"| {v} | {c} | {chunks(v, CAP[c])} | {xs[len(xs) // 2]:.1f} ({xs[0]:.1f}–{xs[-1]:.1f}) | {g:.2f}× ({min(rs):.2f}–{max(rs):.2f}) |")
