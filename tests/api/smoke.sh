#!/bin/sh
# The README's curl pipeline, as a CI smoke test would run it against a running
# meristemd: create a session, grow it, brush it, prune a branch picked from the
# skeleton (with jq), save the GLB, undo the prune.
# Fails on any non-2xx. Usage: smoke.sh [BASE_URL] (default http://127.0.0.1:8080)
# Under `make check` it starts its own daemon on a free port and speaks TAP.
set -eu
base=${1:-}
own=
if [ -z "$base" ] && [ -n "${MERISTEMD:-}" ]; then
  data=$(mktemp -d)
  log=$data/log
  # The log exists before the daemon starts: the redirection below happens in
  # the background child, and the loop's first read may come before it.
  : >"$log"
  "$MERISTEMD" --port 0 --web-root "$MER_WEB_ROOT" --data-dir "$data" >"$log" 2>&1 &
  own=$!
  trap 'kill $own 2>/dev/null; rm -rf "$data"' EXIT
  for _ in $(seq 100); do
    port=$(sed -n 's|.*listening on http://[^:]*:\([0-9]*\)/.*|\1|p' "$log")
    [ -n "$port" ] && break
    sleep 0.1
  done
  base=http://127.0.0.1:$port
fi
base=${base:-http://127.0.0.1:8080}
out=${MER_ARTIFACTS:-.}
echo "1..7"

# --fail-with-body: any non-2xx fails the pipeline and shows the problem detail.
c() { curl -sS --fail-with-body -H 'Content-Type: application/json' "$@"; }
n=0
ok() { n=$((n + 1)); echo "ok $n - $1"; }

# 1. Create a session: the response's Location names it.
id=$(c -X POST "$base/v1/sessions" -d '{"preset": "fig7-bh-0.54", "seed": 42, "ttl_seconds": 3600}' |
  jq -r .id)
[ -n "$id" ] && ok "created session $id"

# 2. Grow it 12 steps.
c -X POST "$base/v1/sessions/$id/edits" -d '{"op": "step", "count": 12}' | grep -q '"step":12' &&
  ok "grew 12 steps"

# 3. Brush a cloud of markers above the crown, then grow into it.
c -X POST "$base/v1/sessions/$id/edits" -d '{"edits": [
  {"op": "add_markers", "center": [0, 40, 0], "radius": 6, "pressure": 0.9, "count": 200},
  {"op": "step", "count": 3}]}' | grep -q '"step":15' && ok "brushed and grew"

# 4. Prune the lowest living first-order branch, picked from the skeleton.
node=$(c "$base/v1/sessions/$id/skeleton?alive=1" |
  jq '[.nodes[] | select(.order == 1)] | min_by(.base[1]) | .id')
c -X POST "$base/v1/sessions/$id/edits" -d "{\"op\": \"prune\", \"node\": $node}" |
  jq -e '.revision == 3' >/dev/null && ok "pruned the lowest branch, node $node"

# 5. Save the GLB.
c -o "$out/smoke-tree.glb" "$base/v1/sessions/$id/snapshot.glb?leaves=1"
head -c 4 "$out/smoke-tree.glb" | grep -q glTF && ok "saved $out/smoke-tree.glb"

# 6. The session summary says where it stands.
c "$base/v1/sessions/$id" | grep -q '"revision":3' && ok "summary at revision 3"

# 7. Undo the prune: revision 2's tree again, as revision 4, its GLB byte for byte.
c -X POST "$base/v1/sessions/$id/edits" -d '{"op": "revert", "revision": 2}' |
  jq -e '.revision == 4 and .step == 15' >/dev/null &&
  c -o "$out/smoke-undone.glb" "$base/v1/sessions/$id/snapshot.glb?leaves=1" &&
  c -o "$out/smoke-r2.glb" "$base/v1/sessions/$id/snapshot.glb?leaves=1&revision=2" &&
  cmp -s "$out/smoke-undone.glb" "$out/smoke-r2.glb" && ok "undid the prune, byte for byte"
