#!/usr/bin/env bash
# Installs the Debian packages the project needs, when they are missing.
# As root it runs apt-get; otherwise it prints the exact command to run.
set -euo pipefail

packages=(build-essential cmake python3 libtinyxml2-dev liblodepng-dev catch2 libcli11-dev libopenexr-dev)
# The instructors' tests check the write-up page in headless Chromium; the
# starter kit, which has no instructors/ folder, does not need it.
if [ -d "$(dirname "$0")/../instructors" ]; then
  packages+=(chromium)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

cmd="apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
elif command -v sudo >/dev/null 2>&1 && [ -t 0 ]; then
  echo "setup: installing ${missing[*]} with sudo"
  sudo sh -c "DEBIAN_FRONTEND=noninteractive $cmd"
else
  echo "setup: missing packages: ${missing[*]}" >&2
  echo "setup: run as root:  sudo sh -c '$cmd'" >&2
  exit 1
fi
