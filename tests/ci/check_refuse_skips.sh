#!/usr/bin/env bash
# Shows that CI cannot pass without ../shared: a test that needs the shared scenes, run as CI runs
# it (scripts/ctest-checked, THICKET_REFUSE_SKIPS=1) with the scenes pointed elsewhere, must make
# the run fail; the same run without the refusal passes with the test marked skipped.
#   check_refuse_skips.sh CTEST_CHECKED UNIT_TEST_PROGRAM
set -uo pipefail
checked=$(realpath "$1") program=$(realpath "$2")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# A one-test ctest project, so this run does not touch the build's own Testing/ logs.
cat > "$dir/CTestTestfile.cmake" <<CMAKE
add_test(shared.scenes_present "$program" "--gtest_filter=SharedScenes.*")
set_tests_properties(shared.scenes_present PROPERTIES SKIP_REGULAR_EXPRESSION "\\\\[  SKIPPED \\\\]")
CMAKE
export THICKET_SHARED_SCENES="$dir/no-such-directory"
if THICKET_REFUSE_SKIPS=1 "$checked" "$dir" > "$dir/refused.log" 2>&1; then
  echo "FAIL: a run without the shared scenes passed although skips are refused:"; cat "$dir/refused.log"; exit 1
fi
grep -q "refuses skips" "$dir/refused.log" || { echo "FAIL: no message that says why:"; cat "$dir/refused.log"; exit 1; }
if ! THICKET_REFUSE_SKIPS=0 "$checked" "$dir" > "$dir/allowed.log" 2>&1; then
  echo "FAIL: without the refusal the run should pass with a skip:"; cat "$dir/allowed.log"; exit 1
fi
grep -q "(Skipped)" "$dir/allowed.log" || { echo "FAIL: the test was not marked skipped:"; cat "$dir/allowed.log"; exit 1; }
echo "a missing ../shared fails a run that refuses skips, and shows as a skip otherwise"
