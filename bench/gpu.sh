#!/usr/bin/env bash
# The batch engine on the GPU against the CPU of the same machine, in one run (issues 45, 58;
# docs/gpu.md): the paper's damper during cycling at the studies' 0.01 m/s (a run.ckpt, the energy
# ledger on), timed by `vppdem bench checkpoint` over 3,000 steps (so that a system's relayouts
# come at their rate, not once inside a short window):
#   device: batches of 1, 16, 64, 128, 256, 512 copies (system-steps/s; the batch of 1 is the
#           one system's steps/s), --backend cuda;
#   CPU:    World on 1 thread and on 16 threads (steps/s), and 16 separate 1-thread runs at once
#           (system-steps/s in all).
# Each device row has the run's own timers: the host's parts of a step (before and after the
# forces and the motion kernels, relayouts in the first), the bus and device, the kernels, the
# waits, the bytes, and the relayouts per 1,000 system-steps. With OLD_STATE (a run.ckpt at
# 0.05 m/s, as runs 1-4 of docs/data/gpu/HISTORY.md timed) the batches of 1 and 256 are timed
# again as those runs did (OLD_STEPS steps), so that a run compares with the old ones.
# Then the projections: the paper's studies at 0.01 m/s (RUNS runs of CYCLES cycles, amplitude
# AMPLITUDE) at the batched rate, and one cycle at 3.33e-4 m/s at the one system's rate.
# usage: bench/gpu.sh [--cpu-only]
# env: VPPDEM (build-device/vppdem), STATE (the damper's run.ckpt at 0.01 m/s; required),
#      OLD_STATE (none), OLD_STEPS (300: runs 1-4's), DEVICE_STEPS (3000), ONE_STEPS (3000), CPU_STEPS (3000), BATCHES ("1 16 64 128 256 512"), CPU_THREADS (16),
#      RUNS (150), CYCLES (5: the paper studies' setting), AMPLITUDE (0.01), ENERGY (--energy; empty: the ledger off),
#      CHUNK (256: the chunks' steps per launch sequence), CHUNK_BATCHES ("1 16 128 256 512": the
#      batches timed again in chunks; empty: none),
#      HOST_THREADS (nproc: the host threads of the device backend's bookkeeping), BACKEND (cuda;
#      emulated: the device backend's kernels on the host, to try this script without a GPU),
#      SPLITS ("1 8": the batches of 1 and 16 again with each system in this many blocks,
#      VPPDEM_CUDA_SPLIT), BLOCK_SIZES ("512": the batches of 1 and 256 again with blocks of this
#      many threads, VPPDEM_CUDA_BLOCK); empty: none
set -uo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-build-device/vppdem}
STATE=${STATE:?"STATE: the run.ckpt of the paper damper"}
OLD_STATE=${OLD_STATE:-}
OLD_STEPS=${OLD_STEPS:-300}
DEVICE_STEPS=${DEVICE_STEPS:-3000}
ONE_STEPS=${ONE_STEPS:-3000}
CPU_STEPS=${CPU_STEPS:-3000}
BATCHES=${BATCHES:-1 16 64 128 256 512}
CPU_THREADS=${CPU_THREADS:-16}
RUNS=${RUNS:-150}
CYCLES=${CYCLES:-5}
AMPLITUDE=${AMPLITUDE:-0.01}
ENERGY=${ENERGY-"--energy"}
HOST_THREADS=${HOST_THREADS:-$(nproc)}
BACKEND=${BACKEND:-cuda}
CHUNK=${CHUNK:-256}
CHUNK_BATCHES=${CHUNK_BATCHES-"1 16 128 256 512"}
BLOCK_SIZES=${BLOCK_SIZES-"512"}
SPLITS=${SPLITS-"1 8"}
cpu_only=0
[ "${1:-}" = "--cpu-only" ] && cpu_only=1

