#!/usr/bin/env bash
# Sets up and builds (scripts/setup.sh), runs the whole test suite with CTest, then the reduced
# set under AddressSanitizer and UndefinedBehaviorSanitizer (scripts/sanitize.sh --ci).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
if ctest --test-dir build --output-on-failure -j2 --timeout 600; then
  bash scripts/sanitize.sh --ci
  exit 0
fi
# A long log shows only in part; repeat what each failed test printed (its last 60 lines) at the
# end, where it is read first.
failed=build/Testing/Temporary/LastTestsFailed.log
log=build/Testing/Temporary/LastTest.log
echo "=== the failed tests again, from $log ==="
while IFS=: read -r _ name; do
  echo "--- $name"
  awk -v start="Testing: $name" -v end="\"$name\" time elapsed" \
    'index($0, start) {on = 1} on {print} on && index($0, end) {exit}' "$log" | tail -n 60
done < "$failed"
exit 1
