#!/usr/bin/env bash
# Shows that CI cannot pass without ../shared, nor with a failure hidden behind a skip: a test that
# needs the shared scenes, run as CI runs it (scripts/ctest-checked, THICKET_REFUSE_SKIPS=1) with
# the scenes pointed elsewhere, must make the run fail; the same run without the refusal passes
# with the test marked skipped; and an entry that fails and also skips fails either way.
#   check_refuse_skips.sh CTEST_CHECKED UNIT_TEST_PROGRAM SKIP_STATUS
set -uo pipefail
checked=$(realpath "$1") program=$(realpath "$2") wrapper=$(realpath "$3")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mkdir "$dir/skips" "$dir/fails"
# One-test ctest projects, so these runs do not touch the build's own Testing/ logs; the entries
# as the build declares them (tests/ci/skip_status.sh, SKIP_RETURN_CODE 77).
cat > "$dir/skips/CTestTestfile.cmake" <<CMAKE
add_test(shared.scenes_present "$wrapper" "$program" "--gtest_filter=SharedScenes.*")
set_tests_properties(shared.scenes_present PROPERTIES SKIP_RETURN_CODE 77)
CMAKE
# A GoogleTest program whose one failure sits beside a skip (the planted bug: before, ctest's
# skip expression marked such an entry skipped, so a run without the refusal passed).
cat > "$dir/fails/CTestTestfile.cmake" <<CMAKE
add_test(fails_and_skips "$wrapper" "/bin/sh" "-c" "echo '[  SKIPPED ] Planted.Skip'; echo '[  FAILED  ] Planted.Failure'; exit 1")
set_tests_properties(fails_and_skips PROPERTIES SKIP_RETURN_CODE 77)
CMAKE
export THICKET_SHARED_SCENES="$dir/no-such-directory"
if THICKET_REFUSE_SKIPS=1 "$checked" "$dir/skips" > "$dir/refused.log" 2>&1; then
  echo "FAIL: a run without the shared scenes passed although skips are refused:"; cat "$dir/refused.log"; exit 1
fi
grep -q "refuses skips" "$dir/refused.log" || { echo "FAIL: no message that says why:"; cat "$dir/refused.log"; exit 1; }
if ! THICKET_REFUSE_SKIPS=0 "$checked" "$dir/skips" > "$dir/allowed.log" 2>&1; then
  echo "FAIL: without the refusal the run should pass with a skip:"; cat "$dir/allowed.log"; exit 1
fi
grep -q "(Skipped)" "$dir/allowed.log" || { echo "FAIL: the test was not marked skipped:"; cat "$dir/allowed.log"; exit 1; }
for refuse in 0 1; do
  if THICKET_REFUSE_SKIPS=$refuse "$checked" "$dir/fails" > "$dir/fails-$refuse.log" 2>&1; then
    echo "FAIL: an entry that failed and skipped passed (THICKET_REFUSE_SKIPS=$refuse):"; cat "$dir/fails-$refuse.log"; exit 1
  fi
  grep -q "Failed" "$dir/fails-$refuse.log" || { echo "FAIL: not marked failed:"; cat "$dir/fails-$refuse.log"; exit 1; }
done
echo "a missing ../shared fails a run that refuses skips and shows as a skip otherwise;" \
     "an entry that fails beside a skip fails either way"
