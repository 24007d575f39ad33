#!/usr/bin/env bash
# One command for a GPU loan: builds sphlab and runs `sphlab study --preset gpu`, which refuses a
# CPU adapter (lavapipe) with exit 2, prints adapter, driver, limits and its plan, and within the
# budget (default 8 min) writes variants, verify (two scenes), E1–E4, scaling to the largest N that
# fits and the full-resolution impact validation under reports/gpu/<adapter>/.
# Extra arguments go to sphlab, e.g.: scripts/gpu-report.sh --dry-run | --budget 5m | --allow-cpu-adapter
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --bin sphlab
exec target/release/sphlab study --preset gpu "$@"