field() { sed -n "s/.*\"$1\": \"\{0,1\}\([^,\"}]*\).*/\1/p"; }
declare -A rate extra
rows=()
bench() {  # name, args...: one `vppdem bench checkpoint` line; its rate into rate[name]
  local name=$1; shift
  local line
  # shellcheck disable=SC2086
  line=$("$VPPDEM" bench checkpoint --state "${BENCH_STATE:-$STATE}" $ENERGY "$@" 2>&1 | tail -1)
  local r
  if [[ $line == *system_steps_per_s* ]]; then r=$(echo "$line" | field system_steps_per_s)
  else r=$(echo "$line" | field steps_per_s); fi
  if [ -z "$r" ]; then
    echo "gpu.sh: $name failed: $line"
    rate[$name]=0
  else
    rate[$name]=$r
    dt=$(echo "$line" | field dt)
    if [[ $line == *host_us_per_step* ]]; then
      local parts
      parts=$(echo "$line" | sed -n 's/.*"host_parts_us_per_step": \[\([^]]*\)\].*/\1/p' | tr -d ' ' | tr ',' '/')
      extra[$name]=$(printf '%.0f | %s | %.0f | %.0f | %.1f | %.0f | %.0f | %.3g' "$(echo "$line" | field host_us_per_step)" "$parts" \
        "$(echo "$line" | field device_us_per_step)" "$(echo "$line" | field kernel_us_per_step)" "$(echo "$line" | field waits_per_step)" \
        "$(echo "$line" | field bytes_up_per_step)" "$(echo "$line" | field bytes_down_per_step)" \
        "$(echo "$line" | field relayouts_per_1000_system_steps)")
    fi
    echo "gpu.sh: $name: $line"
  fi
  rows+=("$name")
}
dt=""
echo "gpu.sh: $(date -u +%FT%TZ) on $(hostname), $(nproc) cores; STATE=$STATE${OLD_STATE:+, OLD_STATE=$OLD_STATE}"
command -v nvidia-smi > /dev/null && nvidia-smi --query-gpu=name,memory.total,clocks.max.sm --format=csv,noheader
if [ $cpu_only = 0 ]; then
  for B in $BATCHES; do
    steps=$DEVICE_STEPS
    [ "$B" = 1 ] && steps=$ONE_STEPS
    bench "device batch $B" --batch "$B" --backend "$BACKEND" --threads "$HOST_THREADS" --steps "$steps"
  done
  # Chunks (DeviceBatch::run): the device runs CHUNK steps per launch sequence by itself, the
  # host only laying out the systems that stop for a rebuild or a compaction (issue 58, item 2).
  for B in $CHUNK_BATCHES; do
    steps=$DEVICE_STEPS
    [ "$B" = 1 ] && steps=$ONE_STEPS
    bench "device batch $B, chunks of $CHUNK" --batch "$B" --backend "$BACKEND" --threads "$HOST_THREADS" --steps "$steps" --chunk "$CHUNK"
  done
  # A batch of a block per system runs a chunk as one launch (k_chunk); the same as a launch per
  # phase and step, for the comparison.
  if [ "$BACKEND" = cuda ] && [ -n "$CHUNK_BATCHES" ]; then
    VPPDEM_CUDA_CHUNK=phases bench "device batch 256, chunks of $CHUNK, a launch per phase" --batch 256 --backend cuda \
      --threads "$HOST_THREADS" --steps "$DEVICE_STEPS" --chunk "$CHUNK"
  fi
  # What the ledger costs (its block sums come back every half step).
  ENERGY="" bench "device batch 256, ledger off" --batch 256 --backend "$BACKEND" --threads "$HOST_THREADS" --steps "$DEVICE_STEPS"
  # Other shapes: a system in one block (VPPDEM_CUDA_SPLIT=1; by default a small batch's systems
  # span several), blocks of other sizes (VPPDEM_CUDA_BLOCK; the default is 256 threads).
  if [ "$BACKEND" = cuda ]; then
    for K in $SPLITS; do
      VPPDEM_CUDA_SPLIT=$K bench "device batch 1, $K blocks per system" --batch 1 --backend cuda --threads "$HOST_THREADS" --steps "$ONE_STEPS"
      VPPDEM_CUDA_SPLIT=$K bench "device batch 16, $K blocks per system" --batch 16 --backend cuda --threads "$HOST_THREADS" --steps "$DEVICE_STEPS"
    done
    for T in $BLOCK_SIZES; do
      VPPDEM_CUDA_BLOCK=$T bench "device batch 1, $T threads per block" --batch 1 --backend cuda --threads "$HOST_THREADS" --steps "$ONE_STEPS"
      VPPDEM_CUDA_BLOCK=$T bench "device batch 256, $T threads per block" --batch 256 --backend cuda --threads "$HOST_THREADS" --steps "$DEVICE_STEPS"
    done
  fi
  if [ -n "$OLD_STATE" ]; then
    BENCH_STATE=$OLD_STATE bench "old protocol: device batch 1" --batch 1 --backend "$BACKEND" --threads "$HOST_THREADS" --steps "$OLD_STEPS"
    BENCH_STATE=$OLD_STATE bench "old protocol: device batch 256" --batch 256 --backend "$BACKEND" --threads "$HOST_THREADS" --steps "$OLD_STEPS"
  fi
