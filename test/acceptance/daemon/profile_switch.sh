#!/bin/sh
# Switching profiles while standing: a valid variant takes over without a fall; a broken one is
# refused with its file, line and column, and the running profile stays. Switching while
# walking: the whole-body controller's gains switch at once, the planner's gait at the next
# stand; the robot walks on without a fall.
. "$(dirname "$0")/lib.sh"

cat >"$WORK/stiff.yaml" <<YAML
extends: $PROFILE
description: stiffer legs
control:
  joint_kp: {legs: 360}
  gain_blend_time: 0.3
YAML
cat >"$WORK/high-steps.yaml" <<YAML
extends: $PROFILE
description: higher swing, softer base tracking
gait:
  swing_apex: 0.1
wbc:
  base_kp: [300, 300, 300, 300, 300, 300]
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
ballast walk --vx 0.5 --for 8s >/dev/null || fail "walk"
sim_time_passes 2
ballast profile use "$WORK/high-steps.yaml" >/dev/null || fail "profile use high-steps while walking"
[ "$(field profile)" = high-steps ] || fail "the switch while walking did not take"
sim_time_passes 3
healthy
[ "$(field mode)" = walk ] || fail "not walking after the switch"
wait_until "stand after the walk" 60 mode_is stand
sim_time_passes 1
healthy
stop_daemon
echo "ok: switched to stiff, refused broken.yaml:3, stayed standing; switched while walking"
