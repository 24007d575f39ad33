#!/usr/bin/env bash
# Four more rounds of commands.sh for the two thread variants whose first three rounds differed
# most (binaries $1 and $2, output under $3, labels $4 and $5; rounds 4–7 (ROUNDS), the order of the
# binaries swapped in the odd rounds). Rounds 8–11: ROUNDS="8 9 10 11" VARIANTS=tracking.thread.cached.f32.
A=$1; B=$2; O=$3; LA=$4; LB=$5
V=${VARIANTS:-tracking.thread.cached.f32,cells.thread.cached.f32}
for r in ${ROUNDS:-4 5 6 7}; do
  if [ $((r % 2)) = 1 ]; then first=$B; lf=$LB; second=$A; ls=$LA; else first=$A; lf=$LA; second=$B; ls=$LB; fi
  XDG_RUNTIME_DIR=/tmp $first study --experiments e4 --sizes 100 --variants $V --cpu-max-n 1 --out $O/$lf-r$r > $O/$lf-r$r.log 2>&1
  XDG_RUNTIME_DIR=/tmp $second study --experiments e4 --sizes 100 --variants $V --cpu-max-n 1 --out $O/$ls-r$r > $O/$ls-r$r.log 2>&1
done
echo finished > $O/done-more
