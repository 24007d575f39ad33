#!/usr/bin/env bash
# Paired A/B in one binary ($1): the full slot layout against the pooled one, variant by variant,
# E4 at the study's sizes for --sizes 100; 3 rounds, the order of each pair reversed in round 2.
# Output under $2.
B=$1; O=$2
P="cells.thread.cached.f32 cells.thread.cached.f64 cells.block-tree.fixed.cached.f32 cells.subgroup.cached.f32 tracking.thread.cached.f32"
mkdir -p $O
for r in 1 2 3; do
  V=""
  for v in $P; do
    if [ $r = 2 ]; then V="$V,$v.pooled,$v.full"; else V="$V,$v.full,$v.pooled"; fi
  done
  XDG_RUNTIME_DIR=/tmp $B study --experiments e4 --sizes 100 --variants ${V#,} --cpu-max-n 1 --out $O/r$r > $O/r$r.log 2>&1
done
echo finished > $O/done
