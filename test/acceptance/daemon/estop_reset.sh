#!/bin/sh
# estop from a client without the lease damps the robot at once and latches; stand is refused
# with what to do; reset clears the latch. A damped humanoid cannot hold itself up: in the
# simulation it sinks to the floor, the fall is detected, and stand is refused until it is put
# back on its feet.
. "$(dirname "$0")/lib.sh"

refused_with() {  # refused_with TEXT VERB...: the verb exits 1 and says TEXT
  text=$1
  shift
  set +e
  out=$(ballast "$@" 2>&1)
  code=$?
  set -e
  [ $code -eq 1 ] || fail "ballast $* exited $code"
  echo "$out" | grep -q "$text" || fail "ballast $* does not say '$text': $out"
}

start_daemon
wait_until "stand" 30 mode_is stand
BALLAST_LEASE_FILE=$WORK/other-lease ballast estop >/dev/null || fail "estop"
[ "$(field mode)" = damp ] || fail "estop did not damp"
[ "$(field estop)" = true ] || fail "estop not latched"
[ "$(field faults.0.kind)" = estop ] || fail "estop not in the faults"
refused_with "ballast reset" stand
refused_with "ballast reset" passive
ballast reset >/dev/null || fail "reset"
[ "$(field mode)" = passive ] || fail "reset did not go to passive"
[ "$(field estop)" = false ] || fail "the latch stayed"
fallen() { [ "$(field fallen)" = true ]; }
wait_until "the fall to be seen" 30 fallen
refused_with "has fallen" stand
stop_daemon
echo "ok: estop latched, stand refused until reset, the damped robot's fall detected"
