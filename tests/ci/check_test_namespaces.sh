#!/usr/bin/env bash
# The test programs are unity builds (THICKET_UNITY_TESTS): eight files compiled as one. Two files'
# file-local helpers with one name (seven files had a `soup()`) would then clash, or worse, become
# overloads of each other and a call could pick the other file's. So every test file keeps its
# code in a namespace named after the file: `thicket::STEM`, `thicket::testing::STEM` or `STEM`.
#   check_test_namespaces.sh TESTS_DIR
set -uo pipefail
dir=$1
bad=0
for f in "$dir"/unit/*_test.cpp "$dir"/conformance/*.cpp "$dir"/cli/*.cpp; do
  stem=$(basename "$f" .cpp)
  [ "$f" = "$dir/cli/compare_test.cpp" ] && stem=compare_cli_test
  if ! grep -Eq "^namespace (thicket::(testing::)?)?${stem} \{" "$f"; then
    echo "$f: its code is not in a namespace named after the file (namespace thicket::${stem} {, thicket::testing::${stem} or ${stem})"
    bad=1
  fi
done
[ $bad = 0 ] && echo "every test file keeps its helpers in its own namespace"
exit $bad
