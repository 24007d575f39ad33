#!/usr/bin/env bash
# The same binary ($1) in the full layout: the 72 ids and the 12 cached tracking `.masks` on the
# four scenes, 20 steps (the command of list-chunks/verify/commands.sh), written under $2, for
# the bit-for-bit comparison with the records of ee99641.
B=$1; O=$2
export XDG_RUNTIME_DIR=/tmp
IDS=$($B variants 2>/dev/null | awk '{print $1}' | grep -E '\.(recomputed|cached)\.f(32|64)$')
TRC=$(echo "$IDS" | grep '^tracking' | grep cached | sed 's/$/.masks/' | paste -sd,)
ALL=$(echo "$IDS" | paste -sd,)
mkdir -p $O/full
for s in "oscillating-drop domain.nx=24" "sessile-90 domain.nx=21 contact.mode=a" "sessile-90 domain.nx=21 contact.mode=b" "impact domain.nx=24"; do
  set -- $s; scene=$1; shift; sets=""; name=$scene
  for kv in "$@"; do sets="$sets --set $kv"; name="$name-${kv#*=}"; done
  $B verify $scene $sets --variants $ALL,$TRC --steps 20 --out $O/full/$name > $O/full/$name.log 2>&1 || true
done
echo done > $O/full-done
