#!/usr/bin/env bash
# Installs the Debian packages the project needs, when they are missing.
# As root it runs apt-get; otherwise it prints the exact command to run.
#   scripts/setup.sh               everything: also the viewer's npm packages
#                                  and, where instructors/ is, Chromium
#   scripts/setup.sh --build-only  what configuring and building needs, no more
#                                  (scripts/run.sh: the renderer and the grader)
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
build_only=0
case "${1:-}" in
  "") ;;
  --build-only) build_only=1 ;;
  *) echo "usage: scripts/setup.sh [--build-only]" >&2; exit 2 ;;
esac
# Configuring needs every library the CMake files look for (the viewer's
# cpp-httplib and the tests' Catch2 too), even to build one target.
# bubblewrap: the sandbox of the grader's renders and of the Gradescope
# package's builds (instructors/gradescope/README.md, "Security").
packages=(build-essential cmake python3 libtinyxml2-dev liblodepng-dev catch2 libcli11-dev libopenexr-dev
          libcpp-httplib-dev pkg-config bubblewrap)
if [ "$build_only" = 0 ]; then
  # ccache: the test suite builds the same files again in the kits' trees
  # (CMakeLists.txt, PT_CCACHE).
  packages+=(nodejs ccache)
  # npm comes with some nodejs packages; Debian's is its own package.
  command -v npm >/dev/null 2>&1 || packages+=(npm)
  # The instructors' tests check the viewer's and the write-up's pages in
  # headless Chromium; the starter kit, which has no instructors/ folder,
  # does not need it.
  if [ -d "$root/instructors" ]; then
    packages+=(chromium)
  fi
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

# The viewer's page and browser tests use three and playwright-core from
# npm, exactly the versions of viewer/web/package-lock.json (npm ci; no
# browser is downloaded: the tests drive Debian's chromium).
npm_packages() {
  local web="$root/viewer/web" omit=()
  [ "$build_only" = 0 ] && [ -f "$web/package-lock.json" ] || return 0
  # Without instructors/ (the starter kit) only the page's own packages:
  # playwright-core drives the browser tests, which the kit does not have.
  [ -d "$root/instructors" ] || omit=(--omit=dev)
  if [ ! -f "$web/node_modules/.package-lock.json" ] || [ "$web/package-lock.json" -nt "$web/node_modules/.package-lock.json" ]; then
    echo "setup: installing the viewer's npm packages (npm ci in viewer/web)"
    (cd "$web" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci "${omit[@]}" --no-audit --no-fund --loglevel=error)
  fi
}

if [ ${#missing[@]} -eq 0 ]; then
  npm_packages
  exit 0
fi

cmd="apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
  npm_packages
elif command -v sudo >/dev/null 2>&1 && [ -t 0 ]; then
  echo "setup: installing ${missing[*]} with sudo"
  sudo sh -c "DEBIAN_FRONTEND=noninteractive $cmd"
  npm_packages
else
  echo "setup: missing packages: ${missing[*]}" >&2
  echo "setup: run as root:  sudo sh -c '$cmd'" >&2
  exit 1
fi
