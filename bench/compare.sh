#!/usr/bin/env bash
# Runs vppdem and the reference codes on the shared benchmark scenes, one right after the
# other, and prints the JSON lines and the ratios (the machine is shared: compare in one run).
# usage: bench/compare.sh [SHARED_BENCH_DIR] [THREADS...]   (needs: apt-get install yade liggghts)
set -uo pipefail
cd "$(dirname "$0")/.."
B=${1:-../shared/bench}
shift || true
THREADS=${*:-1 2}
V=build/vppdem
last_json() { grep -E '^\{|RESULT' | tail -1 | sed 's/^RESULT //'; }
sps() { /usr/bin/python3 -c 'import json,sys; print(json.loads(sys.argv[1])["steps_per_s"])' "$1"; }
for t in $THREADS; do
  ours=$($V bench grains-in-cylinder --grains $B/grains_1000.csv --warmup 50000 --steps 20000 --threads $t | last_json)
  yade=$(yade -n -j$t -x $B/yade/bench_a.py $B/grains_1000.csv --warmup 50000 --steps 20000 2>/dev/null | last_json)
  echo "A N=1000 threads=$t ours=$ours"; echo "A N=1000 threads=$t yade=$yade"
  echo "RATIO A1000 t$t vppdem/yade = $(/usr/bin/python3 -c "print(round($(sps "$ours")/$(sps "$yade"),2))")"
  ours=$($V bench foil-plus-grains --scene-dir $B --warmup 40000 --steps 10000 --threads $t | last_json)
  yade=$(yade -n -j$t -x $B/yade/bench_b.py $B/foil_nodes.csv $B/foil_bonds.csv $B/foil_grains_1010.csv --warmup 40000 --steps 10000 2>/dev/null | last_json)
  echo "B threads=$t ours=$ours"; echo "B threads=$t yade=$yade"
  echo "RATIO B t$t vppdem/yade = $(/usr/bin/python3 -c "print(round($(sps "$ours")/$(sps "$yade"),2))")"
  ours=$($V bench foil-plus-grains --scene-dir $B --warmup 40000 --steps 10000 --threads $t --underpressure 60000 | last_json)
  echo "B+pressure threads=$t ours=$ours"
  ours=$($V bench grains-in-cylinder --grains $B/grains_10000.csv --warmup 20000 --steps 4000 --threads $t | last_json)
  lig=$(python3 $B/liggghts/bench_c.py $B/grains_10000.csv --np $t --warmup 20000 --steps 4000 2>/dev/null | last_json)
  echo "A N=10000 threads=$t ours=$ours"; echo "A N=10000 threads=$t liggghts=$lig"
  [ -n "$lig" ] && echo "RATIO A10000 t$t vppdem/liggghts = $(/usr/bin/python3 -c "print(round($(sps "$ours")/$(sps "$lig"),2))")"
  ours=$($V bench grains-in-cylinder --grains $B/grains_100000.csv --warmup 200 --steps 400 --threads $t | last_json)
  yade=$(yade -n -j$t -x $B/yade/bench_a.py $B/grains_100000.csv --warmup 200 --steps 400 2>/dev/null | last_json)
  echo "A N=100000 threads=$t ours=$ours"; echo "A N=100000 threads=$t yade=$yade"
  echo "RATIO A100000 t$t vppdem/yade = $(/usr/bin/python3 -c "print(round($(sps "$ours")/$(sps "$yade"),2))")"
done
