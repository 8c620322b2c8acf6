#!/bin/sh
# `cmake --install` into a scratch prefix gives a tree that runs on its own: the programs, the
# Simbody plugin (and MuJoCo's where built), the profiles, the robot model, the maps the
# profiles name and the man pages;
# the installed ballastd loads the installed plugin (not the build tree's), stands the robot up
# and stops cleanly. Usage: install.sh BUILD_DIR
set -eu
BUILD=$1
PREFIX=$(mktemp -d "${TMPDIR:-/tmp}/ballast-install.XXXXXX")
cmake --install "$BUILD" --prefix "$PREFIX" >/dev/null
SHARE=$PREFIX/share/ballast
set -- "$PREFIX/bin/ballastd" "$PREFIX/bin/ballast" "$SHARE/profiles/sim-flat.yaml"
. "$(dirname "$0")/../daemon/lib.sh"
trap 'cleanup; rm -rf "$PREFIX"' EXIT

for f in bin/ballastd bin/ballast bin/ballast-mkmap share/man/man1/ballast.1 \
         share/man/man5/ballast-profile.5 share/man/man8/ballastd.8 \
         share/ballast/urdf/humanoid.urdf share/ballast/maps/lab-stage.bt; do
  [ -e "$PREFIX/$f" ] || fail "cmake --install did not install $f"
done
plugin=$(find "$PREFIX" -name libballast_backend_simbody.so)
[ -n "$plugin" ] || fail "cmake --install did not install the simbody plugin"
for p in sim-flat sim-stage sim-rough hardware-example; do
  [ -e "$SHARE/profiles/$p.yaml" ] || fail "profile $p not installed"
done
# Every installed profile that runs here validates against the installed model and maps.
profiles="sim-flat sim-stage sim-rough"
if [ -n "$(find "$PREFIX" -name libballast_backend_mujoco.so)" ]; then
  profiles="$profiles sim-flat-mujoco sim-stage-mujoco"
fi
for p in $profiles; do
  "$PREFIX/bin/ballastd" --profile "$SHARE/profiles/$p.yaml" --check >/dev/null 2>&1 ||
    fail "installed profile $p does not validate: $("$PREFIX/bin/ballastd" --profile "$SHARE/profiles/$p.yaml" --check 2>&1)"
done

start_daemon
grep -q "$plugin" "$LOG" || fail "the installed ballastd did not load the installed plugin $plugin"
wait_until "stand" 30 mode_is stand
healthy
stop_daemon
echo "install: $PREFIX runs on its own"
