#!/usr/bin/env bash
# One command for a GPU loan, run on the lent machine: never builds. It takes the sphlab binary
# from $SPHLAB_BIN, else .gpu-bin/sphlab (made by scripts/gpu-bundle.sh), else
# target/release/sphlab; unpacks the Vulkan/EGL loader packages in .gl/ when no libvulkan is
# installed; points Vulkan at the NVIDIA ICD where it exists; forces wgpu onto Vulkan; gives the
# process a private XDG_RUNTIME_DIR; prints the GPUs nvidia-smi sees; then runs
# `sphlab study --preset gpu` (which prints the adapter wgpu opened and its plan first). With
# nvidia-smi and --archive DIR it also writes DIR/nvidia-smi-q.txt and DIR/gpu-clocks.csv.
#
# Options (passed on): --budget T (default 8m), --archive DIR (DIR/gpu-report.tar.gz and
# DIR/summary.md, rewritten after every part), --allow-cpu-adapter, --dry-run, --out ROOT.
#   e.g. scripts/gpu-report.sh --budget 8m --archive "$OUT"
set -euo pipefail
cd "$(dirname "$0")/.."

bin="${SPHLAB_BIN:-}"
if [ -z "$bin" ]; then
    for b in .gpu-bin/sphlab target/release/sphlab; do
        if [ -x "$b" ]; then bin="$b"; break; fi
    done
fi
if [ -z "$bin" ] || [ ! -x "$bin" ]; then
    echo "gpu-report: no sphlab binary: set SPHLAB_BIN, or run scripts/gpu-bundle.sh on a machine with cargo" >&2
    exit 2
fi

if ! ldconfig -p 2>/dev/null | grep -q libvulkan; then
    if ls .gl/*.deb >/dev/null 2>&1; then
        echo "gpu-report: no libvulkan installed; unpacking the loader packages in .gl/" >&2
        for f in .gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    else
        echo "gpu-report: warning: no libvulkan and no .gl/*.deb (scripts/gpu-bundle.sh downloads them)" >&2
    fi
fi

for icd in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json \
           /etc/vulkan/icd.d/nvidia_icd.json; do
    if [ -f "$icd" ]; then
        export VK_DRIVER_FILES="$icd" VK_ICD_FILENAMES="$icd"
        break
    fi
done
export WGPU_BACKEND=vulkan
XDG_RUNTIME_DIR="$(mktemp -d)"
export XDG_RUNTIME_DIR

echo "gpu-report: $bin ($("$bin" --version 2>/dev/null || echo '?')); VK_DRIVER_FILES=${VK_DRIVER_FILES:-unset}" >&2
if ! command -v nvidia-smi >/dev/null 2>&1; then
    exec "$bin" study --preset gpu "$@"
fi

# An NVIDIA GPU: name it, and beside the archive (--archive DIR) keep the driver's view of clocks
# and power before the run (nvidia-smi-q.txt) and sampled every 250 ms during it
# (gpu-clocks.csv), so a time per step can be read against the clocks it ran at.
nvidia-smi -L || true
archive=""
prev=""
for a in "$@"; do
    if [ "$prev" = "--archive" ]; then archive="$a"; fi
    prev="$a"
done
sampler=""
if [ -n "$archive" ]; then
    mkdir -p "$archive"
    nvidia-smi -q -d CLOCK,PERFORMANCE,POWER >"$archive/nvidia-smi-q.txt" 2>&1 || true
    nvidia-smi --query-gpu=timestamp,pstate,clocks.sm,clocks.max.sm,clocks.mem,utilization.gpu,power.draw,temperature.gpu \
        --format=csv -lms 250 >"$archive/gpu-clocks.csv" 2>/dev/null &
    sampler=$!
fi
"$bin" study --preset gpu "$@" &
study=$!
# SIGINT/SIGTERM go to the study, which finishes its summary and archive (exit 130/143).
trap 'kill -TERM "$study" 2>/dev/null' TERM
trap 'kill -INT "$study" 2>/dev/null' INT
rc=0
wait "$study" || rc=$?
# A trapped signal ends the first wait early; wait again for the study's own exit status.
if kill -0 "$study" 2>/dev/null; then
    rc=0
    wait "$study" || rc=$?
fi
if [ -n "$sampler" ]; then kill "$sampler" 2>/dev/null || true; fi
exit "$rc"
