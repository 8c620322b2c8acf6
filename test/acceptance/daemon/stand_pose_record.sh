#!/bin/sh
# Stand, move the base, take a small push, record it all and plot it: the robot stays up and the
# loop never overruns; stopping leaves no socket.
. "$(dirname "$0")/lib.sh"

start_daemon
wait_until "stand" 30 mode_is stand
ballast stand >/dev/null || fail "stand"
ballast record start "$WORK/run.tsv" >/dev/null || fail "record start"
ballast pose --height 0.83 --pitch 3deg >/dev/null || fail "pose"
wait_until "the base at 0.83 m" 30 near base.position.2 0.83 0.01
wait_until "the base pitched 3 deg" 30 near base.rpy.1 0.0524 0.01
near truth.base.position.2 0.83 0.015 || fail "the simulated base is not where the estimate says"
ballast push --force 15,0,0 --duration 200ms >/dev/null || fail "push"
sim_time_passes 1.5
ballast pose >/dev/null || fail "pose back to nominal"
wait_until "the nominal height" 30 near base.position.2 0.89 0.01
ballast record stop >/dev/null || fail "record stop"
healthy
[ "$(field mode)" = stand ] || fail "not standing"
ballast plot "$WORK/run.tsv" -o "$WORK/run.png" >/dev/null || fail "plot"
[ "$(head -c 4 "$WORK/run.png" | tail -c 3)" = PNG ] || fail "no PNG"
frames=$(grep -vc '^#' "$WORK/run.tsv")
[ "$frames" -gt 2000 ] || fail "only $frames frames recorded"
stop_daemon
echo "ok: stood, posed, took a push, $frames frames recorded and plotted"
