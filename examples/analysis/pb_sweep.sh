#!/usr/bin/env bash
# Background-pressure sweep: the oscillating-drop scene at nx = 24
# (Δx = 1/48, σ/Δx = 48) for each kernel against p_b, two runs per point:
#   rest: initial velocity and relaxation removed, t = 0.3 (spurious speed, Laplace jump, voids);
#   osc:  relax 0.1, then the T84 field on every fluid particle, t = 0.6 (period, amplitude).
# Analysis: examples/analysis/pb_sweep.py → reports/validation/pb-sweep/. Usage: examples/analysis/pb_sweep.sh OUTDIR (the committed runs: reports/validation/pb-sweep/runs)
# BACKGROUND=transport: the same runs with the transport-velocity formulation
# (time.background = "transport", directories transport-KIND-pbPB) at p_b 48, B = 175 and
# ρ0c0² = 1225 (Adami, Hu & Adams 2013 / PySPH's TVF scheme take p_b = ρ0c0²).
set -euo pipefail
out=${1:-out/pb-sweep}
bin=${SPHLAB:-target/release/sphlab}
mkdir -p "$out"
pbs="24 175 48 12 0" prefix="" bg=()
# KERNELS (kind:h_ratio, space-separated) and PBS narrow the sweep, e.g. KERNELS="johnson:1.2
# gaussian:1.0" PBS="24 48 175" for the thesis's other two kernels.
kernels=${KERNELS:-"quintic:1.0 cubic-spline:1.2 wendland-c2:1.3"}
if [ "${BACKGROUND:-momentum}" = transport ]; then
  pbs="1225 175 48" prefix="transport-" bg=(--set 'time.background="transport"')
fi
pbs=${PBS:-$pbs}
# p_b outer, most informative first (the rule's 24, the former B = 175, then 48, 12, 0), so a
# sweep cut short still compares the kernels at the same p_b.
for pb in $pbs; do
  for k in $kernels; do
    kind=${k%%:*} hr=${k##*:}
    common=(--backend cpu1 --quiet --set kernel.kind=$kind --set kernel.h_ratio=$hr --set domain.nx=24
            --set phases.0.p_b=$pb --set phases.1.p_b=$pb "${bg[@]}")
    d="$out/$prefix$kind-pb$pb"
    [ -f "$d-rest/summary.json" ] || "$bin" run oscillating-drop "${common[@]}" --set relax.t=0 \
        --set initial_velocity.v0=0 --t-end 0.3 --every 0 --out "$d-rest" > "$d-rest.log" 2>&1 || true
    [ -f "$d-osc/summary.json" ] || "$bin" run oscillating-drop "${common[@]}" --set relax.t=0.1 \
        --t-end 0.6 --every 0 --out "$d-osc" > "$d-osc.log" 2>&1 || true
  done
done
