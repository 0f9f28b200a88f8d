#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder image
# (the zip is unpacked in /autograder/source). It installs the packages,
# makes the sandbox accounts, builds the grader into a root-only folder,
# warms a build of the starter kit (without the grader) for the
# submissions' builds, makes every secret root-only and records the hashes
# of everything the grading depends on (run_autograder checks them).
#
#   /autograder/            0711: others may pass through, not list
#     source/               0700  the zip: references, case lists, hidden cases
#     pt/                   0700  bin/grader, the grader's build, kit/ (the
#                                 build tree's pristine copy), warm-build/,
#                                 manifest.txt (the hashes), accounts.txt
#     sandbox/              0755  tree/ (root's, read-only to the accounts)
#                                 and build/ (pt-build's): where a submission
#                                 is built
#
# Environment (for testing outside Gradescope):
#   AUTOGRADER_ROOT=DIR     instead of /autograder
#   AUTOGRADER_SKIP_APT=1   do not install packages (they are there already)
#   AUTOGRADER_GRADER_ONLY=1  build only the grader, no warm build (instructors/batch/grade_folder.sh)
#   AUTOGRADER_SKIP_REFERENCE_CHECK=1  do not check the references
#   AUTOGRADER_RENDER_ACCOUNTS=N  render accounts to make (default 8: one per case graded at a time)
set -euo pipefail

source_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=${AUTOGRADER_ROOT:-/autograder}
pt=$root/pt
sandbox=$root/sandbox
jobs=$(nproc 2>/dev/null || echo 2)
render_accounts=${AUTOGRADER_RENDER_ACCOUNTS:-8}
. "$source_dir/sandbox.sh"

[[ "$render_accounts" =~ ^[1-9][0-9]?$ ]] || {
  echo "setup: error: AUTOGRADER_RENDER_ACCOUNTS=$render_accounts: expected a number from 1 to 99" >&2
  exit 1
}

packages=(build-essential cmake python3 libtinyxml2-dev liblodepng-dev libcli11-dev libopenexr-dev
          libcpp-httplib-dev pkg-config bubblewrap util-linux)
if [ "${AUTOGRADER_SKIP_APT:-0}" != 1 ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update
  apt-get install -y --no-install-recommends "${packages[@]}"
fi

# ---- The accounts submitted code runs as (root only) ----
accounts=()
if [ "$(id -u)" = 0 ]; then
  accounts=("$SANDBOX_BUILD_ACCOUNT")
  for i in $(seq 1 "$render_accounts"); do accounts+=("pt-render$i"); done
  for a in "${accounts[@]}"; do
    getent passwd "$a" >/dev/null ||
      useradd --system --user-group --no-create-home --home-dir /nonexistent --shell /usr/sbin/nologin "$a"
  done
else
  echo "setup: not root: no sandbox accounts (run_autograder sandboxes with bubblewrap as $(id -un), or refuses)"
fi

rm -rf "$pt" "$sandbox"
mkdir -p "$pt/bin" "$sandbox"
chmod 0711 "$root"
chmod 0700 "$pt" "$source_dir"
chmod 0755 "$sandbox"
printf '%s\n' ${accounts[@]+"${accounts[@]}"} >"$pt/accounts.txt"

# ---- The grader, from the whole project, in the root-only folder ----
cmake -S "$source_dir/project" -B "$pt/grader-build" -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_TESTS=OFF
cmake --build "$pt/grader-build" --target grader -j "$jobs"
cp "$pt/grader-build/bin/grader" "$pt/bin/grader"
"$pt/bin/grader" --help >/dev/null

# ---- The tree submissions are built in: the kit's renderer, no grader ----
# Only what the target pathtracer needs: no grader/ (the case list), no
# reference_images/, no scenes.
mkdir -p "$pt/kit"
for d in CMakeLists.txt common stages pathtracer; do
  cp -R "$source_dir/project/$d" "$pt/kit/"
done
chmod -R u=rwX,go=rX "$pt/kit"
if [ "${AUTOGRADER_GRADER_ONLY:-0}" != 1 ]; then
  # Warmed at the path every submission is built at, so that its CMake
  # files stay valid when run_autograder copies it back.
  cp -a "$pt/kit" "$sandbox/tree"
  cmake -S "$sandbox/tree" -B "$sandbox/build" -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_TESTS=OFF
  cmake --build "$sandbox/build" --target pathtracer -j "$jobs"
  rm -f "$sandbox/build/bin/pathtracer"
  cp -a "$sandbox/build" "$pt/warm-build"
  echo "$sandbox" >"$pt/warm-build.path"
  rm -rf "$sandbox/tree" "$sandbox/build"
fi

# ---- Every case's reference must load and match its case's definition ----
# A "pathtracer" that renders nothing fails every case, and a missing or
# stale reference makes the case an error (exit status 2). Takes a second.
hidden=()
if [ -f "$source_dir/hidden/cases.txt" ]; then
  hidden=(--hidden-cases "$source_dir/hidden/cases.txt" --hidden-references "$source_dir/hidden/references")
fi
if [ "${AUTOGRADER_SKIP_REFERENCE_CHECK:-0}" != 1 ] && ! grep -q '^reference check: off' "$source_dir/VERSION" 2>/dev/null; then
  check=$(mktemp -d)
  rc=0
  "$pt/bin/grader" run --pathtracer "$(type -P true)" -q -o "$check/out" \
    --cases "$source_dir/project/grader/cases.txt" --references "$source_dir/project/reference_images" \
    --scenes "$source_dir/project/scenes" ${hidden[@]+"${hidden[@]}"} >"$check/log" 2>&1 || rc=$?
  if [ "$rc" -ne 1 ]; then
    grep -w error "$check/out/report.txt" 2>/dev/null || cat "$check/log"
    echo "setup: error: the references do not fit the cases (grader exit status $rc): remake them and the zip" >&2
    exit 1
  fi
  rm -rf "$check"
  echo "setup: every case has its reference${hidden[*]:+ (hidden cases too)}"
fi

# ---- The hashes run_autograder checks after the build and after grading ----
manifest_paths=("$source_dir" "$pt/bin" "$pt/kit")
[ -e "$root/run_autograder" ] && manifest_paths+=("$root/run_autograder")
printf '%s\n' "${manifest_paths[@]}" >"$pt/manifest_paths.txt"
python3 "$source_dir/submission_tools.py" manifest "${manifest_paths[@]}" >"$pt/manifest.txt"
echo "setup: grader in $pt/bin/grader; hashes of $(wc -l <"$pt/manifest.txt") files and folders in $pt/manifest.txt"
