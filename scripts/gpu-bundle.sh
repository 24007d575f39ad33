#!/usr/bin/env bash
# Run here, on a machine with cargo, before a GPU loan: builds the release binary into
# .gpu-bin/sphlab (glibc-linked: it must dlopen the NVIDIA driver, which a static musl build
# cannot), downloads the amd64 Vulkan/EGL loader packages into .gl/ (the lent machine has no
# package registry), keeps both out of git, and prints the one device call that runs the report.
set -euo pipefail
cd "$(dirname "$0")/.."

cargo build --release --bin sphlab
mkdir -p .gpu-bin
cp target/release/sphlab .gpu-bin/sphlab

mkdir -p .gl
if ! ls .gl/libvulkan1_*.deb >/dev/null 2>&1; then
    lists="$(mktemp -d)"
    mkdir -p "$lists/partial"
    o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 "-oDir::State::Lists=$lists")
    apt-get "${o[@]}" update -qq
    (cd .gl && apt-get "${o[@]}" download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
fi

# Both must stay out of git (.gitignore lists them; the device call carries them instead).
for p in .gpu-bin/sphlab .gl/libvulkan1.deb; do
    git check-ignore -q "$p" || { echo "bundle: $p is not ignored by git; add it to .gitignore" >&2; exit 1; }
done

echo "bundle: $(du -sh .gpu-bin | cut -f1) binary, $(ls .gl/*.deb | wc -l) loader packages ($(du -sh .gl | cut -f1))"
echo "bundle: $(.gpu-bin/sphlab --version)"
cat <<CALL
The device call (one run: a 7-minute budget ends within 7.4 min; with the machine's start that
leaves room in a 15-minute loan for a shorter rerun):
  carry:     [".gl", ".gpu-bin"]
  timeout_s: 480
  command:   bash scripts/gpu-report.sh --budget 7m --archive "\$OUT"
The report comes back as gpu-report.tar.gz and summary.md; unpack it with
  tar -xzf gpu-report.tar.gz -C reports/gpu/
and merge it beside lavapipe's study with
  sphlab report reports/study reports/gpu/<adapter>/study --out reports/merged
CALL
