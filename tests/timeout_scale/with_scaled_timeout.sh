#!/usr/bin/env bash
# with_scaled_timeout.sh OPTION SECONDS COMMAND [ARGS...]
# Runs COMMAND OPTION S ARGS..., S being SECONDS times PT_TEST_TIMEOUT_SCALE
# (timeout_scale.sh): for a test whose program takes its timeout as an
# option (the fuzzers' --timeout).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/timeout_scale.sh"
[ $# -ge 3 ] || { echo "usage: with_scaled_timeout.sh OPTION SECONDS COMMAND [ARGS...]" >&2; exit 2; }
option=$1 seconds=$2
shift 2
scaled=$(scaled_seconds "$seconds")
command=$1
shift
exec "$command" "$option" "$scaled" "$@"
