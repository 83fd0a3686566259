#!/bin/sh
# Assembles the web root meristemd serves.
# usage: assemble.sh TOP_SRCDIR NODE_MODULES OUT web/FILE... -- THREE_PART...
# Each web/FILE (a path from TOP_SRCDIR) goes to OUT/FILE.
set -eu
top=$1 modules=$2 out=$3
shift 3
three="$modules/three"
if [ ! -f "$three/package.json" ]; then
  echo "assemble.sh: three.js is not installed in $modules;" \
       "run 'npm ci' in web/ (./quickstart does)" >&2
  exit 1
fi
rm -rf "$out.tmp"
mkdir -p "$out.tmp"
while [ $# -gt 0 ] && [ "$1" != -- ]; do
  f=${1#web/}
  case $f in */*) mkdir -p "$out.tmp/${f%/*}" ;; esac
  cp "$top/$1" "$out.tmp/$f"
  shift
done
shift
while [ $# -gt 0 ]; do
  dest="$out.tmp/node_modules/three/$1"
  mkdir -p "${dest%/*}"
  cp "$three/$1" "$dest"
  shift
done
cp "$three/package.json" "$out.tmp/node_modules/three/package.json"
touch "$out.tmp/.stamp"
rm -rf "$out"
mv "$out.tmp" "$out"
