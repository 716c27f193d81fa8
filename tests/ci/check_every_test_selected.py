#!/usr/bin/env python3
"""Usage: check_every_test_selected.py BUILD_DIR PROGRAM...

Fails when a GoogleTest test of one of the PROGRAMs (paths of test executables) is selected by no
ctest entry of BUILD_DIR: a test that matches no entry's --gtest_filter never runs in CI (issue 45:
DoublePrecisionOffset.FloatLosesTheHitDoubleFinds ran nowhere). Reads the entries with
`ctest --show-only=json-v1`, each program's tests with --gtest_list_tests, and applies GoogleTest's
filter rules: POSITIVE[-NEGATIVE], patterns separated by ':', '*' any string, '?' one character;
an entry without a filter runs the whole program."""

import json
import os
import re
import subprocess
import sys


def pattern_regex(patterns):
    """One regex for a ':'-separated list of GoogleTest patterns (empty list: matches nothing)."""
    parts = [re.escape(p).replace(r"\*", ".*").replace(r"\?", ".") for p in patterns if p]
    return re.compile("^(?:" + "|".join(parts) + ")$") if parts else None


def selects(gtest_filter, name):
    """Whether GoogleTest's --gtest_filter value selects the test `name` (Suite.Test)."""
    positive, _, negative = gtest_filter.partition("-")
    pos = pattern_regex(positive.split(":")) if positive else pattern_regex(["*"])
    neg = pattern_regex(negative.split(":"))
    return bool(pos and pos.match(name)) and not (neg and neg.match(name))


def listed_tests(program):
    """Every test of a GoogleTest program, as Suite.Test (parameterised names included)."""
    out = subprocess.run([program, "--gtest_list_tests"], check=True, capture_output=True, text=True).stdout
    tests, suite = [], None
    for line in out.splitlines():
        if not line.strip():
            continue
        if not line.startswith(" "):
            suite = line.split("#")[0].strip()
        else:
            tests.append(suite + line.split("#")[0].strip())
    return tests


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    build, programs = sys.argv[1], [p for p in sys.argv[2:] if p]  # an absent optional program: ""
    shown = subprocess.run(["ctest", "--show-only=json-v1"], cwd=build, check=True, capture_output=True, text=True)
    entries = json.loads(shown.stdout)["tests"]
    failed = False
    for program in programs:
        if not os.path.exists(program):
            # Declared but not built in this tree (the sanitizer job builds the suite's programs
            # only): the entries that run it fail by themselves if they run.
            print(f"{os.path.basename(program)}: not built in this tree, not checked")
            continue
        real = os.path.realpath(program)
        filters = []  # one per entry running this program: its filter, "*" without one
        for entry in entries:
            command = entry.get("command") or []
            if command and os.path.basename(command[0]) == "skip_status.sh":
                command = command[1:]  # the entries' launcher (tests/ci/skip_status.sh)
            if not command or os.path.realpath(command[0]) != real:
                continue
            given = [a.split("=", 1)[1] for a in command[1:] if a.startswith("--gtest_filter=")]
            filters.append((entry["name"], given[-1] if given else "*"))
        tests = listed_tests(program)
        orphans = [t for t in tests if not any(selects(f, t) for _, f in filters)]
        name = os.path.basename(program)
        if not filters:
            print(f"{name}: no ctest entry runs it")
            failed = True
        elif orphans:
            print(f"{name}: {len(orphans)} of {len(tests)} tests match no ctest entry's --gtest_filter "
                  f"(entries: {', '.join(n for n, _ in filters)}), so they never run:")
            for t in orphans:
                print(f"  {t}")
            failed = True
        else:
            print(f"{name}: all {len(tests)} tests selected by {len(filters)} entries")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
