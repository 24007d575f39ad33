#!/usr/bin/env bash
# One-time set-up of a fresh Debian machine for sphlab: a Vulkan driver for the GPU backend.
# Real GPUs bring their own driver; elsewhere Mesa's lavapipe (software Vulkan) is installed so
# the GPU variants run (slowly) on the CPU. Rust (cargo) must already be installed.
set -euo pipefail
if ! ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json >/dev/null 2>&1; then
    if command -v apt-get >/dev/null 2>&1; then
        SUDO=""
        [ "$(id -u)" -eq 0 ] || SUDO="sudo"
        $SUDO apt-get update -qq
        $SUDO apt-get install -y -qq mesa-vulkan-drivers libvulkan1
    else
        echo "setup: no Vulkan driver found and no apt-get; install a Vulkan driver (e.g. Mesa lavapipe)" >&2
    fi
fi
command -v cargo >/dev/null || { echo "setup: cargo not found; install Rust first" >&2; exit 1; }
