#!/bin/sh
# ballast-study --quick: every run finishes, study.md carries a row per variant and experiment
# with the paper's outcome and ours, study.json parses with every field of a run, and fig3.png
# and fig5.png are PNG images.  Usage: study_quick.sh BALLAST_STUDY BALLASTD
set -eu
STUDY=$1
BALLASTD=$2
OUT=$(mktemp -d "${TMPDIR:-/tmp}/ballast-study-test.XXXXXX")
trap 'rm -rf "$OUT"' EXIT
fail() { echo "FAIL: $*" >&2; cat "$OUT"/runs/*.log >&2 2>/dev/null || true; exit 1; }

"$STUDY" --quick --jobs 2 --ballastd "$BALLASTD" --out "$OUT" || fail "ballast-study exited $?"

for f in study.md study.json fig3.png fig5.png; do [ -s "$OUT/$f" ] || fail "no $f"; done
for f in fig3.png fig5.png; do
  [ "$(head -c 8 "$OUT/$f" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$f is not a PNG"
done
for v in cH cNH cI; do
  for e in walk_1.0 push_40N; do
    grep -Eq "^\| $e \| $v \| (stable|fell|not reported) \| (stable|fell at [0-9.]+ s) \|( ([0-9.]+|-) \|){6}\$" "$OUT/study.md" ||
      fail "study.md has no well-formed row for $v $e"
  done
done
python3 - "$OUT/study.json" <<'PY' || fail "study.json is not complete"
import json, math, sys
d = json.load(open(sys.argv[1]))
assert d["quick"] is True and len(d["runs"]) == 6, d
for r in d["runs"]:
    assert r["ok"], r
    for k in ("velocity_rms", "limb_error_rms", "height_rms", "roll_rms", "pitch_rms", "yaw_rms", "mpc_ms", "wbc_ms"):
        # None: it fell before the window began
        assert (r[k] is None and r["fell"]) or (isinstance(r[k], float) and math.isfinite(r[k]) and r[k] >= 0), (k, r)
    assert isinstance(r["fell"], bool) and (r["fall_time"] is None) == (not r["fell"]), r
    assert r["paper"] in ("stable", "fell", "not reported"), r
PY
echo "ok: ballast-study --quick wrote the table and both figures"
sed -n '/^| experiment | variant | paper/,/^$/p' "$OUT/study.md"
