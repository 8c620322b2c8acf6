#!/bin/sh
# Real-time soak (issue 12 §2): ballastd without --lockstep for SECONDS (default 600), walking
# at 0.5 m/s and standing in turns of 30 s, through the CLI, recording every tick as the binary
# log (issue 18). Never damped, never fallen; at the end the schedule's figures over the whole
# run (from the recording, converted by `ballast log`: each tick's lateness), the daemon's own
# counters, and the recording's size, dropped frames and writer thread's CPU time. With OUTDIR
# the recording and its plots (fig3, contacts, timing, joints) are kept there. Not in CTest (it
# takes the time it says); run it by hand:
#   sh test/acceptance/daemon/realtime_soak.sh build/bin/ballastd build/bin/ballast \
#      profiles/sim-flat.yaml 600 /tmp/soak
# Usage: realtime_soak.sh BALLASTD BALLAST PROFILE [SECONDS [OUTDIR]]
BALLAST_ACCEPTANCE_REALTIME=1
. "$(dirname "$0")/lib.sh"
SECONDS_TOTAL=${4:-600}
OUTDIR=${5:-$WORK}
mkdir -p "$OUTDIR"
RECORDING=$OUTDIR/soak.blog

# CPU seconds (user + system) of the daemon's thread named $1
thread_cpu() {
  for task in /proc/"$DAEMON_PID"/task/*; do
    [ "$(cat "$task/comm")" = "$1" ] || continue
    awk -v hz="$(getconf CLK_TCK)" '{ print ($14 + $15) / hz }' "$task/stat"
    return
  done
  echo 0
}

start_daemon
wait_until "stand" 30 mode_is stand
ballast record start "$RECORDING" >/dev/null || fail "record start"
wall_start=$(date +%s.%N)
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
dropped=$(field recording.dropped)
writer_cpu=$(thread_cpu ballast-writer)
wall=$(calc "$(date +%s.%N) - $wall_start")
ballast record stop >/dev/null || fail "record stop"
echo "daemon: $(timing_line)"
echo "recording: $(ballast log "$RECORDING" --info | grep -E '^(frames|duration|size)' | tr '\n' ' ')"
printf 'recording: %s dropped frames; writer thread %.2f s of CPU in %.0f s (%.2f %% of a core)\n' \
  "$dropped" "$writer_cpu" "$wall" "$(calc "100 * $writer_cpu / $wall")"
# Every tick's lateness over the whole run (telemetry lateness_ms), as percentiles.
ballast log "$RECORDING" --columns lateness_ms |
  awk -F '\t' '/^#/ { next } { print $2 + 0 }' | sort -g >"$WORK/lateness"
awk '{ v[NR] = $1 } END {
  printf "whole run: %d ticks, lateness p50 %.3f p99 %.3f p99.9 %.3f max %.3f ms\n",
    NR, v[int(NR * 0.5)], v[int(NR * 0.99)], v[int(NR * 0.999)], v[NR] }' "$WORK/lateness"
echo "daemon warnings:"; grep -E 'warning|error' "$LOG" | tail -20 || true
stop_daemon
if [ "$OUTDIR" != "$WORK" ]; then
  for fig in fig3 contacts timing joints; do
    ballast plot "$RECORDING" --fig "$fig" -o "$OUTDIR/$fig.png" || fail "plot --fig $fig"
  done
  echo "kept: $RECORDING and its plots in $OUTDIR"
fi
echo "ok: $SECONDS_TOTAL s in real time, never damped"
