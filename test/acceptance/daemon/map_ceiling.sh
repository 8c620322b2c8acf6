#!/bin/sh
# A map with a ceiling (a floor and a slab at 2.5 m, as an indoor lidar map has) loaded while
# standing and while walking: the planner's ground stays the floor, no fall. Bad maps (cut
# short, of the wrong kind, of an enormous extent) are refused with the file's name and the
# map in use stays.
# Usage: map_ceiling.sh BALLASTD BALLAST PROFILE MKMAP
. "$(dirname "$0")/lib.sh"
MKMAP=$4

"$MKMAP" flat --ceiling 2.5 --extent -3 8 -3 3 -o "$WORK/ceiling.bt" >/dev/null || fail "mkmap"
start_daemon
wait_until "stand" 30 mode_is stand
ballast map load "$WORK/ceiling.bt" >/dev/null || fail "map load while standing"
sim_time_passes 2
healthy
[ "$(field mode)" = stand ] || fail "not standing after the map load"
near base.position.2 0.89 0.03 || fail "the base is not at its standing height: $(field base.position.2)"

ballast walk --vx 0.4 --for 6s >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
sim_time_passes 1.5
ballast map load "$WORK/ceiling.bt" >/dev/null || fail "map load while walking"
sim_time_passes 3
healthy
[ "$(field mode)" = walk ] || fail "stopped walking"
x=$(field truth.base.position.0)
awk -v x="$x" 'BEGIN { exit !(x > 0.8) }' || fail "walked only to x = $x"

# Bad maps: each refused, naming the file; the ceiling map stays.
head -c 20000 "$WORK/ceiling.bt" >"$WORK/cut.bt"
"$MKMAP" flat --extent -400 400 -400 400 --resolution 0.2 -o "$WORK/huge.bt" >/dev/null || fail "mkmap huge"
"$MKMAP" flat -o "$WORK/full.ot" >/dev/null || fail "mkmap .ot"
cp "$WORK/full.ot" "$WORK/kind.bt"
# huge.bt is read whole before its extent is refused (21 M nodes: 2 s of CPU, 6.6 s of wall time
# at a load of 8 on two cores, more beside the lockstep robot): the CLI's 10 s is not enough there.
for bad in cut huge kind; do
  if ballast --timeout 60 map load "$WORK/$bad.bt" >"$WORK/out" 2>&1; then fail "$bad.bt was loaded"; fi
  grep -q "map $WORK/$bad.bt: " "$WORK/out" || fail "the error for $bad.bt does not name it: $(cat "$WORK/out")"
  grep -q "the map in use stays" "$WORK/out" || fail "no word that the map stays: $(cat "$WORK/out")"
  echo "refused: $(head -1 "$WORK/out")"
done
ballast map info >"$WORK/info" 2>&1 || fail "map info"
grep -q "ceiling.bt" "$WORK/info" || fail "the ceiling map is no longer in use: $(cat "$WORK/info")"
healthy
stop_daemon
echo "ok: a map with a ceiling at 2.5 m loaded standing and walking (to x = $x), no fall; bad maps refused"
