#!/usr/bin/env bash
# run.sh of a device check bundle (scripts/device_check.sh --bundle DIR; docs/gpu.md): on the GPU
# machine, from any folder, in under 8 minutes:
#   1. the binaries start (ldd: every library found, beside them or in the system);
#   2. the device tests: vppdem_cuda_tests (the laws' bits on the device), vppdem_device_tests
#      (the batch engine: a batch of one over 10,000 steps and 8 mixed cases give World's bits, so
#      do chunks of 1, 16 and 256 steps, a sweep with --backend cuda writes the files of --backend cpu);
#   3. bench/gpu.sh: the device against the CPU of this machine;
#   4. compute-sanitizer memcheck, racecheck and synccheck on the device tests (shorter runs).
# Each step has a time limit, cut to what is left of DEVICE_CHECK_BUDGET (460 s); a step the budget
# cannot start is reported NOT RUN.
# Everything goes to DIR/device_check.log, printed at the end (the steps' headers as they run). Exit status: 0 all passed, 1 a step
# failed, 3 no GPU (without --host-only).
# usage: run.sh [--host-only]   (--host-only: steps 1-2 with the device tests skipped, and the
#        paper's damper stepped briefly on the emulated device, for a machine without a GPU:
#        checks that the bundle is whole and runs from where it is)
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
log=$here/device_check.log
host_only=0
[ "${1:-}" = "--host-only" ] && host_only=1
: > "$log"
say() { echo "$@" | tee -a "$log"; }
# Runs a step with a time limit, its output into the log; records PASS/FAIL.
results=()
budget=${DEVICE_CHECK_BUDGET:-460}  # [s] for all steps: the run stays under 8 minutes
step() {  # name, limit_s, command...  (the limit is cut to what is left of the budget)
  local name=$1 limit=$2; shift 2
  local left=$((budget - SECONDS))
  if [ $left -lt 15 ]; then
    say ""
    say "== $name: NOT RUN (the ${budget} s budget is spent)"
    results+=("NOT RUN  $name  (budget spent)")
    return 0
  fi
  [ "$limit" -le "$left" ] || limit=$left
  say ""
  say "== $name ($(date -u +%T), limit ${limit}s): $*"
  local t0=$SECONDS rc
  if declare -F "$1" > /dev/null; then "$@" >> "$log" 2>&1; else timeout --kill-after=10 "$limit" "$@" >> "$log" 2>&1; fi
  rc=$?
  local verdict=PASS
  [ $rc -eq 0 ] || verdict="FAIL (exit $rc$([ $rc -eq 124 ] && echo ', timed out'))"
  results+=("$verdict  $name  ($((SECONDS - t0)) s)")
  say "== $name: $verdict after $((SECONDS - t0)) s"
  return 0
}
cd "$here"
unset LD_LIBRARY_PATH
export VPPDEM_DEVICE_INPUTS=$here/inputs VPPDEM_BINARY=$here/vppdem
say "device check: $(date -u +%FT%TZ) on $(hostname), $(nproc) cores, bundle $here"
[ -f MANIFEST ] && head -3 MANIFEST | tee -a "$log"
gpu=0
if command -v nvidia-smi > /dev/null && nvidia-smi -L >> "$log" 2>&1; then gpu=1
elif ls /dev/nvidia[0-9]* > /dev/null 2>&1; then gpu=1; say "(no nvidia-smi; /dev/nvidia* present: trying the device)"; fi
if [ $gpu = 0 ] && [ $host_only = 0 ]; then
  say "device check: no GPU here (nvidia-smi -L finds none or is missing, no /dev/nvidia*): nothing to check on a device."
  say "  (run.sh --host-only runs the host-side parts: the bundle's libraries and the skipped tests)"
  exit 3
fi

check_ldd() {
  local bad=0
  for b in vppdem vppdem_cuda_tests vppdem_device_tests libvppdem_cuda_ref.so; do
    if ldd "$here/$b" | grep -q "not found"; then
      echo "$b: a library is not found:"; ldd "$here/$b" | grep "not found"; bad=1
    else
      echo "$b: every library found"
    fi
  done
  return $bad
}
step "the binaries' libraries (ldd)" 30 check_ldd
step "vppdem starts" 30 "$here/vppdem" --help
step "vppdem_cuda_tests" 60 "$here/vppdem_cuda_tests"
step "vppdem_device_tests" 200 "$here/vppdem_device_tests"
if [ $host_only = 1 ]; then
  step "the benchmark script parses" 10 bash -n "$here/bench/gpu.sh"
  step "the paper's damper on the emulated device (2 copies, 20 steps)" 120 "$here/vppdem" bench checkpoint \
    --state "$here/inputs/paper/run.ckpt" --batch 2 --backend emulated --steps 20 --energy
  step "the paper's damper on the emulated device in chunks (2 copies, 20 steps, chunks of 8)" 120 "$here/vppdem" bench \
    checkpoint --state "$here/inputs/paper/run.ckpt" --batch 2 --backend emulated --steps 20 --energy --chunk 8
else
  step "bench/gpu.sh" 300 env VPPDEM="$here/vppdem" STATE="$here/inputs/paper/run.ckpt" \
    OLD_STATE="$here/inputs/paper_005/run.ckpt" "$here/bench/gpu.sh"
  cs=/usr/local/cuda/bin/compute-sanitizer
  [ -x $cs ] || cs=$(command -v compute-sanitizer || true)
  if [ -n "$cs" ]; then
    for tool in memcheck racecheck synccheck; do
      step "compute-sanitizer $tool: vppdem_cuda_tests" 120 "$cs" --tool "$tool" --error-exitcode 9 "$here/vppdem_cuda_tests" \
        --gtest_filter='*Device*'
      step "compute-sanitizer $tool: vppdem_device_tests (200 steps)" 150 env VPPDEM_DEVICE_TEST_STEPS=200 \
        "$cs" --tool "$tool" --error-exitcode 9 "$here/vppdem_device_tests" --gtest_filter='DeviceBatch.*'
    done
  else
    say "compute-sanitizer: not found (/usr/local/cuda/bin, PATH)"
    results+=("FAIL  compute-sanitizer not found")
  fi
fi
say ""
say "== summary ($(date -u +%T))"
failed=0
for r in "${results[@]}"; do
  say "  $r"
  [[ $r == PASS* ]] || failed=1
done
notes=$(grep -h "no CUDA device" "$log" | sort -u | head -3 | paste -sd ';' -)
[ -z "$notes" ] || say "  skipped: $notes"
say "device check: $([ $failed = 0 ] && echo 'all passed' || echo 'FAILED'); the log: $log"
echo
echo "======== $log ========"
cat "$log"
exit $failed
