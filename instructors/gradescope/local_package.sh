# Sourced by the scripts that grade through the Gradescope package on this
# machine (bench_sandbox.sh, ../legal_variants/through_package.sh, bash).
#
# local_package TOOL KEEP: sets base (KEEP, or a temporary folder under /tmp
# deleted at exit when KEEP is empty) and ag (base/ag, an AUTOGRADER_ROOT),
# and makes and sets up the package there once: make_autograder.sh
# --unpacked, setup.sh as Gradescope runs it (no apt-get), run_autograder
# copied to its root. A package already set up in KEEP is used again.
# Exits 2 with the log's end when either step fails.
local_package() {
  local tool=$1 keep=$2 here
  here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
  if [ -n "$keep" ]; then
    mkdir -p "$keep"
    base=$(cd "$keep" && pwd)
  else
    base=$(mktemp -d "/tmp/$tool.XXXXXX")
    # shellcheck disable=SC2064
    trap "rm -rf '$base'" EXIT
  fi
  chmod 0711 "$base"
  ag=$base/ag
  [ -f "$ag/pt/manifest.txt" ] && return 0
  rm -rf "$ag"
  echo "$tool: making and setting up the package in $ag (once)"
  "$here/make_autograder.sh" --unpacked "$ag/source" >"$base/zip.log" 2>&1 || { cat "$base/zip.log"; exit 2; }
  (cd "$ag/source" && AUTOGRADER_ROOT=$ag AUTOGRADER_SKIP_APT=1 bash ./setup.sh) >"$base/setup.log" 2>&1 ||
    { tail -30 "$base/setup.log"; exit 2; }
  cp "$ag/source/run_autograder" "$ag/run_autograder"
}
