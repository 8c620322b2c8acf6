#!/bin/sh
# Writes the example maps of this directory:
#     sh maps/make-maps.sh build/bin/ballast-mkmap maps
# With --check first, writes them into the given scratch directory and fails unless they are
# byte for byte the ones in this directory (CTest: maps_up_to_date).
# All: 2 cm cells, floor from x = -2 m to 6 m and y = -2 m to 2 m, top of the floor at z = 0.
set -e
check=
if [ "$1" = --check ]; then check=1; shift; fi
usage="usage: make-maps.sh [--check] <ballast-mkmap> <output dir>"
mkmap=${1:?$usage}
out=${2:?$usage}
mkdir -p "$out"
extent="--extent -2 6 -2 2"
"$mkmap" flat  -o "$out/lab-flat.bt"  $extent
"$mkmap" stage -o "$out/lab-stage.bt" $extent --height 0.15 --start 1.5 --depth 2 --width 3
"$mkmap" steps -o "$out/lab-steps.bt" $extent --count 3 --rise 0.10 --run 0.30 --start 1.5 --width 2
"$mkmap" rough -o "$out/lab-rough.bt" $extent --amplitude 0.04 --patch 0.2 --seed 1
if [ -n "$check" ]; then
  here=$(dirname "$0")
  for map in lab-flat lab-stage lab-steps lab-rough; do
    if ! cmp -s "$here/$map.bt" "$out/$map.bt"; then
      echo "$here/$map.bt is not what make-maps.sh writes: regenerate with" >&2
      echo "    sh $0 $mkmap $here" >&2
      exit 1
    fi
  done
  echo "the maps in $here are up to date"
fi
