#!/bin/sh
# The state estimator while walking (issue 7): `ballast walk --vx VX` for 20 s of simulated time
# with the controller on the estimate (sim-flat: realistic sensor noise and biases). From the
# telemetry, estimate against ground truth over the recorded 20 s: horizontal position drift
# ≤ 2 % of the distance walked, velocity RMS error ≤ 0.05 m/s, height error ≤ 1 cm, roll and
# pitch errors ≤ 1°.  Usage: estimate_walk.sh BALLASTD BALLAST PROFILE VX
. "$(dirname "$0")/lib.sh"
VX=$4

start_daemon
wait_until "stand" 30 mode_is stand
[ "$(field profile)" = sim-flat ] || fail "expected the default profile"
ballast record start "$WORK/walk.tsv" >/dev/null || fail "record start"
ballast walk --vx "$VX" --for 22s >/dev/null || fail "walk"
sim_time_passes 20
ballast record stop >/dev/null || fail "record stop"
healthy
awk -F '\t' -v deg="$(calc "atan2(0, -1) / 180")" "$RECORDING"'
  function abs(a) { return a < 0 ? -a : a }
  $(col["mode"]) != 3 { next }   # walk
  {
    ex = $(col["x"]) - $(col["true_x"]); ey = $(col["y"]) - $(col["true_y"])
    if (n == 0) { ex0 = ex; ey0 = ey; x0 = $(col["true_x"]); y0 = $(col["true_y"]) }
    n++
    d = $(col["true_x"]) - px; e = $(col["true_y"]) - py
    if (n > 1) dist += sqrt(d * d + e * e)
    px = $(col["true_x"]); py = $(col["true_y"])
    for (i = 0; i < 3; ++i) {
      a = substr("xyz", i + 1, 1)
      dv = $(col["v" a]) - $(col["true_v" a]); sv += dv * dv
    }
    h = abs($(col["z"]) - $(col["true_z"])); if (h > hmax) hmax = h
    r = abs($(col["roll"]) - $(col["true_roll"])); if (r > rmax) rmax = r
    p = abs($(col["pitch"]) - $(col["true_pitch"])); if (p > pmax) pmax = p
    exn = ex; eyn = ey
  }
  END {
    drift = sqrt((exn - ex0) ^ 2 + (eyn - ey0) ^ 2)
    vrms = sqrt(sv / n)
    printf "walked %.2f m in %d samples: drift %.3f m (%.2f %%), velocity RMS error %.4f m/s, height error max %.4f m, roll error max %.3f deg, pitch error max %.3f deg\n", dist, n, drift, 100 * drift / dist, vrms, hmax, rmax / deg, pmax / deg
    exit !(n > 15000 && drift <= 0.02 * dist && vrms <= 0.05 && hmax <= 0.01 && rmax <= deg && pmax <= deg)
  }' "$WORK/walk.tsv" || fail "the estimate is off the bars"
stop_daemon
echo "ok: the estimate held while walking"
