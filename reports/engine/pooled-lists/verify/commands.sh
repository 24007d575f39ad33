#!/usr/bin/env bash
# Verification records of the pooled slot lists (binary: $1), written under $2: every cached
# variant forced `.pooled` (the tracking ones with candidate masks) on the four scenes, per
# stage and after 20 steps; then in list chunks at a 256 KiB binding.
B=$1; O=$2
export XDG_RUNTIME_DIR=/tmp
IDS=$($B variants 2>/dev/null | awk '{print $1}' | grep -E '\.cached\.f(32|64)$')
CACHED=$( (echo "$IDS" | grep -v '^tracking' | sed 's/$/.pooled/'; echo "$IDS" | grep '^tracking' | sed 's/$/.masks.pooled/') | paste -sd,)
mkdir -p $O/all $O/chunks
for s in "oscillating-drop domain.nx=24" "sessile-90 domain.nx=21 contact.mode=a" "sessile-90 domain.nx=21 contact.mode=b" "impact domain.nx=24"; do
  set -- $s; scene=$1; shift; sets=""; name=$scene
  for kv in "$@"; do sets="$sets --set $kv"; name="$name-${kv#*=}"; done
  $B verify $scene $sets --variants $CACHED --steps 20 --per-stage --out $O/all/$name > $O/all/$name.log 2>&1 || true
done
$B verify oscillating-drop --set domain.nx=24 --variants $CACHED --steps 20 --per-stage --gpu-binding 256K --out $O/chunks/oscillating-drop-24-256K > $O/chunks/oscillating-drop-24-256K.log 2>&1 || true
echo done > $O/done
