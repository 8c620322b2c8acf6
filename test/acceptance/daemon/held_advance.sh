#!/bin/sh
# A held lockstep daemon (ballastd --lockstep --hold, as lib.sh starts every lockstep one) driven
# by `ballast advance`: the controller
# time a command lands at is the script's, not the wall clock's, so two runs of one script are
# the same run. Here: walk at 0.5 m/s from t = 1.5 s, stop at 4.0 s; at 6.0 s the estimated
# base position of two daemons agrees to the last digit `status` prints (17 significant). A daemon not held
# refuses `advance` with what to do.
. "$(dirname "$0")/lib.sh"

run_once() {
  start_daemon
  [ "$(field t)" = 0.0 ] || [ "$(field t)" = 0 ] || fail "a held daemon ran before advance: t=$(field t)"
  ballast advance 1.5 >/dev/null || fail "advance 1.5"
  [ "$(field mode)" = stand ] || fail "not standing at 1.5 s: $(field mode)"
  ballast walk --vx 0.5 >/dev/null || fail "walk"
  ballast advance +2.5 >/dev/null || fail "advance +2.5"
  near t 4.0 0.01 || fail "advance +2.5 from 1.5 s ended at t=$(field t)"
  ballast stop >/dev/null || fail "stop"
  ballast advance 6 >/dev/null || fail "advance 6"
  healthy
  position=$(field base.position)
  stop_daemon
}

run_once
first=$position
run_once
[ "$position" = "$first" ] || fail "two held runs differ at 6 s: $first against $position"
x=${first%% *}
awk -v x="$x" 'BEGIN { exit !(x > 0.7) }' || fail "walked only to x = $x m in 2.5 s at 0.5 m/s"

LOCKSTEP=--lockstep start_daemon
set +e
out=$(ballast advance 3 2>&1)
code=$?
set -e
[ $code -eq 1 ] || fail "advance on a daemon not held exited $code"
echo "$out" | grep -q -- "--hold" || fail "advance refused without saying what to do: $out"
stop_daemon
echo "ok: two held runs at the same base position at 6 s ($first), advance refused unheld"
