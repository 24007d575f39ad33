#!/usr/bin/env bash
# The drop at rest (oscillating-drop without initial velocity or relaxation, to t = 1, quintic
# h = 1.2Δx) under the capillary rule at nx 24, 30, 36, 45: the lattice start and jittered
# realisations (domain.jitter 0.05, seeds 1-3), for the Laplace jump, spurious speed and density
# error against R/Δx (reports/validation/capillary-rule/README.md). Finished points are skipped.
# Usage: examples/analysis/rest_convergence.sh OUTDIR
set -euo pipefail
out=${1:-out/rest-convergence}
bin=${SPHLAB:-target/release/sphlab}
mkdir -p "$out"
for nx in 24 30 36 45 60; do
  for seed in 0 1 2 3; do
    [ "$nx" = 60 ] && [ "$seed" = 3 ] && continue
    d="$out/rest-nx$nx-seed$seed"
    [ -f "$d/summary.json" ] && continue
    jitter=()
    [ "$seed" != 0 ] && jitter=(--set domain.jitter=0.05 --set domain.seed=$seed)
    "$bin" run oscillating-drop --backend cpu1 --quiet --set domain.nx=$nx --set time.dt_policy=scale \
      --set relax.t=0 --set initial_velocity.v0=0 --t-end 1.0 --every 0 "${jitter[@]}" --out "$d" > "$d.log" 2>&1 || true
  done
done
