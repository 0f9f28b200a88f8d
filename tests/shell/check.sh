# Sourced by the suite's shell tests: check DESCRIPTION COMMAND... runs the
# command and prints "ok: DESCRIPTION" or "FAILED: DESCRIPTION", counting
# the failures in $failures.
failures=${failures:-0}
check() {
  local what=$1
  shift
  if "$@"; then
    echo "ok: $what"
  else
    echo "FAILED: $what"
    failures=$((failures + 1))
  fi
}
