#!/bin/sh
# `ballast stop` after walking at 1.0 m/s (issue 6 §3): the robot comes to rest standing within
# 2 s of simulated time: mode stand, ground-truth base speed under 0.05 m/s, all four contact
# points on the ground.
. "$(dirname "$0")/lib.sh"

start_daemon
wait_until "stand" 30 mode_is stand
ballast walk --vx 1.0 --for 20s >/dev/null || fail "walk"
sim_time_passes 4
healthy
ballast stop >/dev/null || fail "stop"
t0=$(field t)
ballast record start "$WORK/stop.tsv" >/dev/null || fail "record start"
at_rest() {
  [ "$(field mode)" = stand ] &&
    awk -v vx="$(field truth.base.velocity.0)" -v vy="$(field truth.base.velocity.1)" \
      'BEGIN { exit !(vx * vx + vy * vy < 0.05 * 0.05) }' &&
    [ "$(ballast status --get contacts)" = "true true true true" ]
}
wait_until "the robot at rest" 60 at_rest
t1=$(field t)
ballast record stop >/dev/null || fail "record stop"
echo "at rest $(calc "$t1 - $t0") s after stop"
motion_report "$WORK/stop.tsv"
awk -v a="$t1" -v b="$t0" 'BEGIN { exit !(a - b <= 2.0) }' || fail "took $(calc "$t1 - $t0") s to stop"
healthy
stop_daemon
echo "ok: stopped within 2 s"
