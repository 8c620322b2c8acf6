#!/bin/sh
# Switching profiles while standing: a valid variant takes over without a fall; a broken one is
# refused with its file, line and column, and the running profile stays.
. "$(dirname "$0")/lib.sh"

cat >"$WORK/stiff.yaml" <<YAML
extends: $PROFILE
description: stiffer legs
control:
  joint_kp: {legs: 360}
  gain_blend_time: 0.3
YAML
cat >"$WORK/broken.yaml" <<YAML
extends: $PROFILE
control:
  joint_kp: {legs: lots}
YAML

start_daemon
wait_until "stand" 30 mode_is stand
ballast profile use "$WORK/stiff.yaml" >/dev/null || fail "profile use stiff"
[ "$(field profile)" = stiff ] || fail "the switch did not take"
sim_time_passes 1.0
healthy
[ "$(field mode)" = stand ] || fail "not standing after the switch"
set +e
out=$(ballast profile use "$WORK/broken.yaml" 2>&1)
code=$?
set -e
[ $code -eq 1 ] || fail "a broken profile was not refused (exit $code)"
echo "$out" | grep -q "broken.yaml:3:" || fail "the refusal does not name the line: $out"
[ "$(field profile)" = stiff ] || fail "the running profile did not stay"
stop_daemon
echo "ok: switched to stiff, refused broken.yaml:3, stayed standing"
