#!/bin/sh
# Runs one node test file with node's test runner, printing TAP.
# Without node or the npm test tools the test is skipped, unless
# MER_REQUIRE_ALL=1 (set by ./quickstart test) turns a skip into a failure.
test_file=$1
missing=
[ -n "$NODE" ] && [ -x "$NODE" ] || missing="node"
[ -d "$NODE_PATH/playwright-core" ] && [ -d "$NODE_PATH/gltf-validator" ] ||
  missing="${missing:+$missing, }npm test tools in $NODE_PATH (run npm ci)"
if [ -n "$missing" ]; then
  if [ "${MER_REQUIRE_ALL:-0}" = 1 ]; then
    echo "Bail out! missing $missing"
    exit 1
  fi
  echo "1..0 # SKIP missing $missing"
  exit 0
fi
exec "$NODE" --test --test-reporter=tap "$test_file"
