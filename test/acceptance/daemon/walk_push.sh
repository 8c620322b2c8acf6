#!/bin/sh
# A push while walking (issues 6 §3 and 13): walking at VX (0.5 m/s unless given), a force on
# the torso for 1 s; no fall, the robot walks on, and 2-3 s after the push's end its velocity
# (ground truth, averaged over that second) is back within 0.1 m/s of the command, forward and
# sideways.
# FORCE is N along x, or FX,FY,FZ in the world frame.
# Usage: walk_push.sh BALLASTD BALLAST PROFILE FORCE [VX]
. "$(dirname "$0")/lib.sh"
case $4 in *,*) FORCE=$4 ;; *) FORCE="$4,0,0" ;; esac
VX=${5:-0.5}

start_daemon
wait_until "stand" 30 mode_is stand
ballast walk --vx $VX --for 12s >/dev/null || fail "walk"
sim_time_passes 4
ballast record start "$WORK/push.tsv" >/dev/null || fail "record start"
ballast push --force "$FORCE" --duration 1s --body torso >/dev/null || fail "push"
sim_time_passes 4
ballast record stop >/dev/null || fail "record stop"
healthy
[ "$(field mode)" = walk ] || fail "not walking after the push"
motion_report "$WORK/push.tsv"
# Mean forward and lateral velocity from 3 to 4 s after the recording's start (the push's).
set -- $(awk -F '\t' "$RECORDING"'
  n++ == 0 { t0 = $1 }
  $1 >= t0 + 3 && $1 <= t0 + 4 { m++; f += $(col["true_v_fwd"]); l += $(col["true_v_lat"]) }
  END { if (m > 0) printf "%.3f %.3f\n", f / m, l / m }' "$WORK/push.tsv")
[ $# = 2 ] || fail "cannot read the velocity from the recording"
echo "velocity 2-3 s after the push: forward $1 m/s (command $VX), lateral $2 m/s"
awk -v f="$1" -v l="$2" -v c=$VX 'BEGIN { exit !(f - c <= 0.1 && c - f <= 0.1 && l <= 0.1 && -l <= 0.1) }' ||
  fail "the velocity is not back within 0.1 m/s of the command 2-3 s after the push"
stop_daemon
echo "ok: took a ($FORCE) N push for 1 s while walking"
