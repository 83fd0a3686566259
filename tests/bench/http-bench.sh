#!/bin/sh
# meristemd under load on loopback, measured with wrk (Debian package wrk).
# Not a test: it prints figures. Usage: tests/bench/http-bench.sh [MERISTEMD]
#   - small JSON requests: GET /v1/health and GET /v1/sessions/{id}
#   - one-step edits of a 10,000-internode session answered with the GLB (p99)
#   - that session's snapshot with implicit junctions, on lent cores and on one
#   - 1,000 idle young sessions: RSS, and the time to restore them on start
set -eu
exe=${1:-server/meristemd}
if ! command -v wrk >/dev/null; then
  echo "http-bench: wrk is not installed (apt-get install wrk)" >&2
  exit 1
fi
data=$(mktemp -d)
log=$data/log
web=$(mktemp -d)
trap 'kill $pid 2>/dev/null; rm -rf "$data" "$web"' EXIT

start() {
  # A fresh log before the daemon starts: the redirection below happens in the
  # background child, so the loop may read first (and must not read an earlier
  # start's port).
  : >"$log"
  "$exe" --port 0 --web-root "$web" --data-dir "$data/j" --quiet --threads 2 --workers 2 \
    --max-sessions 100000 --max-steps 100000 "$@" >"$log" 2>&1 &
  pid=$!
  for _ in $(seq 300); do
    port=$(sed -n 's|.*listening on http://[^:]*:\([0-9]*\)/.*|\1|p' "$log")
    [ -n "$port" ] && break
    sleep 0.05
  done
  base=http://127.0.0.1:$port
}
post() { curl -sS --fail-with-body -H 'Content-Type: application/json' -X POST "$@"; }

start
id=$(post "$base/v1/sessions" -d '{"preset":"fig7-bh-0.54","seed":1}' | sed -n 's/.*"id":"\([0-9a-f]*\)".*/\1/p')
# Grow to about 10,000 internodes.
while :; do
  n=$(post "$base/v1/sessions/$id/edits" -d '{"op":"step","count":1}' | sed -n 's/.*"internodes":\([0-9]*\).*/\1/p')
  [ "$n" -ge 10000 ] && break
done
echo "session $id: $n internodes"

echo "== GET /v1/health (wrk -t2 -c64 -d5s)"
wrk -t2 -c64 -d5s "$base/v1/health" | grep -E 'Requests/sec|Latency'
echo "== GET /v1/sessions/{id} (wrk -t2 -c64 -d5s)"
wrk -t2 -c64 -d5s "$base/v1/sessions/$id" | grep -E 'Requests/sec|Latency'
echo "== GET /v1/health, a new connection for each (wrk -t1 -c1 -d5s, Connection: close)"
wrk -t1 -c1 -d5s -H 'Connection: close' "$base/v1/health" | grep -E 'Requests/sec|Latency'
echo "== GET /v1/health, one kept-alive connection (wrk -t1 -c1 -d5s)"
wrk -t1 -c1 -d5s "$base/v1/health" | grep -E 'Requests/sec|Latency'
curl -sS -o /dev/null "$base/v1/sessions/$id/snapshot.glb"
size=$(curl -sS -o /dev/null -w '%{size_download}' "$base/v1/sessions/$id/snapshot.glb")
echo "== GET snapshot.glb of that session ($size bytes, cached), one connection (wrk -t1 -c1 -d5s)"
wrk -t1 -c1 -d5s "$base/v1/sessions/$id/snapshot.glb" | grep -E 'Requests/sec|Latency|Transfer/sec'

