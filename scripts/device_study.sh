#!/usr/bin/env bash
# The device studies of issue 47 (docs/devices.md): every case of a study, seed by seed, one run
# at a time, each into out/devices/<study>/<case>_s<seed>/ from the example's device file with
# --set overrides; a finished run (its `done` marker) is skipped and an interrupted one resumes
# from its run.ckpt, so rerunning the script picks up where it stopped. After each run its small
# records (summary.json, tools.csv from the press on as tools.csv.gz, the case's command) are
# published into
# docs/data/devices/<study>/<case>_s<seed>/.
#   scripts/device_study.sh gripper      # then PYTHONPATH=src/python /usr/bin/python3 -m vppdem.report device gripper
#   scripts/device_study.sh gripper_pour # the pour against the lattice fill (needs gripper's dp50)
# env: VPPDEM (build/vppdem), SEEDS ("1 2 3 4 5"), NICE (10), ONLY (a case name: run only it),
#      PUBLISH_ONLY (1: run nothing, publish the finished runs again)
set -euo pipefail
cd "$(dirname "$0")/.."
study=${1:?usage: scripts/device_study.sh gripper|gripper_pour|beam}
VPPDEM=${VPPDEM:-build/vppdem}
NICE=${NICE:-10}

declare -a names sets
case "$study" in
gripper)
    file=examples/devices/gripper.toml
    SEEDS=${SEEDS:-"1 2 3 4 5"}
    f() { echo "tools.0.program.0.force=$1 tools.0.program.1.force=$1"; }
    # holding force against underpressure (press 2 N), against the immersion (the press force
    # sets the depth; dp 50 kPa), and the mechanisms (dp 50 kPa, press 2 N): no friction on the
    # membrane (rubber on object and grains), no friction between the grains
    names=(dp0 dp25 dp50 press1_dp50 press4_dp50 mu_membrane0_dp50 mu_grains0_dp50)
    sets=("stages.underpressure=0"
          "stages.underpressure=25000"
          "stages.underpressure=50000"
          "stages.underpressure=50000 $(f 1.0)"
          "stages.underpressure=50000 $(f 4.0)"
          "stages.underpressure=50000 membrane.friction=0.0"
          "stages.underpressure=50000 grains.friction=0.0")
    ;;
gripper_pour)
    # The gripper filled by a pour through the opening of its top 4 mm (docs/devices.md "The
    # pour"), frictionless (grains.fill_friction = 0: a frictionless pour comes to rest in the
    # bag; with the example's 0.5 a heap over the opening kept avalanching past 0.3 s in a trial),
    # at 50 kPa and a 2 N press; beside it the lattice fill settled frictionless. Both against the
    # gripper study's dp50 (the lattice settled at 0.5; the same seeds, every other key the same).
    file=examples/devices/gripper.toml
    SEEDS=${SEEDS:-"1 2 3 4 5"}
    names=(pour_dp50 lattice_mu0_dp50)
    sets=("stages.underpressure=50000 grains.fill_mode=pour grains.opening_height=0.004 grains.pour_count=650 grains.fill_friction=0 stages.fill_time=0.3 stages.fill_min_time=0.05"
          "stages.underpressure=50000 grains.fill_friction=0")
    ;;
beam)
    file=examples/devices/beam.toml
    SEEDS=${SEEDS:-"1 2 3"}
    names=(dp0 dp25 dp50)
    sets=("stages.underpressure=0" "stages.underpressure=25000" "stages.underpressure=50000")
    ;;
*) echo "device_study: unknown study '$study' (gripper, gripper_pour, beam)" >&2; exit 2 ;;
esac

# The small records: summary.json, and tools.csv from the press on (stage >= 2), six digits, gzipped.
publish() {
    mkdir -p "$2"
    cp "$1/summary.json" "$2/"
    python3 - "$1/tools.csv" "$2/tools.csv.gz" <<'PY'
import csv, gzip, sys
with open(sys.argv[1]) as f, gzip.open(sys.argv[2], "wt", compresslevel=9) as g:
    r = csv.reader(f)
    g.write(",".join(next(r)) + "\n")
    for row in r:
        if float(row[1]) >= 2:
            g.write(",".join("%.6g" % float(v) for v in row) + "\n")
PY
}

# seed-major: every case gets seed 1 before any gets seed 2, so a study cut short is balanced
for seed in $SEEDS; do
    for i in "${!names[@]}"; do
        name=${names[$i]}
        [ -n "${ONLY:-}" ] && [ "$ONLY" != "$name" ] && continue
        run=out/devices/$study/${name}_s$seed
        pub=docs/data/devices/$study/${name}_s$seed
        if [ -f "$run/done" ]; then
            [ -n "${PUBLISH_ONLY:-}" ] && publish "$run" "$pub"
            continue
        fi
        [ -n "${PUBLISH_ONLY:-}" ] && continue
        args=(device "$file" --out "$run" --set simulation.seed=$seed --set output.vtk=false)
        for s in ${sets[$i]}; do args+=(--set "$s"); done
        mkdir -p "$(dirname "$run")"
        echo "== $(date -u +%H:%M:%S) $study $name seed $seed"
        start=$(date +%s)
        nice -n "$NICE" "$VPPDEM" "${args[@]}" 2> "$run.log"
        echo "$(( $(date +%s) - start ))" > "$run/done"
        cp "$run.log" "$run/stderr.log"
        mkdir -p "$pub"
        publish "$run" "$pub"
        { echo "# $(date -u +%Y-%m-%dT%H:%M:%SZ), wall $(cat "$run/done") s"
          printf '%q ' "$VPPDEM" "${args[@]}"; echo; } > "$pub/command.txt"
    done
done
echo "== $study: all runs done"
