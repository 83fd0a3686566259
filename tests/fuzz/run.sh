#!/bin/sh
# Runs each libFuzzer harness over its seed corpus and prints TAP, one line per
# harness. Usage: run.sh SRCDIR HARNESS...
#   FUZZ_SMOKE_RUNS  inputs per harness (default 500): a smoke test
#   FUZZ_SECONDS     instead, run each this long (a release run, README.md)
# New inputs that find coverage go to tests/fuzz/found/NAME in the build folder
# (kept between release runs, emptied before a smoke run so that it always runs
# the same inputs); a crash leaves its input in tests/fuzz/crash-* there.
srcdir=$1; shift
echo "1..$#"
n=0 status=0
for h in "$@"; do
  n=$((n + 1))
  name=$(basename "$h" | sed 's/^fuzz_//')
  found=tests/fuzz/found/$name
  [ -n "${FUZZ_SECONDS:-}" ] || rm -rf "$found"
  mkdir -p "$found"
  seeds=""
  [ -d "$srcdir/tests/fuzz/corpus/$name" ] && seeds="$srcdir/tests/fuzz/corpus/$name"
  case $name in edits|spec) seeds="$seeds $srcdir/proto/examples" ;; esac
  # A smoke run is the same every time (seed 1); a release run takes a new seed.
  if [ -n "${FUZZ_SECONDS:-}" ]; then limit="-max_total_time=$FUZZ_SECONDS" seed="-seed=0"
  else limit="-runs=${FUZZ_SMOKE_RUNS:-500}" seed="-seed=1"; fi
  log=tests/fuzz/$name.log
  if "$h" "$seed" "$limit" -max_len=65536 -timeout=20 -rss_limit_mb=2048 \
       -artifact_prefix=tests/fuzz/ -print_final_stats=1 "$found" $seeds >"$log" 2>&1; then
    stats=$(grep -E '^#[0-9]+.*(DONE|cov:)' "$log" | tail -n 1 | sed 's/  */ /g')
    echo "ok $n - fuzz_$name # $stats"
  else
    echo "not ok $n - fuzz_$name (see $log)"
    grep -E 'ERROR|SUMMARY|Test unit written' "$log" | head -n 5 | sed 's/^/# /'
    status=1
  fi
done
exit $status
