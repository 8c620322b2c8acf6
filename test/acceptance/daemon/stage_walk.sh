#!/bin/sh
# Walking onto a stage through the CLI (issue 14 §3): a stage HEIGHT m high from x = 1.5 m
# (ballast-mkmap, 2 cm cells; the simulation and the planner both take it from the profile's
# terrain.map), `ballast walk --vx 0.4` from standing at the origin for 7 s of simulated time,
# then `ballast stop`. Passes when the robot was never damped, stands again, and its base
# (ground truth) is on the stage: past the edge by 0.3 m and risen by the stage's height to
# 3 cm.
# Usage: stage_walk.sh BALLASTD BALLAST PROFILE BALLAST_MKMAP HEIGHT
. "$(dirname "$0")/lib.sh"
MKMAP=$4 HEIGHT=$5
EDGE=1.5

"$MKMAP" stage -o "$WORK/stage.bt" --extent -2 6 -2 2 --height "$HEIGHT" --start "$EDGE" \
  --depth 3 --width 3 >/dev/null || fail "ballast-mkmap"
DAEMON_PROFILE=$WORK/stage.yaml
printf 'extends: %s\nterrain:\n  map: %s\n' "$PROFILE" "$WORK/stage.bt" >"$DAEMON_PROFILE"

start_daemon
wait_until "stand" 30 mode_is stand
x0=$(field truth.base.position.0) z0=$(field truth.base.position.2)
ballast walk --vx 0.4 --for 60s >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
for_seconds 7
ballast stop >/dev/null || fail "stop"
wait_until "stand" 60 mode_is stand
for_seconds 1
x1=$(field truth.base.position.0) z1=$(field truth.base.position.2)
echo "base from x $x0 z $z0 to x $x1 z $z1 (stage $HEIGHT m high from x = $EDGE m)"
awk -v x="$x1" -v e="$EDGE" 'BEGIN { exit !(x >= e + 0.3) }' || fail "the base is not past the edge: x = $x1"
within "$(calc "$z1 - $z0")" "$HEIGHT" "$(calc "0.03 / $HEIGHT")" ||
  fail "the base rose by $(calc "$z1 - $z0") m, not the stage's $HEIGHT m"
stop_daemon
echo "ok: on the stage"
