#!/bin/sh
# The installed libmeristem exports the mer_ prefix and nothing else
# (a version script, lib/libmeristem.map), so tinygltf and helpers never leak into users' links.
lib="$MER_BUILDDIR/lib/.libs/libmeristem.so"
echo "1..2"
if [ ! -f "$lib" ]; then
  echo "not ok 1 - $lib exists"; echo "not ok 2 - only mer_ symbols exported # no library"; exit 0
fi
echo "ok 1 - $lib exists"
bad=$(nm -D --defined-only "$lib" | awk '$2 ~ /^[TDBRVW]$/ {print $3}' | grep -v '^mer_' | head -n 10)
count=$(nm -D --defined-only "$lib" | awk '$2 ~ /^[TDBR]$/ {print $3}' | grep -c '^mer_')
if [ -z "$bad" ] && [ "$count" -gt 0 ]; then
  echo "ok 2 - only mer_ symbols exported ($count)"
else
  echo "not ok 2 - only mer_ symbols exported; found others:"; echo "$bad" | sed 's/^/# /'
fi
