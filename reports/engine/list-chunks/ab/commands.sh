#!/usr/bin/env bash
# Paired A/B: the engine before the list chunks (596b2a4) against after (ee99641), alternating, 4 rounds.
V=cells.thread.cached.f32,tracking.thread.cached.f32,cells.block-tree.fixed.cached.f32,cells.subgroup.cached.f32,cells.thread.recomputed.f32,cells.subgroup.recomputed.f32
mkdir -p /tmp/lc/ab
for r in 1 2 3 4; do
  for b in 596b2a4 ee99641; do
    XDG_RUNTIME_DIR=/tmp /work/bin/sphlab-$b study --experiments e4 --sizes 100 --variants $V --cpu-max-n 1 --out /tmp/lc/ab/$b-r$r > /tmp/lc/ab/$b-r$r.log 2>&1
  done
done
echo finished > /tmp/lc/ab/done
