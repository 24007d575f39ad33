#!/usr/bin/env bash
# The most neighbours one particle had in one evaluation (summary.json `peak_neighbours`,
# CPU f64, one thread) over whole runs of the built-ins, at or near their resolutions
# (binary: $1; output folder: $2). Snapshots are not kept (`output.every` past the end).
B=$1; O=$2
run() { name=$1; shift; $B run "$@" --backend cpu1 --set output.every=100000000 --out $O/$name > $O/$name.log 2>&1; }
mkdir -p $O
run oscillating-drop-30 oscillating-drop
run relax-60-33-b relax-60 --set domain.nx=33
run relax-60-33-a relax-60 --set domain.nx=33 --set contact.mode=a
run sessile-90-33-b sessile-90 --set domain.nx=33
run impact-50 impact --set domain.nx=50
run capillary-wave-44 capillary-wave
run capillary-wave-1000-44 capillary-wave-1000
run poiseuille-8 poiseuille
echo done > $O/done