# A snapshot with implicit junctions, each of eight variants (colour ×
# quantize) meshed anew: the patches on the cores lent to it (the default)
# and, in a second daemon, on one thread (--patch-threads 1). Two untimed
# variants (detail 2 and 4) first, so that each daemon's heap is faulted in.
implicit_latency() {
  for detail in 2 4; do
    curl -sS -o /dev/null "$base/v1/sessions/$id/snapshot.glb?junctions=implicit&detail=$detail"
  done
  : >"$data/times"
  for c in none order light age; do
    for q in 0 1; do
      curl -sS -o /dev/null -w '%{time_total}\n' \
        "$base/v1/sessions/$id/snapshot.glb?junctions=implicit&color=$c&quantize=$q" >>"$data/times"
    done
  done
  sort -n "$data/times" | awk '{ t[NR] = $1 * 1000 } END {
    printf "   min %.1f ms  median %.1f ms  max %.1f ms  (%d variants)\n", t[1], (t[int((NR + 1) / 2)] + t[int(NR / 2) + 1]) / 2, t[NR], NR }'
}
echo "== GET snapshot.glb?junctions=implicit of that session, 8 uncached variants, patches on the lent cores"
implicit_latency

# A one-step edit changes the tree, so each sample needs its own copy of the
# 10,000-internode tree: the same preset, seed and steps give the same tree.
steps=$(curl -sS "$base/v1/sessions/$id" | sed -n 's/.*"step":\([0-9]*\).*/\1/p')
edit_latency() {
  echo "== one-step edit answered with the GLB, 100 copies of that tree (step $steps), $1"
  echo "   (after 5 warm-up edits: the first one or two after start fault the heap in, ~35 ms)"
  : >"$data/times"
  i=-5
  while [ $i -lt 100 ]; do
    sid=$(post "$base/v1/sessions" -d '{"preset":"fig7-bh-0.54","seed":1}' | sed -n 's/.*"id":"\([0-9a-f]*\)".*/\1/p')
    post "$base/v1/sessions/$sid/edits" -d "{\"op\":\"step\",\"count\":$steps}" >/dev/null
    t=$(post -o /dev/null -w '%{time_total}' -H 'Accept: model/gltf-binary' \
      "$base/v1/sessions/$sid/edits" -d '{"op":"step","count":1}')
    [ $i -ge 0 ] && echo "$t" >>"$data/times"
    curl -sS -X DELETE "$base/v1/sessions/$sid"
    i=$((i + 1))
  done
  sort -n "$data/times" | awk '{ t[NR] = $1 * 1000 } END {
    printf "   p50 %.1f ms  p90 %.1f ms  p99 %.1f ms  max %.1f ms  (%d samples)\n",
           t[int(NR * 0.5)], t[int(NR * 0.9)], t[int(NR * 0.99)], t[NR], NR }'
}
edit_latency "--fsync=always (the default: every reply waits for the disk)"
kill $pid; wait $pid 2>/dev/null || true
rm -rf "$data/j"
start --fsync=interval
id=$(post "$base/v1/sessions" -d '{"preset":"fig7-bh-0.54","seed":1}' | sed -n 's/.*"id":"\([0-9a-f]*\)".*/\1/p')
edit_latency "--fsync=interval"
kill $pid; wait $pid 2>/dev/null || true
rm -rf "$data/j"

echo "== the same with --patch-threads 1"
start --patch-threads 1
id=$(post "$base/v1/sessions" -d '{"preset":"fig7-bh-0.54","seed":1}' | sed -n 's/.*"id":"\([0-9a-f]*\)".*/\1/p')
post "$base/v1/sessions/$id/edits" -d "{\"op\":\"step\",\"count\":$steps}" >/dev/null
implicit_latency
kill $pid; wait $pid 2>/dev/null || true
rm -rf "$data/j"

echo "== 1,000 idle sessions of a young tree (default preset, 5 steps)"
start
i=0
while [ $i -lt 1000 ]; do
  sid=$(post "$base/v1/sessions" -d "{\"seed\":$i}" | sed -n 's/.*"id":"\([0-9a-f]*\)".*/\1/p')
  post "$base/v1/sessions/$sid/edits" -d '{"op":"step","count":5}' >/dev/null
  i=$((i + 1))
done
echo "   RSS with 1,000 sessions: $(awk '/VmRSS/ {printf "%.0f MiB", $2 / 1024}' /proc/$pid/status)"
kill $pid; wait $pid 2>/dev/null || true
start
sed -n 's/^meristemd: \(restored .*\)/   \1/p' "$log"
echo "   RSS after restoring them: $(awk '/VmRSS/ {printf "%.0f MiB", $2 / 1024}' /proc/$pid/status)"
