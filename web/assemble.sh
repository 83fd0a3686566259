#!/bin/sh
# Assembles the web root meristemd serves.
# usage: assemble.sh WEB_SRC NODE_MODULES OUT FILE... -- THREE_PART...
set -eu
src=$1 modules=$2 out=$3
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
  case $1 in */*) mkdir -p "$out.tmp/${1%/*}" ;; esac
  cp "$src/$1" "$out.tmp/$1"
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
