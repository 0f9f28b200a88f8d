# Sourced by the tests written in bash. PT_TEST_TIMEOUT_SCALE (README,
# "Tests"), a number > 0 such as 2 or 2.5, default 1, multiplies every
# timeout a test gives the programs it runs, as it multiplies the tests'
# own TIMEOUT in ctest.
#   scaled_seconds N   prints N times the scale, rounded up to a second
#   timeout_scale      prints the scale (for the grader's --timeout-scale)
timeout_scale() {
  local s=${PT_TEST_TIMEOUT_SCALE:-1}
  if ! [[ "$s" =~ ^[0-9]+(\.[0-9]*)?$ ]] || ! awk -v s="$s" 'BEGIN { exit !(s > 0) }'; then
    echo "PT_TEST_TIMEOUT_SCALE=$s: not a number > 0 such as 2 or 2.5" >&2
    return 2
  fi
  echo "$s"
}

scaled_seconds() {
  local s
  s=$(timeout_scale) || return 2
  awk -v s="$s" -v t="$1" 'BEGIN { v = t * s; r = int(v); if (r < v) r++; print r }'
}
