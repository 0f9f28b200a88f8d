#!/usr/bin/env bash
# Rebuilds every scene from its pinned sources and checks that the committed
# files are byte for byte what the generator writes.
#
#   instructors/scene_generator/check_all_scenes.sh           verify only
#   instructors/scene_generator/check_all_scenes.sh --write   regenerate scenes/*.dae first
#
# Steps: fetch_sources.sh (downloads into $PT_SCENE_SOURCES, default
# build/scene-sources, and checks SHA-256 sums; needs the Debian and npm
# registries the first time only), a standalone build of make_scenes in
# $PT_SCENE_GENERATOR_BUILD (default build/scene-generator), then
# `make_scenes --check --require-sources scenes/`, which fails if any scene
# is missing, differs or could not be built.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
export PT_SCENE_SOURCES=${PT_SCENE_SOURCES:-$root/build/scene-sources}
build=${PT_SCENE_GENERATOR_BUILD:-$root/build/scene-generator}

write=0
case "${1:-}" in
  "") ;;
  --write) write=1 ;;
  *) echo "usage: $0 [--write]" >&2; exit 2 ;;
esac

"$here/fetch_sources.sh" "$PT_SCENE_SOURCES"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" >/dev/null
if [[ $write -eq 1 ]]; then
  "$build/make_scenes" --require-sources "$root/scenes"
fi
"$build/make_scenes" --check --require-sources "$root/scenes"