fi
bench "CPU World, 1 thread" --threads 1 --steps "$CPU_STEPS"
bench "CPU World, $CPU_THREADS threads" --threads "$CPU_THREADS" --steps "$CPU_STEPS"
# CPU_THREADS separate 1-thread runs at once (as many studies' cases run on a CPU).
tmp=$(mktemp -d)
pids=()
for k in $(seq "$CPU_THREADS"); do
  # shellcheck disable=SC2086
  "$VPPDEM" bench checkpoint --state "$STATE" $ENERGY --threads 1 --steps "$CPU_STEPS" > "$tmp/$k.out" 2>&1 &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p"; done
sum=0
for k in $(seq "$CPU_THREADS"); do
  r=$(tail -1 "$tmp/$k.out" | field steps_per_s)
  sum=$(awk -v a="$sum" -v b="${r:-0}" 'BEGIN{print a + b}')
done
rm -rf "$tmp"
name="CPU $CPU_THREADS runs at once, 1 thread each"
rate[$name]=$sum
rows+=("$name")

echo
echo "| run | rate | unit | host us/step | host parts us/step (forces before/after, motion before/after) | bus+device us/step | of which kernels | waits/step | bytes up/step | bytes down/step | relayouts per 1000 system-steps |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for name in "${rows[@]}"; do
  unit="system-steps/s"
  case $name in "device batch 1"|"device batch 1, "*|"old protocol: device batch 1"|"CPU World"*) unit="steps/s";; esac
  printf '| %s | %.0f | %s | %s |\n' "$name" "${rate[$name]}" "$unit" "${extra[$name]:-| | | | | | |}"
done
echo
if [ $cpu_only = 0 ] && [ -n "$dt" ]; then
  # The batched rate for a study of RUNS runs: the smaller of the batches of 128 and 256 (a batch
  # of 150 lies between them); one system: the batch of 1.
  batched=$(awk -v a="${rate[device batch 128]:-0}" -v b="${rate[device batch 256]:-0}" 'BEGIN{print (a < b ? a : b)}')
  one=${rate[device batch 1]:-0}
  # In chunks where they ran (the protocol a study and a damper run use on the device).
  cb=$(awk -v a="${rate[device batch 128, chunks of $CHUNK]:-0}" -v b="${rate[device batch 256, chunks of $CHUNK]:-0}" 'BEGIN{print (a < b ? a : b)}')
  c1=${rate[device batch 1, chunks of $CHUNK]:-0}
  awk -v x="$cb" -v y="$batched" 'BEGIN{exit !(x > y)}' && batched=$cb
  awk -v x="$c1" -v y="$one" 'BEGIN{exit !(x > y)}' && one=$c1
  awk -v dt="$dt" -v A="$AMPLITUDE" -v n="$RUNS" -v c="$CYCLES" -v batched="$batched" -v one="$one" \
      -v cpu16="${rate[CPU $CPU_THREADS runs at once, 1 thread each]}" 'BEGIN {
    fast = c * 2 * A / 0.01 / dt          # steps of one run at 0.01 m/s (triangle: period 2A/v)
    slow = 2 * A / 3.33e-4 / dt           # steps of one cycle at 3.33e-4 m/s
    h_dev = (batched > 0) ? n * fast / batched / 3600 : -1
    h_cpu = (cpu16 > 0) ? n * fast / cpu16 / 3600 : -1
    m_one = (one > 0) ? slow / one / 60 : -1
    ok_b = (batched >= 400000) ? "met" : "NOT met"
    ok_1 = (one >= 50000) ? "met" : "NOT met"
    printf "projections (dt = %.4g s):\n", dt
    printf "  the paper study at 0.01 m/s, %d runs x %d cycles (%.3g steps each): %.2f h on the device (batched %.0f system-steps/s; target < 1 h), %.1f h on the CPU (%.0f system-steps/s)\n", n, c, fast, h_dev, batched, h_cpu, cpu16
    printf "  one cycle at 3.33e-4 m/s (%.3g steps): %.1f min on the device (one system %.0f steps/s; target < 15 min)\n", slow, m_one, one
    printf "  targets: batched >= 400000 system-steps/s: %s; one system >= 50000 steps/s: %s\n", ok_b, ok_1
  }'
fi
