#!/usr/bin/env bash
# What list chunks cost: the oscillating drop at the E4 size (nx = 100, N = 11,664, no
# relaxation, as the study runs it), 200 steps of each variant under a per-buffer cap of the
# adapter's own (1 chunk), 2M and 256K (`run --gpu-binding`), the caps in a rotating order,
# 3 rounds (binary $1, output under $2; ms_per_step of each summary.json).
B=$1; O=$2
V="cells.thread.cached.f32 cells.subgroup.cached.f32 cells.block-tree.fixed.cached.f32 cells.thread.cached.f64.pooled"
mkdir -p $O
for r in 1 2 3; do
  case $r in 1) C="none 2M 256K";; 2) C="256K none 2M";; 3) C="2M 256K none";; esac
  for v in $V; do
    for c in $C; do
      cap=""; [ $c != none ] && cap="--gpu-binding $c"
      XDG_RUNTIME_DIR=/tmp $B run --backend gpu --variant $v --set domain.nx=100 --set relax.t=0 \
        --set time.dt_policy=scale --steps 200 $cap --quiet --out $O/$v-$c-r$r > $O/$v-$c-r$r.log 2>&1
      rm -f $O/$v-$c-r$r/particles_*
    done
  done
done
echo finished > $O/done
