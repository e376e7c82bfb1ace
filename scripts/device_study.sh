#!/usr/bin/env bash
# The device studies of issue 47 (docs/devices.md): each one study file, studies/devices/<study>.toml,
# run by `vppdem sweep` into out/devices/<study>/<case>_s<seed>/ (finished runs skipped, an
# interrupted one resumed from its run.ckpt) and its small records published into
# docs/data/devices/<study>/; then the report.
#   scripts/device_study.sh gripper       # gripper_pour (needs gripper's dp50), beam; gripper_vacuum,
#                                          # gripper_mechanisms, gripper_mechanisms_sphere, gripper_size (one report:
#                                          # gripper_jamming)
# env: VPPDEM (build/vppdem), SEEDS (the study's: --seeds), NICE (10), PUBLISH_ONLY (1: run
#      nothing, publish the finished runs again)
set -euo pipefail
cd "$(dirname "$0")/.."
study=${1:?usage: scripts/device_study.sh gripper|gripper_pour|beam|gripper_vacuum|gripper_mechanisms|gripper_mechanisms_sphere|gripper_size}
[ -f "studies/devices/$study.toml" ] || { echo "device_study: unknown study '$study' (studies/devices/*.toml)" >&2; exit 2; }
args=(sweep "studies/devices/$study.toml" --out "out/devices/$study" --publish "docs/data/devices/$study")
[ -z "${SEEDS:-}" ] || args+=(--seeds "$SEEDS")
[ -z "${PUBLISH_ONLY:-}" ] || args+=(--report-only)
nice -n "${NICE:-10}" "${VPPDEM:-build/vppdem}" "${args[@]}"
report=$study
case "$study" in gripper_vacuum | gripper_mechanisms | gripper_mechanisms_sphere | gripper_size) report=gripper_jamming ;; esac
PYTHONPATH=src/python /usr/bin/python3 -m vppdem.report device "$report"
