# Helpers for the acceptance scripts: start ballastd in a scratch directory (lockstep, or real
# time with BALLAST_ACCEPTANCE_REALTIME=1), drive it with ballast, wait on status fields (no
# sleeps where a status poll works), fail loudly. Real time on a busy host:
# BALLAST_ACCEPTANCE_LOAD=N keeps N processes computing at normal priority from before the daemon
# starts to the end (more than the cores: other programs on the robot's computer); without a
# real-time priority for the loop (refused) such a run is skipped (exit 77).
# Lockstep is held (ballastd --lockstep --hold): controller time passes only when a helper here
# runs it on (`ballast advance`), so a command lands at the controller time the script reaches,
# whatever the machine's load, and a run is the same every time. Real time polls the wall clock.
# Usage from a script:  . "$(dirname "$0")/lib.sh" BALLASTD BALLAST PROFILE
set -eu

BALLASTD=$1
BALLAST_BIN=$2
PROFILE=$3
WORK=$(mktemp -d "${TMPDIR:-/tmp}/ballast-acceptance.XXXXXX")
SOCKET=$WORK/ballastd.sock
LOG=$WORK/ballastd.log
export BALLAST_SOCKET=$SOCKET BALLAST_LEASE_FILE=$WORK/lease
DAEMON_PID=
LOAD_PIDS=

fail() {
  echo "FAIL: $*" >&2
  echo "--- ballastd log ---" >&2
  cat "$LOG" >&2 || true
  [ -n "$DAEMON_PID" ] && kill -KILL "$DAEMON_PID" 2>/dev/null || true
  exit 1
}

cleanup() {
  [ -n "$DAEMON_PID" ] && kill -KILL "$DAEMON_PID" 2>/dev/null || true
  for p in $LOAD_PIDS; do kill -KILL "$p" 2>/dev/null || true; done
  rm -rf "$WORK"
}
trap cleanup EXIT
# sh (dash) skips the EXIT trap when a signal ends it: the daemon and the load would outlive it.
trap 'exit 1' INT TERM HUP

ballast() { "$BALLAST_BIN" "$@"; }

if [ "${BALLAST_ACCEPTANCE_REALTIME:-0}" = 1 ]; then LOCKSTEP=; else LOCKSTEP="--lockstep --hold"; fi

# held: the daemon is a held lockstep one (time passes by advance_by only)
held() { [ -n "$LOCKSTEP" ]; }
# advance_by SECONDS: a held daemon runs that much controller time on (and the call returns
# there); in real time, the wall clock does it
advance_by() {
  if held; then ballast advance "+$1" >/dev/null || fail "advance +$1 at t=$(field t)"; else sleep "$1"; fi
}

# start_daemon [OPTIONS...]: ballastd on $PROFILE (or $DAEMON_PROFILE), waits for its socket
start_daemon() {
  # Once per script: a daemon started again runs under the same load.
  if [ -z "$LOAD_PIDS" ] && [ -z "$LOCKSTEP" ]; then
    i=0
    while [ "$i" -lt "${BALLAST_ACCEPTANCE_LOAD:-0}" ]; do
      sh -c 'while :; do :; done' &
      LOAD_PIDS="$LOAD_PIDS $!"
      i=$((i + 1))
    done
  fi
  "$BALLASTD" --profile "${DAEMON_PROFILE:-$PROFILE}" $LOCKSTEP --socket "$SOCKET" "$@" 2>"$LOG" &
  DAEMON_PID=$!
  i=0
  until ballast status --get mode >/dev/null 2>&1; do
    i=$((i + 1))
    [ $i -lt 300 ] || fail "ballastd did not come up"
    kill -0 "$DAEMON_PID" 2>/dev/null || fail "ballastd exited at start"
    sleep 0.05
  done
  if [ -n "$LOAD_PIDS" ] && ! grep -q 'control thread: SCHED_FIFO' "$LOG"; then
    echo "SKIP: the host refused the loop a real-time priority; a busy host starves it" >&2
    exit 77
  fi
}

# wait_until DESCRIPTION SECONDS COMMAND...: runs COMMAND until it succeeds (polling status),
# every 0.05 s of controller time (held) or wall time, for at most SECONDS of it.
wait_until() {
  what=$1 limit=$2
  shift 2
  i=0
  until "$@"; do
    i=$((i + 1))
    [ $i -lt $((limit * 20)) ] || fail "timed out waiting for $what"
    advance_by 0.05
  done
}

