#!/usr/bin/env bash
# The performance targets of issue 7, measured in one run beside the reference codes:
#   foil-plus-grains with 60 kPa underpressure at 1 and 2 threads (target: 20,000 steps/s at 2),
#   grains-in-cylinder N = 1000, 10000, 100000 against LIGGGHTS at the same thread count
#   (target: 2x its particle-steps/s, and ours flat within 30% over N), 2 threads / 1 thread,
#   peak memory at N = 100000 (target: < 300 B/particle + 100 B/contact), and a per-phase profile.
# usage: bench/targets.sh [SHARED_BENCH_DIR] [--no-ref]     (references: apt-get install liggghts)
# Quote the ratios of one run: the machine is shared and absolute figures drift.
set -uo pipefail
cd "$(dirname "$0")/.."
B=${1:-../shared/bench}
REF=1
[ "${2:-}" = "--no-ref" ] && REF=0
V=build/vppdem
PY=/usr/bin/python3
last_json() { grep -E '^\{|RESULT' | tail -1 | sed 's/^RESULT //'; }
field() { $PY -c 'import json,sys; print(json.loads(sys.argv[1]).get(sys.argv[2], "nan"))' "$1" "$2"; }
ratio() { $PY -c "import sys; a,b=float(sys.argv[1]),float(sys.argv[2]); print(round(a/b,2) if b==b and b>0 else 'nan')" "$1" "$2"; }

declare -A SPS
echo "== foil-plus-grains, underpressure 60 kPa (target: 20000 steps/s at 2 threads)"
for t in 1 2; do
  j=$($V bench foil-plus-grains --scene-dir "$B" --warmup 40000 --steps 10000 --threads "$t" --underpressure 60000 | last_json)
  SPS[B$t]=$(field "$j" steps_per_s)
  echo "threads=$t steps/s=${SPS[B$t]}  $j"
done
echo "RATIO B 2t/1t = $(ratio "${SPS[B2]}" "${SPS[B1]}")   (target 1.8)"

declare -A ARGS=([1000]="--warmup 50000 --steps 20000" [10000]="--warmup 20000 --steps 4000" [100000]="--warmup 200 --steps 400")
for n in 1000 10000 100000; do
  echo "== grains-in-cylinder N=$n"
  for t in 1 2; do
    j=$($V bench grains-in-cylinder --grains "$B/grains_$n.csv" ${ARGS[$n]} --threads "$t" | last_json)
    SPS[A$n.$t]=$(field "$j" particle_steps_per_s)
    echo "vppdem threads=$t particle-steps/s=${SPS[A$n.$t]}  $j"
    if [ $REF = 1 ]; then
      l=$(python3 "$B/liggghts/bench_c.py" "$B/grains_$n.csv" --np "$t" ${ARGS[$n]} 2>/dev/null | last_json)
      lp=$(field "${l:-{\}}" particle_steps_per_s)
      echo "liggghts ranks=$t particle-steps/s=$lp  $l"
      echo "RATIO A$n t$t vppdem/liggghts = $(ratio "${SPS[A$n.$t]}" "$lp")   (target 2)"
    fi
  done
  echo "RATIO A$n 2t/1t = $(ratio "${SPS[A$n.2]}" "${SPS[A$n.1]}")   (target 1.8 at N=100000)"
done
for t in 1 2; do
  echo "RATIO flatness t$t: N=1000 / N=100000 = $(ratio "${SPS[A1000.$t]}" "${SPS[A100000.$t]}"), N=10000 / N=100000 = $(ratio "${SPS[A10000.$t]}" "${SPS[A100000.$t]}")   (target within 0.7..1.3)"
done

echo "== profile (foil-plus-grains, 60 kPa, 2 threads)"
$V bench foil-plus-grains --scene-dir "$B" --warmup 40000 --steps 10000 --threads 2 --underpressure 60000 --profile | grep -v '^{'
echo "== profile (grains-in-cylinder N=100000, 1 thread)"
$V bench grains-in-cylinder --grains "$B/grains_100000.csv" --warmup 200 --steps 400 --threads 1 --profile | grep -v '^{'
