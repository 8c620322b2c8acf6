#!/bin/sh
# Real time (issue 12 §2): the deadline policy with the host's delays injected into the
# simulation's ticks (backend.simbody.host: the sleep happens inside the tick, as a slow tick's
# work would). A 3 ms stall once, then 2 ms on 5 % of the ticks while walking: the robot rides
# through (late ticks counted, never damped). A 50 ms stall: the motors go 50 ms without a
# command, more than safety.max_command_gap: damped, fault command_gap. And the planner late:
# 150 ms rides through, 400 ms damps (planner.injected_stall, safety.max_plan_age).
# Usage: realtime_delays.sh BALLASTD BALLAST PROFILE
BALLAST_ACCEPTANCE_REALTIME=1
. "$(dirname "$0")/lib.sh"

profile() {  # profile NAME STALL_AT STALL JITTER_FRACTION
  cat >"$WORK/$1.yaml" <<EOP
extends: $PROFILE
backend:
  simbody:
    host: {stall_at: $2, stall: $3, jitter_from: 4.5, jitter_fraction: $4, jitter: 0.002}
EOP
  echo "$WORK/$1.yaml"
}

# Rides through: 3 ms once at t = 4 s, then 2 ms on 5 % of the ticks, walking 0.5 m/s.
DAEMON_PROFILE=$(profile jitter 4.0 0.003 0.05)
start_daemon
wait_until "stand" 30 mode_is stand
ballast walk --vx 0.5 --for 8s >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
t_end=$(calc "$(field t) + 8")
until time_after "$t_end" 0; do
  [ "$(field mode)" != damp ] || fail "damped by late ticks: $(field faults)"
  sleep 0.1
done
healthy
late=$(field timing.late_ticks) max=$(field timing.lateness_ms.max)
echo "jitter: $(timing_line)"
# About 5 % of the 5 s after 4.5 s (250 ticks) are late; with a margin for chance (> 3 σ).
[ "$late" -ge 150 ] || fail "only $late late ticks: the delays were not injected"
awk -v m="$max" 'BEGIN { exit !(m >= 2.0) }' || fail "the longest lateness $max ms is not the 3 ms stall"
stop_daemon

# Damps: a 50 ms stall at t = 3 s while standing.
DAEMON_PROFILE=$(profile stall 3.0 0.05 0)
start_daemon
wait_until "stand" 30 mode_is stand
wait_until "the stall to damp the robot" 30 mode_is damp
[ "$(field faults.0.kind)" = command_gap ] || fail "damped by $(field faults) instead of the command gap"
echo "stall: $(field faults.0.message)"
stop_daemon

# The planner late (planner.injected_stall: its thread does not run, as on a busy host) while
# walking 1.0 m/s: the loop tracks the plan in force. 150 ms rides through, said in the log at
# half safety.max_plan_age; 400 ms is past it: damped, a planner fault naming the key.
planner_profile() {  # planner_profile NAME STALL
  printf 'extends: %s\nplanner:\n  injected_stall: %s\n  injected_stall_at: 4.0\n' "$PROFILE" "$2" \
    >"$WORK/$1.yaml"
  echo "$WORK/$1.yaml"
}
DAEMON_PROFILE=$(planner_profile planner_late 0.15)
start_daemon
wait_until "stand" 30 mode_is stand
ballast walk --vx 1.0 --for 8s >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
until time_after 7 0; do never_damped; sleep 0.1; done
healthy
grep -q 'planner: the plan in force is 0\.1[0-9]* s old (safety.max_plan_age 0.200 s): the planner did not answer: in a solve' "$LOG" ||
  fail "no warning of the late planner in the log"
echo "planner late: $(grep -o 'the plan in force is.*' "$LOG" | head -1)"
stop_daemon

DAEMON_PROFILE=$(planner_profile planner_stalled 0.4)
start_daemon
wait_until "stand" 30 mode_is stand
ballast walk --vx 1.0 --for 8s >/dev/null || fail "walk"
wait_until "the planner's stall to damp the robot" 30 mode_is damp
[ "$(field faults.0.kind)" = planner ] || fail "damped by $(field faults) instead of the planner"
field faults.0.message | grep -q 'no valid plan for 0.2[0-9]* s (safety.max_plan_age 0.200 s)' ||
  fail "the planner fault does not name the plan's age and the key: $(field faults.0.message)"
echo "planner stalled: $(field faults.0.message)"
stop_daemon
echo "ok: late ticks and a late planner rode through, the stalls damped"
