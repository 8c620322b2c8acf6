#!/bin/sh
# Real-time soak (issue 12 §2): ballastd without --lockstep for SECONDS (default 600), walking
# at 0.5 m/s and standing in turns of 30 s, through the CLI. Never damped, never fallen; at the
# end the schedule's figures over the whole run (from the recording: each tick's lateness) and
# the daemon's own counters. Not in CTest (it takes the time it says); run it by hand:
#   sh test/acceptance/daemon/realtime_soak.sh build/bin/ballastd build/bin/ballast \
#      profiles/sim-flat.yaml 600
# Usage: realtime_soak.sh BALLASTD BALLAST PROFILE [SECONDS]
BALLAST_ACCEPTANCE_REALTIME=1
. "$(dirname "$0")/lib.sh"
SECONDS_TOTAL=${4:-600}

start_daemon
wait_until "stand" 30 mode_is stand
ballast record start "$WORK/soak.tsv" >/dev/null || fail "record start"
t_start=$(field t)
turn=0
while ! time_after "$t_start" "$SECONDS_TOTAL"; do
  if [ $((turn % 2)) = 0 ]; then
    ballast walk --vx 0.5 --for 30s >/dev/null || fail "walk at t=$(field t)"
  else
    ballast stop >/dev/null || fail "stop at t=$(field t)"
  fi
  for_seconds 30
  turn=$((turn + 1))
  printf 't=%.1f s: %s; %s\n' "$(field t)" "$(field mode)" "$(timing_line)"
done
ballast stop >/dev/null
for_seconds 3
ballast record stop >/dev/null || fail "record stop"
echo "daemon: $(timing_line)"
# Every tick's lateness over the whole run (telemetry lateness_ms), as percentiles.
awk -F '\t' '
  /^# t\t/ { for (i = 2; i <= NF; ++i) col[$i] = i; next }
  /^#/ { next }
  { print $(col["lateness_ms"]) + 0 }' "$WORK/soak.tsv" | sort -g >"$WORK/lateness"
awk '{ v[NR] = $1 } END {
  printf "whole run: %d ticks, lateness p50 %.3f p99 %.3f p99.9 %.3f max %.3f ms\n",
    NR, v[int(NR * 0.5)], v[int(NR * 0.99)], v[int(NR * 0.999)], v[NR] }' "$WORK/lateness"
echo "daemon warnings:"; grep -E 'warning|error' "$LOG" | tail -20 || true
stop_daemon
echo "ok: $SECONDS_TOTAL s in real time, never damped"
