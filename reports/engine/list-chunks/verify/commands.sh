#!/usr/bin/env bash
# Verification records of the list chunks (binary: $1), written under $2.
B=$1; O=$2
export XDG_RUNTIME_DIR=/tmp
IDS=$($B variants 2>/dev/null | awk '{print $1}' | grep -E '\.(recomputed|cached)\.f(32|64)$')
TRC=$(echo "$IDS" | grep '^tracking' | grep cached | sed 's/$/.masks/' | paste -sd,)
CACHED=$(echo "$IDS" | grep -v '^tracking' | grep cached | paste -sd,)
SLOTS=$(echo "$IDS" | grep -v '^tracking' | grep recomputed | grep -v '\.thread\.' | sed 's/$/.slots/' | paste -sd,)
ALL=$(echo "$IDS" | paste -sd,)
mkdir -p $O/all $O/chunks
for s in "oscillating-drop domain.nx=24" "sessile-90 domain.nx=21 contact.mode=a" "sessile-90 domain.nx=21 contact.mode=b" "impact domain.nx=24"; do
  set -- $s; scene=$1; shift; sets=""; name=$scene
  for kv in "$@"; do sets="$sets --set $kv"; name="$name-${kv#*=}"; done
  $B verify $scene $sets --variants $ALL,$TRC --steps 20 --out $O/all/$name > $O/all/$name.log 2>&1 || true
done
$B verify oscillating-drop --set domain.nx=24 --variants $CACHED,$TRC,$SLOTS --steps 20 --per-stage --gpu-binding 256K --out $O/chunks/oscillating-drop-24-256K > $O/chunks/oscillating-drop-24-256K.log 2>&1 || true
echo done > $O/done
# The slot lists split too (2026-12-05 03:0x UTC): the 20 non-tracking recomputed block/subgroup ids, .slots, at 128K.
# $B verify oscillating-drop --set domain.nx=24 --variants $SLOTS --steps 20 --per-stage --gpu-binding 128K --out chunks/oscillating-drop-24-128K-slots
