#!/bin/sh
# Walking down a real building's corridor: profiles/sim-building*.yaml put the robot in the lidar
# map of Freiburg's building 079 (from Debian's liboctomap-dev), which the planner plans on and
# the simulation is built from (its floor, walls and furniture; not its ceiling). Stand, walk
# 0.5 m/s for 8 s along the corridor, stop: never damped, the base where the command takes it,
# the estimate on the map (the localisation fixes fused), the file map and the live map in use.
# Exits 77 (skipped) when the map file is not installed (a Debian image without /usr/share/doc).
# Usage: map_building.sh BALLASTD BALLAST PROFILE
MAP=/usr/share/doc/liboctomap-dev/examples/data/geb079.bt
if [ ! -r "$MAP" ]; then
  echo "skipped: $MAP is not installed (liboctomap-dev ships it; this image drops /usr/share/doc)"
  exit 77
fi
. "$(dirname "$0")/lib.sh"

start_daemon
wait_until "stand" 60 mode_is stand
sim_time_passes 1
healthy
ballast map info >"$WORK/info" || fail "map info"
grep -q "file map $MAP" "$WORK/info" || fail "the building's map is not in use: $(cat "$WORK/info")"
x0=$(field truth.base.position.0)
y0=$(field truth.base.position.1)
near base.position.0 "$x0" 0.05 || fail "the estimate is not on the map: x $(field base.position.0), truly $x0"

ballast walk --vx 0.5 --for 8s >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
for _ in 1 2 3 4; do
  sim_time_passes 2
  healthy
done
wait_until "stand after the walk" 60 mode_is stand
sim_time_passes 1
healthy
x=$(field truth.base.position.0)
y=$(field truth.base.position.1)
awk -v x="$x" -v x0="$x0" 'BEGIN { exit !(x - x0 > 3.6 && x - x0 < 4.4) }' ||
  fail "walked from x = $x0 to $x (8 s at 0.5 m/s: 4 m)"
awk -v y="$y" -v y0="$y0" 'BEGIN { d = y - y0; exit !(d < 0.5 && d > -0.5) }' ||
  fail "drifted sideways from y = $y0 to $y"
near base.position.0 "$x" 0.05 || fail "the estimate left the map: x $(field base.position.0), truly $x"
echo "ok: walked down the corridor of building 079 from ($x0, $y0) to ($x, $y), never damped"