field() { ballast status --get "$1"; }
mode_is() { [ "$(field mode)" = "$1" ]; }
# near FIELD VALUE TOLERANCE: |field - value| <= tolerance
near() { awk -v a="$(field "$1")" -v b="$2" -v tol="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= tol) }'; }
# time_after T0 D: the controller time is at least T0 + D
time_after() { awk -v t="$(field t)" -v t0="$1" -v d="$2" 'BEGIN { exit !(t >= t0 + d) }'; }
# sim_time_passes SECONDS: waits until the controller time has advanced that much
# (wall-time limit: 60 s, or 8 s per simulated second when longer: lockstep under a loaded
# CI machine runs well below real time)
sim_time_passes() {
  if held; then advance_by "$1"; return; fi
  wait_until "$1 s of controller time" "$(awk -v d="$1" 'BEGIN { l = 8 * d; print (l > 60 ? int(l) : 60) }')" \
    time_after "$(field t)" "$1"
}

healthy() {
  [ "$(field fallen)" = false ] || fail "the robot fell"
  [ "$(field mode)" != damp ] || fail "the robot was damped: $(field faults)"
}

# The real-time schedule in one line (status timing).
timing_line() {
  awk -v p50="$(field timing.lateness_ms.p50)" -v p99="$(field timing.lateness_ms.p99)" \
      -v max="$(field timing.lateness_ms.max)" -v w="$(field timing.window_s)" \
      -v late="$(field timing.late_ticks)" -v n="$(field timing.ticks)" \
      -v skipped="$(field timing.skipped_periods)" -v hs="$(field timing.host_stalls)" \
      -v hsmax="$(field timing.host_stall_ms_max)" \
      'BEGIN { printf "lateness p50 %.3f p99 %.3f max %.3f ms over %.1f s; late ticks %d of %d; skipped periods %d; host stalls the world waited for %d (max %.1f ms)\n", p50, p99, max, w, late, n, skipped, hs, hsmax }'
}

stop_daemon() {
  kill -TERM "$DAEMON_PID"
  wait "$DAEMON_PID" || fail "ballastd exited $? after SIGTERM"
  DAEMON_PID=
  [ ! -e "$SOCKET" ] || fail "the socket was left behind"
}

# calc EXPRESSION: awk arithmetic on numbers (prints the result)
calc() { awk "BEGIN { print $1 }"; }
# within VALUE TARGET FRACTION: |value - target| <= fraction * |target|
within() { awk -v a="$1" -v b="$2" -v f="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; t = b < 0 ? -b : b; exit !(d <= f * t) }'; }

# never_damped: fails when the robot is damped or has fallen (the faults named)
never_damped() {
  [ "$(field mode)" != damp ] || fail "damped at t=$(field t), base at x=$(field base.position.0): $(field faults)"
  [ "$(field fallen)" = false ] || fail "fell at t=$(field t), base at x=$(field base.position.0)"
}

# for_seconds S: S s of controller time (wall time in real time), never_damped at every poll
for_seconds() {
  t_end=$(calc "$(field t) + $1")
  until time_after "$t_end" 0; do never_damped; advance_by 0.1; done
}

# RECORDING: the start of an awk program (awk -F '\t' "$RECORDING"'...') over a telemetry
# recording (`ballast record` TSV): col["name"] is each field's column, the comment lines skipped.
RECORDING='/^# t\t/ { for (i = 2; i <= NF; ++i) col[$i] = i; col["t"] = 1; next }
/^#/ { next }
'

# motion_report TSV: the ground-truth base over a recorded telemetry file, for the README's
# backend table: mean base height, its RMS about that mean, and the RMS tilt (roll and pitch).
motion_report() {
  awk -F '\t' "$RECORDING"'
    { z = $(col["true_z"]); r = $(col["true_roll"]); p = $(col["true_pitch"]);
      n++; sz += z; szz += z * z; st += r * r + p * p }
    END {
      if (n == 0) { print "motion: no samples"; exit }
      m = sz / n; v = szz / n - m * m; if (v < 0) v = 0
      printf "motion: base height %.3f m (RMS about it %.1f mm), tilt RMS %.2f deg over %d samples\n", m, 1000 * sqrt(v), sqrt(st / n) * 45 / atan2(1, 1), n
    }' "$1"
}
