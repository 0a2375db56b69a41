#!/usr/bin/env bash
# Regenerates the pictures the README shows, from a Release build in build/.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
bin="$here/../../build/bin"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/btf-datagen" --preset plastic-red --seed 1 -o "$work/plastic-red.binary" >/dev/null
"$bin/btf" plot "$work/plastic-red.binary" -o "$here/plastic-red.png"
