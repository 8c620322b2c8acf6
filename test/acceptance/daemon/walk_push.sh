#!/bin/sh
# A push while walking (issue 6 §3): walking at 0.5 m/s, FORCE N along x on the torso for 1 s;
# no fall, and the robot walks on.  Usage: walk_push.sh BALLASTD BALLAST PROFILE FORCE
. "$(dirname "$0")/lib.sh"
FORCE=$4

start_daemon
wait_until "stand" 30 mode_is stand
ballast walk --vx 0.5 --for 12s >/dev/null || fail "walk"
sim_time_passes 4
ballast push --force "$FORCE,0,0" --duration 1s --body torso >/dev/null || fail "push"
ballast record start "$WORK/push.tsv" >/dev/null || fail "record start"
sim_time_passes 4
ballast record stop >/dev/null || fail "record stop"
healthy
[ "$(field mode)" = walk ] || fail "not walking after the push"
motion_report "$WORK/push.tsv"
stop_daemon
echo "ok: took a $FORCE N push for 1 s while walking"
