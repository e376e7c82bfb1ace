#!/usr/bin/env bash
# The device check that fits a loan (issue 45, docs/gpu.md): on any machine with nvcc,
#   scripts/device_check.sh --bundle DIR
# builds the CUDA build (build-device/: VPPDEM_CUDA, rpath $ORIGIN) and puts into DIR everything
# the check needs, found relative to DIR: the binaries (vppdem, vppdem_cuda_tests with
# libvppdem_cuda_ref.so, vppdem_device_tests), the shared libraries they need that are not the C
# runtime's or CUDA's (ldd decides: libhwy, libtomlplusplus, ...), the inputs (the tests' small
# damper after its cycle, seeds 1 and 2; the device sweep's study; a run.ckpt of the paper's
# damper at 0.01 m/s, made by a short run unless STATE names one, and one at 0.05 m/s), bench/gpu.sh
# and run.sh. On the GPU
# machine, DIR/run.sh runs the device tests, compute-sanitizer (memcheck, racecheck, synccheck) on them and
# bench/gpu.sh, writing DIR/device_check.log; DIR/run.sh --host-only runs what needs no GPU.
# env: NVCC (nvcc on PATH, else /usr/local/cuda/bin/nvcc), BUILD (build-device), STATE (a run.ckpt
#      of the paper's damper to carry instead of making one), JOBS (nproc)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
[ "${1:-}" = "--bundle" ] && [ -n "${2:-}" ] || { echo "usage: scripts/device_check.sh --bundle DIR" >&2; exit 2; }
out=$2
NVCC=${NVCC:-$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)}
[ -x "$NVCC" ] || { echo "device_check: no nvcc ($NVCC): install CUDA or set NVCC" >&2; exit 2; }
BUILD=${BUILD:-build-device}
JOBS=${JOBS:-$(nproc)}

echo "== building $BUILD (VPPDEM_CUDA, $NVCC)"
cfg_log=$(mktemp)
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DVPPDEM_CUDA=ON -DVPPDEM_NVCC="$NVCC" \
      -DVPPDEM_BENCHMARKS=OFF -DVPPDEM_PYTHON=OFF '-DCMAKE_BUILD_RPATH=$ORIGIN' > "$cfg_log" 2>&1 \
  || { cat "$cfg_log"; exit 1; }
rm -f "$cfg_log"
cmake --build "$BUILD" -j "$JOBS" --target vppdem vppdem_cuda_tests vppdem_device_tests

mkdir -p "$out/inputs" "$out/bench"
out=$(cd "$out" && pwd)
bins=(vppdem vppdem_cuda_tests vppdem_device_tests)
for b in "${bins[@]}"; do install -m 755 "$BUILD/$b" "$out/$b"; done
install -m 644 "$BUILD/libvppdem_cuda_ref.so" "$out/libvppdem_cuda_ref.so"
install -m 755 bench/gpu.sh "$out/bench/gpu.sh"
install -m 755 scripts/device_check_run.sh "$out/run.sh"
install -m 644 tests/device/small_study.toml "$out/inputs/small_study.toml"

# The shared libraries a bare CUDA image lacks: everything ldd resolves but the C and C++
# runtimes, the loader, the CUDA driver and runtime, and our own.
echo "== shared libraries"
skip='^(linux-vdso|linux-gate|ld-linux|libc\.so|libm\.so|libmvec|libpthread|libdl\.so|librt\.so|libstdc\+\+|libgcc_s|libcuda\.so|libcudart|libnvidia|libvppdem_cuda_ref)'
for b in "${bins[@]}" libvppdem_cuda_ref.so; do
  ldd "$out/$b" | awk '/=>/ && $3 ~ /^\// {print $1, $3}'
done | sort -u | while read -r name path; do
  if [[ $name =~ $skip ]]; then continue; fi
  # A bundle made again in place: the binaries' rpath finds the copy already there.
  if [ -e "$out/$name" ] && [ "$path" -ef "$out/$name" ]; then echo "  $name (in the bundle)"; continue; fi
  echo "  $name <- $path"
  cp -L "$path" "$out/$name"
  chmod 644 "$out/$name"
done

echo "== inputs"
for seed in 1 2; do
  if [ ! -f "$out/inputs/s$seed/run.ckpt" ]; then
    "$out/vppdem" damper --out "$out/inputs/s$seed" --overwrite --no-plot --quiet \
      --set damper.radius=0.012 --set damper.height=0.03 --set grains.volume_fraction=0.45 \
      --set process.velocity=0.1 --set process.amplitude=0.002 --set process.cycles=1 \
      --set process.samples_per_cycle=20 --set simulation.threads=1 --set simulation.seed=$seed
    find "$out/inputs/s$seed" -mindepth 1 ! -name run.ckpt -delete
  fi
done
# The paper's damper, prepared and one short cycle run (as bench/batch_host.sh prepares it): its
# run.ckpt is the damper in its cycling state (about 3.5 minutes on 2 cores each). inputs/paper
# cycles at the studies' 0.01 m/s (an amplitude of 0.2 mm, so that the cycle has as many steps
# as the old one), inputs/paper_005 at 0.05 m/s and 1 mm, the state runs 1-4 timed (bench/gpu.sh's
# OLD_STATE).
make_state() {  # DIR VELOCITY AMPLITUDE
  [ -f "$out/inputs/$1/run.ckpt" ] && return
  mkdir -p "$out/inputs/$1"
  local tmp
  tmp=$(mktemp -d)
  "$out/vppdem" damper --out "$tmp/paper" --overwrite --no-plot --quiet \
    --set process.cycles=1 --set process.amplitude="$3" --set process.velocity="$2" --set simulation.threads="$JOBS"
  cp "$tmp/paper/run.ckpt" "$out/inputs/$1/run.ckpt"
  rm -rf "$tmp"
}
if [ -n "${STATE:-}" ]; then
  mkdir -p "$out/inputs/paper"
  cp "$STATE" "$out/inputs/paper/run.ckpt"
fi
make_state paper 0.01 0.0002
make_state paper_005 0.05 0.001
{
  echo "vppdem device check bundle"
  echo "made: $(date -u +%FT%TZ) on $(hostname) from $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '?')$(git -C "$root" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
  echo "nvcc: $("$NVCC" --version | tail -1)"
  (cd "$out" && find . -type f ! -name MANIFEST | sort | xargs sha256sum)
} > "$out/MANIFEST"
echo "== the bundle: $out ($(du -sh "$out" | cut -f1)); on the GPU machine: $out/run.sh (here: $out/run.sh --host-only)"
