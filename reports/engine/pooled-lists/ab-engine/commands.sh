#!/usr/bin/env bash
# Paired A/B of the engine before this change (binary $1, the list chunks) and after it (binary
# $2, the pooled layout available, the full one chosen at this size), alternating, 3 rounds of
# E4 at the sizes of --sizes 100; output under $3 ($3/<label>-r<k>, label the binaries' 4th arg).
A=$1; B=$2; O=$3; LA=$4; LB=$5
V=cells.thread.cached.f32,cells.thread.cached.f64,cells.subgroup.cached.f32,cells.block-tree.fixed.cached.f32,tracking.thread.cached.f32,cells.subgroup.recomputed.f32
mkdir -p $O
for r in 1 2 3; do
  XDG_RUNTIME_DIR=/tmp $A study --experiments e4 --sizes 100 --variants $V --cpu-max-n 1 --out $O/$LA-r$r > $O/$LA-r$r.log 2>&1
  XDG_RUNTIME_DIR=/tmp $B study --experiments e4 --sizes 100 --variants $V --cpu-max-n 1 --out $O/$LB-r$r > $O/$LB-r$r.log 2>&1
done
echo finished > $O/done
