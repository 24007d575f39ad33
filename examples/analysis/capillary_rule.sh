#!/usr/bin/env bash
# The capillary rule's checks (reports/validation/capillary-rule/README.md): the oscillating drop
# and the drop at rest with every kernel at nx 30 and 45 under the rule (p_b and c0 follow the
# kernel and resolution set here), and both at α × 0.5 and × 2 (nx = 30). Two runs at a time.
# Usage: examples/analysis/capillary_rule.sh OUTDIR [STREAM [--set KEY=VALUE ...]]
#   STREAM 0 or 1: half of the points ("" for all); the --set pairs go to every run (e.g.
#   --set time.background=transport). ALPHA_POINTS=0 leaves out the α sensitivity points;
#   KERNELS="kind:h_ratio ..." replaces the kernels and their h (default: the scenes' own).
set -euo pipefail
out=${1:-out/capillary-rule}
stream=${2:-}
shift $(( $# < 2 ? $# : 2 ))
extra=("$@")
bin=${SPHLAB:-target/release/sphlab}
mkdir -p "$out"
# The α sensitivity first, then nx = 45 (the costly points), then nx = 30.
kernels=${KERNELS:-quintic:1.2 wendland-c2:1.5 gaussian:1.2 cubic-spline:1.2 johnson:2.0}
points=()
if [ "${ALPHA_POINTS:-1}" != 0 ]; then
  for k in $kernels; do
    for a in 1.0 4.0; do points+=("osc 30 $k $a" "rest 30 $k $a"); done
  done
fi
for nx in 45 30; do
  for k in $kernels; do
    points+=("osc $nx $k 2.0" "rest $nx $k 2.0")
  done
done
i=0
for p in "${points[@]}"; do
  i=$((i + 1))
  if [ -n "$stream" ] && [ $((i % 2)) != "$stream" ]; then continue; fi
  set -- $p
  tag=$1 nx=$2 kind=${3%%:*} hr=${3##*:} alpha=$4
  d="$out/$tag-nx$nx-$kind-a$alpha"
  [ -f "$d/summary.json" ] && continue
  common=(--backend cpu1 --quiet --set kernel.kind=$kind --set kernel.h_ratio=$hr --set domain.nx=$nx
          --set capillary_rule.alpha=$alpha --set time.dt_policy=scale --every 0 --out "$d" ${extra[@]+"${extra[@]}"})
  if [ "$tag" = rest ]; then
    "$bin" run oscillating-drop "${common[@]}" --set relax.t=0 --set initial_velocity.v0=0 --t-end 1.0 > "$d.log" 2>&1 || true
  else
    "$bin" run oscillating-drop "${common[@]}" > "$d.log" 2>&1 || true
  fi
done
