#!/usr/bin/env bash
# Regenerates the pictures in docs/images from the real data in ../shared.
set -euo pipefail
cd "$(dirname "$0")/.."
gd=build/release/gazedirector
out=docs/images
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"

# Landmarks and head pose on a portrait and on a group photo.
$gd landmarks ../shared/data/images/d30.jpg -o "$tmp/d30.json" --overlay "$tmp/d30.png" -q
$gd landmarks ../shared/data/dlib-faces/bald_guys.jpg -o "$tmp/group.json" --overlay "$tmp/group.png" -q
ffmpeg -v error -y -i "$tmp/d30.png" -vf "crop=400:400:100:130" "$out/landmarks_d30.jpg"
ffmpeg -v error -y -i "$tmp/group.png" -vf "scale=900:-2" -q:v 4 "$out/landmarks_group.jpg"
echo "figures written to $out"
