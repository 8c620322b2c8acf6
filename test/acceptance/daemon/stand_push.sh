#!/bin/sh
# A push while standing (issue 13): FORCE N along x on the torso for 1 s carries the capture
# point out of the support polygon; the robot leaves stand (mode recover), steps, and is back in
# stand within 5 s of the push's end, on its feet. A push it can take in place (MIN_STEPS 0)
# never leaves stand.  Usage: stand_push.sh BALLASTD BALLAST PROFILE FORCE MIN_STEPS
. "$(dirname "$0")/lib.sh"
FORCE=$4
MIN_STEPS=$5

start_daemon
wait_until "stand" 30 mode_is stand
sim_time_passes 1
ballast record start "$WORK/push.tsv" >/dev/null || fail "record start"
ballast push --force "$FORCE,0,0" --duration 1s --body torso >/dev/null || fail "push"
sim_time_passes 7
ballast record stop >/dev/null || fail "record stop"
healthy
[ "$(field mode)" = stand ] || fail "not standing 7 s after the push began: $(field mode)"
# From the recording (every tick, started just before the push request, so its first frame is
# the push's start within a status poll): whether the robot left stand (mode 5, recover), how
# many toe touch-downs, and the last frame not in stand.
set -- $(awk -F '\t' "$RECORDING"'
  n++ == 0 { t0 = $1; for (c = 0; c < 4; ++c) was[c] = $(col["contact_" c]) }
  {
    if ($(col["mode"]) == 5) recover = 1
    if ($(col["mode"]) != 2) last = $1
    for (c = 0; c < 4; c += 2) { if ($(col["contact_" c]) && !was[c]) steps++; was[c] = $(col["contact_" c]) }
  }
  END { printf "%s %d %d %s\n", t0, recover, steps, last == "" ? t0 : last }' "$WORK/push.tsv")
[ $# = 4 ] || fail "cannot read the recording"
t0=$1 recovered=$2 steps=$3 last=$4
echo "push at $t0 s: left stand: $recovered, $steps touch-downs, last frame not in stand $(calc "$last - $t0") s after the push began"
motion_report "$WORK/push.tsv"
if [ "$MIN_STEPS" -gt 0 ]; then
  [ "$recovered" = 1 ] || fail "never left stand (mode recover) for a $FORCE N push"
  [ "$steps" -ge "$MIN_STEPS" ] || fail "$steps touch-downs, expected at least $MIN_STEPS"
  # The push ends 1 s after it began: back in stand within 5 s of that.
  awk -v a="$last" -v b="$t0" 'BEGIN { exit !(a - b <= 6.0) }' ||
    fail "back in stand $(calc "$last - $t0 - 1") s after the push ended (5 s allowed)"
else
  [ "$recovered" = 0 ] || fail "stepped for a $FORCE N push it should take in place"
fi
stop_daemon
echo "ok: took a $FORCE N push for 1 s standing"
