#!/bin/sh
# A wrong map never makes a standing robot fall (issue 14 §2): standing on the flat floor, load a
# map that has a 20 cm platform where the robot stands. The map disagrees with the stance feet:
# the status and the log say so, the estimated base stays at its height (the estimator is not
# given the map's heights), the robot stands and walks on the plane its feet stood on. A right
# map loaded then agrees again, and the log says that too.
# Usage: map_disagrees.sh BALLASTD BALLAST PROFILE MKMAP
. "$(dirname "$0")/lib.sh"
MKMAP=$4

"$MKMAP" stage --start -2 --depth 6 --width 4 --height 0.2 -o "$WORK/wrong.bt" >/dev/null || fail "mkmap wrong"
"$MKMAP" flat -o "$WORK/right.bt" >/dev/null || fail "mkmap right"
start_daemon
wait_until "stand" 60 mode_is stand
sim_time_passes 0.5
z0=$(field base.position.2)
[ "$(field terrain.map_agrees)" = true ] || fail "the profile's own floor does not agree: $(field terrain)"

ballast --timeout 60 map load "$WORK/wrong.bt" >/dev/null || fail "map load"
wait_until "the map to disagree" 30 sh -c '[ "$("$0" status --get terrain.map_agrees)" = false ]' "$BALLAST_BIN"
error=$(field terrain.map_error_m)
awk -v e="$error" 'BEGIN { exit !(e > 0.17 && e < 0.23) }' || fail "the map's error under the feet reads $error m, not 0.2"
grep -q "warning .*terrain: the map is 0.2[0-9]* m off where the stance feet stand" "$LOG" ||
  fail "no warning in the log"
ballast status | grep -q "the map DISAGREES with the stance feet by 0.2" || fail "the status does not say it: $(ballast status)"
sim_time_passes 2
healthy
near base.position.2 "$z0" 0.02 || fail "the estimated base went from $z0 to $(field base.position.2) m with the wrong map"
near truth.base.position.2 "$z0" 0.03 || fail "the base went from $z0 to $(field truth.base.position.2) m with the wrong map"

x0=$(field truth.base.position.0)
ballast walk --vx 0.4 --for 4s >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
sim_time_passes 2
healthy
wait_until "stand after the walk" 60 mode_is stand
sim_time_passes 0.5
healthy
x=$(field truth.base.position.0)
awk -v x="$x" -v x0="$x0" 'BEGIN { exit !(x - x0 > 1.2) }' || fail "walked from x = $x0 only to $x"

ballast --timeout 60 map load "$WORK/right.bt" >/dev/null || fail "map load right"
wait_until "the right map to agree" 30 sh -c '[ "$("$0" status --get terrain.map_agrees)" = true ]' "$BALLAST_BIN"
grep -q "info .*terrain: the map agrees with the stance feet again" "$LOG" || fail "no word in the log that it agrees"
sim_time_passes 1
healthy
stop_daemon
echo "ok: a map $error m off under the feet was not used (base z $z0 -> $(field base.position.2 2>/dev/null || echo -)); walked $x0 -> $x; the right map agrees"
