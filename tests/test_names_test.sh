#!/usr/bin/env bash
# No test case name holds a ';': ctest keeps a list in a ';'-separated string, so such a test is
# registered under the part before it, matches no test case and "passes" without running.
# Usage: test_names_test.sh TEST_PROGRAM...
set -u
status=0
for program in "$@"; do
  names=$("$program" --list-test-cases --no-version 2>&1 | grep -F ';')
  if [ -n "$names" ]; then
    echo "$(basename "$program"): test names with ';' (ctest would not run them):"
    echo "$names"
    status=1
  fi
done
[ $status -eq 0 ] && echo "no test name holds a ';'"
exit $status
