#!/bin/sh
# Walking onto a stage through the CLI (issue 14 §3): a stage HEIGHT m high from x = 1.5 m
# (ballast-mkmap, 2 cm cells; the simulation and the planner both take it from the profile's
# terrain.map), `ballast walk --vx 0.4` from standing at the origin, then `ballast stop`.
# WAY (default up):
#   up      onto a stage 3 m deep, 7 s of walking: passes when the base (ground truth) is past
#           the edge by 0.3 m and has risen by the stage's height to 3 cm;
#   down    up and off again, a stage 1.5 m deep (down at x = 3 m), 11 s of walking: past the far
#           edge by 0.3 m and back at its height on the floor to 3 cm;
#   off     off a platform the robot starts on (to x = 1.5 m; the profile's terrain.ground_height
#           says how high it stands), 7 s of walking: past the edge by 0.3 m and lowered by the
#           platform's height to 3 cm;
#   lidar   as up, after `ballast map clear`: the planner knows only what the robot's lidar has
#           seen since (the simulation keeps the stage).
# Every way: the robot is never damped and stands again after the stop. Lockstep, or real time
# with BALLAST_ACCEPTANCE_REALTIME=1. AFTER (default 0): seconds between reaching stand and the
# walk command, which moves the gait's phase at the edge.
# Usage: stage_walk.sh BALLASTD BALLAST PROFILE BALLAST_MKMAP HEIGHT [WAY [AFTER]]
. "$(dirname "$0")/lib.sh"
MKMAP=$4 HEIGHT=$5 WAY=${6:-up} AFTER=${7:-0}
EDGE=1.5
case $WAY in
  up | lidar) DEPTH=3 WALK=7 END=$EDGE RISE=$HEIGHT ;;
  down) DEPTH=1.5 WALK=11 END=$(calc "$EDGE + 1.5") RISE=0 ;;
  off) DEPTH=4 WALK=7 END=$EDGE RISE=-$HEIGHT ;;
  *) fail "WAY is up, down, off or lidar, not $WAY" ;;
esac
START=$EDGE
[ "$WAY" != off ] || START=$(calc "$EDGE - $DEPTH")

"$MKMAP" stage -o "$WORK/stage.bt" --extent -2 6 -2 2 --height "$HEIGHT" --start "$START" \
  --depth "$DEPTH" --width 3 >/dev/null || fail "ballast-mkmap"
DAEMON_PROFILE=$WORK/stage.yaml
printf 'extends: %s\nterrain:\n  map: %s\n' "$PROFILE" "$WORK/stage.bt" >"$DAEMON_PROFILE"
# Standing on the platform: without it the estimator puts the feet on the floor (0), the map
# disagrees with them by the platform's height and is not used, and the robot walks off the
# edge blind.
[ "$WAY" != off ] || printf '  ground_height: %s\n' "$HEIGHT" >>"$DAEMON_PROFILE"

start_daemon
wait_until "stand" 30 mode_is stand
# The walk starts on an empty map: not even the floor under the feet is known (the lidar's
# lowest line meets the floor 1 m ahead).
[ "$WAY" != lidar ] || ballast map clear >/dev/null || fail "map clear"
[ "$AFTER" = 0 ] || { advance_by "$AFTER"; never_damped; }
x0=$(field truth.base.position.0) z0=$(field truth.base.position.2)
ballast walk --vx 0.4 --for 60s >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
for_seconds "$WALK"
ballast stop >/dev/null || fail "stop"
wait_until "stand" 60 mode_is stand
for_seconds 1
x1=$(field truth.base.position.0) z1=$(field truth.base.position.2)
echo "base from x $x0 z $z0 to x $x1 z $z1 (stage $HEIGHT m high, $DEPTH m deep from x = $START m, $WAY)"
awk -v x="$x1" -v e="$END" 'BEGIN { exit !(x >= e + 0.3) }' || fail "the base is not past x = $END + 0.3 m: x = $x1"
awk -v d="$(calc "$z1 - $z0")" -v r="$RISE" 'BEGIN { e = d - r; exit !(e <= 0.03 && e >= -0.03) }' ||
  fail "the base rose by $(calc "$z1 - $z0") m, not $RISE m"
[ "$WAY" != lidar ] || ballast map info
held || echo "real time: $(timing_line)"
stop_daemon
echo "ok: $WAY, $HEIGHT m"
