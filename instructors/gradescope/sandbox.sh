# The build sandbox, sourced by setup.sh and run_autograder (bash).
#
# A submission's code is compiled and linked by an unprivileged account
# (pt-build, made by setup.sh) that sees only the toolchain, the build tree
# (the kit's sources with the submission's, read-only) and the build folder
# (writable), in one of two ways:
#   bwrap  Debian's bubblewrap: new namespaces of every kind (no network, its
#          own processes, a fresh /tmp), /usr read-only, nothing of the
#          autograder mounted but the tree and the build folder
#   user   where user namespaces are forbidden (Docker's default seccomp
#          profile): the account alone, kept out by file permissions (every
#          secret of the autograder is root-only, mode 0700)
# Run as a user other than root (tests, batch grading by hand), there is no
# account to switch to: bwrap mode runs bubblewrap as that user.

SANDBOX_BUILD_ACCOUNT=pt-build
SANDBOX_PATH=/usr/local/bin:/usr/bin:/bin

# sandbox_account_ids ACCOUNT: "UID GID" of the account (empty when none).
sandbox_account_ids() {
  local line
  line=$(getent passwd "$1" 2>/dev/null) || return 1
  echo "$line" | awk -F: '{ print $3, $4 }'
}

# sandbox_as ACCOUNT COMMAND...: COMMAND as ACCOUNT (no groups, no
# capabilities, no way back to privileges), in a clean environment; as
# the current user when ACCOUNT is empty.
sandbox_as() {
  local account=$1
  shift
  if [ -z "$account" ]; then
    env -i PATH="$SANDBOX_PATH" LC_ALL=C "$@"
    return
  fi
  local ids
  ids=$(sandbox_account_ids "$account") || { echo "sandbox: no account $account" >&2; return 126; }
  set -- setpriv --reuid="${ids% *}" --regid="${ids#* }" --clear-groups --no-new-privs --inh-caps=-all \
    env -i PATH="$SANDBOX_PATH" LC_ALL=C "$@"
  "$@"
}

# sandbox_bwrap_args TREE BUILD: bubblewrap's arguments for a build of TREE
# in BUILD (both at their own paths, so that the build folder's CMake files
# stay valid).
sandbox_bwrap_args() {
  local tree=$1 build=$2 d
  args=(--unshare-all --die-with-parent --new-session --clearenv
        --ro-bind /usr /usr --proc /proc --dev /dev --tmpfs /tmp --tmpfs /var/tmp)
  # Debian and Ubuntu link /bin, /lib, ... to /usr; elsewhere, bind them.
  for d in /bin /sbin /lib /lib32 /lib64 /libx32; do
    if [ -L "$d" ]; then
      args+=(--symlink "$(readlink "$d")" "$d")
    elif [ -d "$d" ]; then
      args+=(--ro-bind "$d" "$d")
    fi
  done
  # What the compilers and the dynamic linker read from /etc.
  for d in /etc/alternatives /etc/ld.so.cache /etc/ld.so.conf /etc/ld.so.conf.d; do
    args+=(--ro-bind-try "$d" "$d")
  done
  args+=(--ro-bind "$tree" "$tree" --bind "$build" "$build"
         --setenv PATH "$SANDBOX_PATH" --setenv HOME /tmp --setenv TMPDIR /tmp --setenv LC_ALL C
         --chdir "$build")
}

# sandbox_run MODE ACCOUNT TREE BUILD TMP COMMAND...: COMMAND in the sandbox
# (MODE bwrap or user; none: as is). TMP: the account's temporary folder in
# user mode. Runs in a subshell (its limits stay there).
sandbox_run() (
  local mode=$1 account=$2 tree=$3 build=$4 tmp=$5
  shift 5
  # Limits for the account: processes (a fork bomb), the size of one file,
  # each process's memory (#include "/dev/zero" makes the compiler read
  # forever). No input.
  ulimit -S -u 4096 2>/dev/null || true
  ulimit -S -f $((4 * 1024 * 1024)) 2>/dev/null || true
  ulimit -S -v $((4 * 1024 * 1024)) 2>/dev/null || true
  exec </dev/null
  case "$mode" in
    bwrap)
      local args
      sandbox_bwrap_args "$tree" "$build"
      sandbox_as "$account" bwrap "${args[@]}" "$@"
      ;;
    user)
      sandbox_as "$account" env HOME=/nonexistent TMPDIR="$tmp" setsid --wait sh -c 'cd "$1" && shift && exec "$@"' sh "$build" "$@"
      ;;
    none)
      (cd "$build" && "$@")
      ;;
    *)
      echo "sandbox: unknown mode $mode" >&2
      exit 2
      ;;
  esac
)

# sandbox_probe MODE ACCOUNT TREE BUILD TMP: whether MODE works here: the
# account reads the tree and writes the build folder through it.
sandbox_probe() {
  sandbox_run "$@" sh -c 'test -r "$1/CMakeLists.txt" && touch "$2/.sandbox-probe" && rm -f "$2/.sandbox-probe"' sh "$3" "$4" \
    >/dev/null 2>&1
}

# sandbox_end_account ACCOUNT [KEEP]: kills every process of ACCOUNT (again
# until none is left: a process may fork while it is being killed) and
# deletes its files in the shared temporary folders, except under KEEP (the
# sandbox folder, when it is in /tmp).
sandbox_end_account() {
  local account=$1 keep=${2:-/nonexistent} ids uid i left
  ids=$(sandbox_account_ids "$account") || return 0
  uid=${ids% *}
  for i in 1 2 3 4 5 6 7 8 9 10; do
    # (awk fails on a process that ended while it read /proc: not an error here)
    left=$({ awk -v u="$uid" '/^Uid:/ { if ($2 == u || $3 == u) { print FILENAME; exit } }' /proc/[0-9]*/status 2>/dev/null || true; } | head -1)
    [ -z "$left" ] && break
    sandbox_as "$account" bash -c 'kill -KILL -1' 2>/dev/null || true
    sleep 0.1
  done
  find /tmp /var/tmp /dev/shm -xdev -mindepth 1 -path "$keep" -prune -o -user "$uid" -prune -exec rm -rf {} + \
    2>/dev/null || true
}
