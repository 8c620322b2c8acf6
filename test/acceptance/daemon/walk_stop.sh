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
ballast record start "$WORK/stop.tsv" >/dev/null || fail "record start"
ballast stop >/dev/null || fail "stop"
at_rest() {
  [ "$(field mode)" = stand ] &&
    awk -v vx="$(field truth.base.velocity.0)" -v vy="$(field truth.base.velocity.1)" \
      'BEGIN { exit !(vx * vx + vy * vy < 0.05 * 0.05) }' &&
    [ "$(ballast status --get contacts)" = "true true true true" ]
}
wait_until "the robot at rest" 60 at_rest
ballast record stop >/dev/null || fail "record stop"
# The times from the recording (every tick), not from status polls, whose own latency is
# simulated time in lockstep: the stop is the first frame whose command is zero, at rest the
# first after it standing with a ground-truth speed under 0.05 m/s and four contacts.
set -- $(awk -F '\t' "$RECORDING"'
  !stopped && $(col["cmd_vx"]) == 0 { stopped = 1; t0 = $1 }
  stopped && $(col["mode"]) == 2 && $(col["true_vx"]) ^ 2 + $(col["true_vy"]) ^ 2 < 0.05 ^ 2 &&
    $(col["contact_0"]) && $(col["contact_1"]) && $(col["contact_2"]) && $(col["contact_3"]) {
    print t0, $1; exit
  }' "$WORK/stop.tsv")
[ $# = 2 ] || fail "the recording shows no stop followed by rest"
t0=$1 t1=$2
echo "at rest $(calc "$t1 - $t0") s after stop"
motion_report "$WORK/stop.tsv"
awk -v a="$t1" -v b="$t0" 'BEGIN { exit !(a - b <= 2.0) }' || fail "took $(calc "$t1 - $t0") s to stop"
healthy
stop_daemon
echo "ok: stopped within 2 s"
