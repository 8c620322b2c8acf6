#!/bin/sh
# Walk through the CLI (issue 6 §3): `ballast walk --vx VX --vy VY --yaw-rate WZ` from standing
# for 5 s and then MEASURE s more (default 5) of simulated time. No fall; over those MEASURE s
# the mean velocity (ground truth, in the heading frame at the start of the window) is within TOL
# (fraction) of the command; turning, the yaw rate and the speed along the command's arc (WZ times
# MEASURE under pi: the yaw's change is read unwrapped within a half turn);
# walking forward, the arms swing (not frozen) in antiphase with each other, as a human's do.
# Usage: walk.sh BALLASTD BALLAST PROFILE VX VY WZ TOL [MEASURE]
. "$(dirname "$0")/lib.sh"
VX=$4 VY=$5 WZ=$6 TOL=$7 MEASURE=${8:-5}

start_daemon
wait_until "stand" 30 mode_is stand
ballast walk --vx "$VX" --vy "$VY" --yaw-rate "$WZ" --for 20s >/dev/null || fail "walk"
wait_until "the loop to take the walk command" 10 mode_is walk
sim_time_passes 5
ballast record start "$WORK/walk.tsv" >/dev/null || fail "record start"
t0=$(field t) x0=$(field truth.base.position.0) y0=$(field truth.base.position.1)
yaw0=$(field truth.base.rpy.2)
sim_time_passes "$MEASURE"
t1=$(field t) x1=$(field truth.base.position.0) y1=$(field truth.base.position.1)
yaw1=$(field truth.base.rpy.2)
ballast record stop >/dev/null || fail "record stop"
healthy
[ "$(field mode)" = walk ] || fail "stopped walking before the command's 20 s"
motion_report "$WORK/walk.tsv"

dt=$(calc "$t1 - $t0")
# Displacement in the heading frame of the window's start, and the yaw rate (unwrapped).
fwd=$(calc "(($x1 - $x0) * cos($yaw0) + ($y1 - $y0) * sin($yaw0)) / $dt")
lat=$(calc "(-($x1 - $x0) * sin($yaw0) + ($y1 - $y0) * cos($yaw0)) / $dt")
dyaw=$(awk -v a="$yaw1" -v b="$yaw0" 'BEGIN { d = a - b; pi = atan2(0, -1); while (d > pi) d -= 2 * pi; while (d < -pi) d += 2 * pi; print d }')
wz=$(calc "$dyaw / $dt")
echo "over ${dt} s: forward $fwd m/s (command $VX), lateral $lat m/s (command $VY), yaw rate $wz rad/s (command $WZ)"
if [ "$WZ" = 0 ]; then
  # Walking straight: velocities in the heading frame.
  [ "$VX" = 0 ] || within "$fwd" "$VX" "$TOL" || fail "forward velocity $fwd is not within $TOL of $VX"
  [ "$VY" = 0 ] || within "$lat" "$VY" "$TOL" || fail "lateral velocity $lat is not within $TOL of $VY"
else
  within "$wz" "$WZ" "$TOL" || fail "yaw rate $wz is not within $TOL of $WZ"
  # Turning while walking: the base runs the command's arc, whose chord over the window is
  # 2 v sin(WZ dt / 2) / WZ.
  if [ "$VX" != 0 ] || [ "$VY" != 0 ]; then
    chord=$(calc "sqrt($fwd * $fwd + $lat * $lat)")
    arc=$(calc "2 * sqrt($VX * $VX + $VY * $VY) * sin($WZ * $dt / 2) / ($WZ * $dt)")
    echo "speed along the chord $chord m/s (the command's arc: $arc m/s)"
    within "$chord" "$arc" "$TOL" || fail "speed along the chord $chord is not within $TOL of $arc"
  fi
fi

# Arms, walking forward: each shoulder pitch swings through at least 0.05 rad, and the two
# swing in antiphase (their correlation over the window is negative). (Sideways or turning on
# the spot, people hardly swing their arms; neither need the robot.)
[ "$VX" != 0 ] && [ "$WZ" = 0 ] || { stop_daemon; echo "ok: walked"; exit 0; }
awk -F '\t' "$RECORDING"'
  { l = $(col["q_left_shoulder_pitch"]); r = $(col["q_right_shoulder_pitch"]);
    n++; sl += l; sr += r; sll += l * l; srr += r * r; slr += l * r;
    if (n == 1 || l < lmin) lmin = l; if (n == 1 || l > lmax) lmax = l;
    if (n == 1 || r < rmin) rmin = r; if (n == 1 || r > rmax) rmax = r }
  END {
    cov = slr / n - (sl / n) * (sr / n);
    vl = sll / n - (sl / n) ^ 2; vr = srr / n - (sr / n) ^ 2;
    corr = (vl > 0 && vr > 0) ? cov / sqrt(vl * vr) : 0;
    printf "arms: left shoulder pitch range %.3f rad, right %.3f rad, correlation %.2f\n", lmax - lmin, rmax - rmin, corr;
    exit !(lmax - lmin >= 0.05 && rmax - rmin >= 0.05 && corr < 0)
  }' "$WORK/walk.tsv" || fail "the arms do not swing in coordination"
stop_daemon
echo "ok: walked"
