#!/usr/bin/env bash
# The oscillating drop (quintic h = 1.2Δx, relax 0.5, T84 field, t = 0.6) under the capillary
# rule at nx 24, 30, 36, 45, 60, 120: the lattice start and, at nx <= 36, jittered realisations
# (domain.jitter 0.05, seeds 1-3), for the period and damping against R/Δx
# (reports/validation/capillary-rule/README.md). nx 30 and 45 lattice runs are the rule's own
# (capillary-rule/runs/osc-nx{30,45}-quintic-a2.0); finished points are skipped, unfinished ones run again.
# Usage: examples/analysis/period_convergence.sh OUTDIR
set -euo pipefail
out=${1:-out/period-convergence}
bin=${SPHLAB:-target/release/sphlab}
mkdir -p "$out"
points=("24 0" "36 0" "24 1" "24 2" "24 3" "30 1" "30 2" "30 3" "36 1" "36 2" "36 3" "60 0" "120 0")
for p in "${points[@]}"; do
  set -- $p
  nx=$1 seed=$2
  d="$out/osc-nx$nx-seed$seed"
  # a finished point is skipped; one that stopped part-way (status "running") is run again
  grep -q '"status": "ok"' "$d/summary.json" 2>/dev/null && continue
  rm -rf "$d"
  jitter=()
  [ "$seed" != 0 ] && jitter=(--set domain.jitter=0.05 --set domain.seed=$seed)
  "$bin" run oscillating-drop --backend cpu1 --quiet --set domain.nx=$nx --set time.dt_policy=scale \
    --every 0 "${jitter[@]}" --out "$d" > "$d.log" 2>&1 || true
done
