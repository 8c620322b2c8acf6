#!/bin/sh
# Walking on rough ground through the CLI (issue 14 §3): the profile's rough ground (sim-rough:
# 20 cm patches at random heights from 0 to 4 cm, seed 1) made long enough for the walk
# (ballast-mkmap, the same patches from x = -2 m to 16 m; the simulation and the planner both
# take it from terrain.map), standing up on it, then `ballast walk --vx VX` for SECONDS s.
# Passes when the robot is never damped and, over the walk (ground truth, recorded), the base
# covered at least 80 % of VX x SECONDS forward, its roll and pitch stayed within 0.25 rad and
# its height above z = 0 within 0.8 to 1.0 m (nominal 0.89 m over patches 0 to 4 cm high).
# Environment: ROUGH_SEED (1) the patches' seed; ROUGH_MAPPING=off keeps the lidar's scans out
# of the map (the planner has the file's map only; default: the file's map seeded into the live
# map, the scans inserted into it), ROUGH_MAPPING=lidar sends `ballast map clear` standing (the
# planner has what the lidar maps from then on, at mapping.resolution or ROUGH_RESOLUTION);
# ROUGH_SAVE=FILE saves the map the planner had at the end (and FILE-truth.bt, FILE.tsv);
# ROUGH_DISTANCE (0.8) the share of VX x SECONDS the base must cover.
# Usage: rough_walk.sh BALLASTD BALLAST PROFILE BALLAST_MKMAP VX SECONDS
. "$(dirname "$0")/lib.sh"
MKMAP=$4 VX=$5 SECONDS_WALKED=$6 SEED=${ROUGH_SEED:-1}

"$MKMAP" rough -o "$WORK/rough.bt" --extent -2 16 -2 2 --amplitude 0.04 --patch 0.2 --seed "$SEED" \
  >/dev/null || fail "ballast-mkmap"
DAEMON_PROFILE=$WORK/rough.yaml
printf 'extends: %s\nterrain:\n  map: %s\n' "$PROFILE" "$WORK/rough.bt" >"$DAEMON_PROFILE"
if [ "${ROUGH_MAPPING:-on}" = off ] || [ -n "${ROUGH_RESOLUTION:-}" ]; then
  echo 'mapping:'
  [ "${ROUGH_MAPPING:-on}" != off ] || echo '  enabled: false'
  [ -z "${ROUGH_RESOLUTION:-}" ] || echo "  resolution: $ROUGH_RESOLUTION"
fi >>"$DAEMON_PROFILE"

start_daemon
wait_until "stand" 30 mode_is stand
[ "${ROUGH_MAPPING:-on}" != lidar ] || ballast map clear >/dev/null || fail "map clear"
for_seconds 1
ballast record start "$WORK/walk.tsv" >/dev/null || fail "record start"
x0=$(field truth.base.position.0)
ballast walk --vx "$VX" --for "$(calc "$SECONDS_WALKED + 5")s" >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
for_seconds "$SECONDS_WALKED"
ballast record stop >/dev/null || fail "record stop"
x1=$(field truth.base.position.0)
# The mode first: a map save can take seconds under load, past the walk command's end.
[ "$(field mode)" = walk ] || fail "stopped walking before the command's end"
[ -z "${ROUGH_SAVE:-}" ] || ballast map save "$ROUGH_SAVE" >/dev/null || fail "map save"
[ -z "${ROUGH_SAVE:-}" ] || cp "$WORK/rough.bt" "${ROUGH_SAVE%.bt}-truth.bt"
[ -z "${ROUGH_SAVE:-}" ] || cp "$WORK/walk.tsv" "${ROUGH_SAVE%.bt}.tsv"
motion_report "$WORK/walk.tsv"
awk -F '\t' -v x0="$x0" -v x1="$x1" -v vx="$VX" -v s="$SECONDS_WALKED" -v share="${ROUGH_DISTANCE:-0.8}" "$RECORDING"'
  function abs(a) { return a < 0 ? -a : a }
  {
    r = abs($(col["true_roll"])); p = abs($(col["true_pitch"])); z = $(col["true_z"])
    if (n == 0 || r > rmax) rmax = r
    if (n == 0 || p > pmax) pmax = p
    if (n == 0 || z < zmin) zmin = z
    if (n == 0 || z > zmax) zmax = z
    n++
  }
  END {
    printf "walked %.2f m in %s s (command %s m/s): roll max %.3f rad, pitch max %.3f rad, height %.3f to %.3f m over %d samples\n", x1 - x0, s, vx, rmax, pmax, zmin, zmax, n
    exit !(n > 0 && x1 - x0 >= share * vx * s && rmax <= 0.25 && pmax <= 0.25 && zmin >= 0.8 && zmax <= 1.0)
  }' "$WORK/walk.tsv" || fail "off the bars (distance, roll, pitch or height)"
held || echo "real time: $(timing_line)"
stop_daemon
echo "ok: walked on rough ground"
