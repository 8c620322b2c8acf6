#!/bin/sh
# Real time (issue 12 §2): ballastd without --lockstep, the whole controller (estimator, planner
# thread, whole-body controller) on a simulated robot: stand, pose the base and back, walk at VX
# for SECONDS (default 20), stand again.
# Never damped, never fallen; the forward velocity over the walk's second half within 10 % of
# the command (ground truth). Prints the schedule's figures (status timing).
# Usage: realtime_walk.sh BALLASTD BALLAST PROFILE VX [SECONDS]
BALLAST_ACCEPTANCE_REALTIME=1
. "$(dirname "$0")/lib.sh"
VX=$4 WALK=${5:-20}
HALF=$(calc "$WALK / 2")

start_daemon
wait_until "stand" 30 mode_is stand
ballast pose --height 0.83 --pitch 3deg >/dev/null || fail "pose"
wait_until "the base at 0.83 m" 10 near base.position.2 0.83 0.01
wait_until "the base pitched 3 deg" 10 near base.rpy.1 0.0524 0.01
ballast pose >/dev/null || fail "pose back to nominal"
wait_until "the nominal height" 10 near base.position.2 0.89 0.01
for_seconds 1
ballast walk --vx "$VX" --for "${WALK}s" >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
for_seconds "$HALF"
t0=$(field t) x0=$(field truth.base.position.0)
for_seconds "$HALF"
t1=$(field t) x1=$(field truth.base.position.0)
wait_until "the walk to end (ttl)" 10 mode_is stand
for_seconds 2
never_damped
v=$(calc "($x1 - $x0) / ($t1 - $t0)")
echo "real time: walked at $v m/s (command $VX) over $(calc "$t1 - $t0") s"
echo "real time: $(timing_line)"
within "$v" "$VX" 0.1 || fail "forward velocity $v is not within 10 % of $VX"
stop_daemon
echo "ok: walked in real time, never damped"
