#!/usr/bin/env bash
# Speed against physical error: CPU runs, one thread, and GPU
# variants (`gpu`, GPU_ONLY=1 runs just those) of
#   drop:  the oscillating drop, relax 0.1, T84 field on every fluid particle, t = 0.6 (error of
#          the period against the thesis's 0.37), kernels × p_b × nx × precision;
#   relax: relax-60 Mode B no-slip to t = 5 at nx = 26 with dt = 1.4e-4 (error of the circle-fit
#          angle against 60° over t ∈ [4.3, 4.5]), kernels × p_b × precision.
# The nx = 24 f64 drop runs are the p_b sweep's (reports/validation/pb-sweep/runs, same set-up);
# the relax-60 runs at nx = 33 and 45 are reports/validation/relax-60's. Analysis:
# examples/analysis/speed_vs_physical_error.py. Usage: examples/analysis/speed_vs_physical_error.sh OUTDIR
set -uo pipefail
out=${1:-out/speed-vs-physical-error}
bin=${SPHLAB:-target/release/sphlab}
mkdir -p "$out"
drop() { # id nx kind h p_b precision
  local d="$out/drop-$1"
  local scale=() # above nx = 30 the scene's dt breaks the CFL limit: rescale it (time.dt_policy)
  [ "$2" -gt 30 ] && scale=(--set time.dt_policy=scale)
  [ -f "$d/summary.json" ] || "$bin" run oscillating-drop --threads 1 --quiet --precision "$6" "${scale[@]}" \
    --set domain.nx=$2 --set kernel.kind=$3 --set kernel.h_ratio=$4 --set phases.0.p_b=$5 --set phases.1.p_b=$5 \
    --set relax.t=0.1 --t-end 0.6 --every 0 --out "$d" > "$d.log" 2>&1
}
relax() { # id kind h p_b precision
  local d="$out/relax-$1"
  [ -f "$d/summary.json" ] || "$bin" run relax-60 --threads 1 --quiet --precision "$5" \
    --set domain.nx=26 --set time.dt=1.4e-4 --set output.every=100 --set kernel.kind=$2 --set kernel.h_ratio=$3 \
    --set phases.0.p_b=$4 --set phases.1.p_b=$4 --t-end 5 --every 0 --out "$d" > "$d.log" 2>&1
}
gpu() { # id nx variant: the default drop set-up (quintic, p_b = σ/(2Δx) = nx) on a GPU variant
  local d="$out/drop-$1"
  [ -f "$d/summary.json" ] || "$bin" run oscillating-drop --backend gpu --variant "$3" --quiet --steps-per-submit 64 \
    --set domain.nx=$2 --set time.dt_policy=scale --set kernel.kind=quintic --set kernel.h_ratio=1.0 --set phases.0.p_b=$2 --set phases.1.p_b=$2 \
    --set relax.t=0.1 --t-end 0.6 --every 0 --out "$d" > "$d.log" 2>&1
}
if [ "${GPU_ONLY:-0}" = 1 ]; then # the GPU rows alone (variants × precision × resolution)
  gpu q30-pb30-cells.thread.recomputed.f32 30 cells.thread.recomputed.f32
  gpu q24-pb24-cells.thread.recomputed.f32 24 cells.thread.recomputed.f32
  gpu q30-pb30-cells.thread.recomputed.f64 30 cells.thread.recomputed.f64
  gpu q30-pb30-cells.block-tree.fixed.recomputed.f32 30 cells.block-tree.fixed.recomputed.f32
  gpu q36-pb36-cells.thread.recomputed.f32 36 cells.thread.recomputed.f32
  gpu q30-pb30-tracking.subgroup.recomputed.f32 30 tracking.subgroup.recomputed.f32
  exit 0
fi
# most informative first, so a cut-short sweep still has every axis
for pb in 24 30 60; do
  drop q30-pb$pb-f64 30 quintic 1.0 $pb f64
  drop c30-pb$pb-f64 30 cubic-spline 1.2 $pb f64
  drop w30-pb$pb-f64 30 wendland-c2 1.5 $pb f64
done
relax c-pb26-f64 cubic-spline 1.2 26 f64
relax q-pb26-f64 quintic 1.0 26 f64
relax w-pb26-f64 wendland-c2 1.5 26 f64
for k in "q quintic 1.0" "c cubic-spline 1.2" "w wendland-c2 1.5"; do
  set -- $k
  drop ${1}30-pb24-f32 30 $2 $3 24 f32
done
for k in "q quintic 1.0" "c cubic-spline 1.2" "w wendland-c2 1.3"; do
  set -- $k
  drop ${1}24-pb24-f32 24 $2 $3 24 f32
done
relax c-pb26-f32 cubic-spline 1.2 26 f32
drop q36-pb29-f64 36 quintic 1.0 28.8 f64
drop q36-pb36-f64 36 quintic 1.0 36 f64
relax c-pb52-f64 cubic-spline 1.2 52 f64
relax q-pb52-f64 quintic 1.0 52 f64
relax w-pb52-f64 wendland-c2 1.5 52 f64
