#!/usr/bin/env bash
# relax-60 started from another angle: is a mode's end angle an equilibrium or a
# pinned contact line? The 90° half-disc of radius R0 = 0.25 is replaced by the cap of equal
# area that meets the wall at THETA0 (circle of radius R centred at (0, −R cos θ0), with
# R² (θ0 − sin θ0 cos θ0)/2 = π R0²/4); everything else is relax-60's: θ_d = 60°, no-slip,
# dt scaled with the stability limits, and the scene's p_b and c0 from the capillary rule
# (docs/PHYSICS.md §3.1, re-applied at every nx). A contact line that
# ends at the same angle from above and below 60° is at its model's equilibrium; one that stops
# short from both sides is pinned. Usage:
#   examples/analysis/relax_start_angle.sh NX MODE THETA0 OUT [--set KEY=VALUE ...]
# e.g. examples/analysis/relax_start_angle.sh 65 a 45 out/a-from45. One thread, to t = 5 (T_END=… for
# another end), a snapshot every 5000 steps, a series row every 500; `/usr/bin/time -v` in
# OUT/time-v.txt, the run's output in OUT/log.txt. Analysis: examples/analysis/relax_window.py NX 4.3 4.5
# OUT…
set -euo pipefail
nx=$1 mode=$2 theta0=$3 out=$4
shift 4
bin=${SPHLAB:-target/release/sphlab}
t_end=${T_END:-5}
# The start's overrides come from the binary (`sphlab scene relax-start`, the same
# relax::start_sets as validate's relax-60 variants); none at 90°: the scene's own half-disc.
sets=$("$bin" scene relax-start "$theta0")
shape=()
while read -r kv; do if [ -n "$kv" ]; then shape+=(--set "$kv"); fi; done <<< "$sets"
mkdir -p "$out"
/usr/bin/time -v -o "$out/time-v.txt" "$bin" run relax-60 --threads 1 --set domain.nx="$nx" \
  --set time.dt_policy=scale --set output.every=500 --set contact.mode="$mode" \
  "${shape[@]}" "$@" --t-end "$t_end" --every 5000 --out "$out" > "$out/log.txt" 2>&1
