#!/usr/bin/env bash
# Usage: check_consumer.sh package BUILD_DIR SOURCE_DIR   (install, then find_package)
#        check_consumer.sh subdirectory BUILD_DIR SOURCE_DIR
set -euo pipefail
via=$1 build=$2 source=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ "$via" = package ]; then
  cmake --install "$build" --prefix "$work/prefix" >/dev/null
  # The bench is the tool's: neither its headers nor its code are installed, and the tracing
  # library holds no rendering or reporting code (that is thicket::render's, or the bench's).
  if [ -e "$work/prefix/include/thicket/bench" ]; then echo "bench headers were installed" >&2; exit 1; fi
  [ -f "$work/prefix/include/thicket/render/camera.h" ] || { echo "render headers are missing" >&2; exit 1; }
  lib=$(find "$work/prefix" -name 'libthicket.a' | head -n1)
  if [ -n "$lib" ] && ar t "$lib" | grep -E '(svg_plot|compare_report|bench_tables|camera|font|views)\.cpp' >&2; then
    echo "libthicket.a holds rendering or bench objects" >&2; exit 1
  fi
  cmake -S "$source/tests/package/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
else
  # The library is compiled again here, with the main build's flags and compiler launcher: where
  # that is ccache (scripts/test), every object is a cache hit. Only what the consumer links is built.
  # The main build's unity directory too: the units' paths are part of what ccache hashes.
  launcher=$(sed -n 's/^CMAKE_CXX_COMPILER_LAUNCHER:[A-Z]*=//p' "$build/CMakeCache.txt")
  unity=$(sed -n 's/^THICKET_UNITY_DIR:[A-Z]*=//p' "$build/CMakeCache.txt")
  cmake -S "$source/tests/package/consumer" -B "$work/consumer" -DTHICKET_VIA=subdirectory \
        -DTHICKET_SOURCE="$source" -DCMAKE_BUILD_TYPE=Release ${launcher:+"-DCMAKE_CXX_COMPILER_LAUNCHER=$launcher"} \
        ${unity:+"-DTHICKET_UNITY_DIR=$unity"} >/dev/null
fi
cmake --build "$work/consumer" -j2 --target consumer >/dev/null
"$work/consumer/consumer"
