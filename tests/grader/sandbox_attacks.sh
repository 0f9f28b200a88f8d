#!/usr/bin/env bash
# The grader's render sandbox against a hostile "pathtracer": a script that,
# instead of rendering, tries what a submission that wants the answer key
# would try, and prints what it managed. Graded with `grader run --sandbox
# MODE` on one case whose case list, references and output folder are
# readable by root only (as the Gradescope package keeps them), then:
#   - nothing it printed shows a reference, the case list or a leak marker;
#   - it wrote nothing outside its own folder (output folder, references);
#   - the daemon it started is gone;
#   - the connection it tried to a port open on loopback never arrived;
#   - the reference it offered as its image through a link was not read;
#   - the reference pathtracer still passes the case through the same sandbox.
#
#   sandbox_attacks.sh GRADER PATHTRACER SOURCE_DIR MODE WORK
#
# MODE is bwrap or user. As root it renders as two accounts made here
# (pt-sbx-MODE-1, pt-sbx-MODE-2); mode user needs root. Exits 77 (skipped) with
# the reason when the machine cannot run the mode.
set -uo pipefail
grader=$1 pathtracer=$2 src=$3 mode=$4 work=$5

skip() { echo "SKIPPED: $*"; exit 77; }
failures=0
. "$src/tests/shell/check.sh"  # check DESCRIPTION COMMAND...

command -v python3 >/dev/null || skip "python3 is not installed (the loopback listener is a python3 script)"
if [ "$mode" = bwrap ]; then
  command -v bwrap >/dev/null || skip "bubblewrap (bwrap) is not installed: apt-get install bubblewrap"
  bwrap --unshare-all --ro-bind /usr /usr --symlink usr/lib64 /lib64 --symlink usr/lib /lib --symlink usr/bin /bin \
    -- /usr/bin/true 2>/dev/null || skip "bwrap cannot make namespaces here (user namespaces not allowed?)"
fi
accounts=()
# One run of a mode at a time on this machine (a starter kit's suite may run
# the same test beside this tree's): the grader kills every process of an
# account after each render. flock waits for the other run to end.
exec 9>"/tmp/pt-sbx-$mode.lock"
flock 9
if [ "$(id -u)" = 0 ]; then
  # Accounts of this mode's own: the other mode's test may run at the same
  # time, and the grader kills every process of an account after a render.
  for a in "pt-sbx-$mode-1" "pt-sbx-$mode-2"; do
    id "$a" >/dev/null 2>&1 || useradd --system --no-create-home --shell /usr/sbin/nologin "$a" 2>/dev/null ||
      skip "cannot create the account $a (useradd failed)"
  done
  accounts=(--sandbox-user "pt-sbx-$mode-1,pt-sbx-$mode-2")
elif [ "$mode" = user ]; then
  skip "--sandbox user renders as other accounts: run as root"
fi

rm -rf "$work"
mkdir -p "$work"
chmod 755 "$work"
# The canary is written only into the secret files; the hostile script
# builds it from two halves, so that its own text does not hold it.
canary_a=CANARY- canary_b=$RANDOM$RANDOM
canary=$canary_a$canary_b
# make_secret DIR: the case list, the references and the grader, readable by
# root only.
make_secret() {
  mkdir -m 700 "$1"
  { echo "# $canary"; grep '^p1_teapot ' "$src/grader/cases.txt"; } >"$1/cases.txt"
  mkdir -p "$1/refs"
  cp -R "$src/reference_images/p1_teapot" "$1/refs/"
  # The reference's control also grades a case of every other output the
  # grader reads back: a probability case (its --env-probability image, and
  # an -e input file staged).
  grep '^p8_probability_sun ' "$src/grader/cases.txt" >>"$1/cases.txt"
  cp -R "$src/reference_images/p8_probability_sun" "$1/refs/"
  echo "$canary" >"$1/refs/p1_teapot/canary.txt"
  cp "$grader" "$1/grader"
}
secret=$work/secret
make_secret "$secret"
out=$secret/out

# A listener on loopback: writes a line to $work/connections for every
# connection it accepts. Its port comes through a fifo (read blocks until
# it is listening).
mkfifo "$work/port"
python3 - "$work/port" "$work/connections" <<'EOF' &
import socket, sys
s = socket.socket()
s.bind(("127.0.0.1", 0))
s.listen(8)
open(sys.argv[2], "w").close()
with open(sys.argv[1], "w") as f:
    f.write(f"{s.getsockname()[1]}\n")
while True:
    c, _ = s.accept()
    with open(sys.argv[2], "a") as f:
        f.write("connection\n")
    c.close()
EOF
listener=$!
read -r port <"$work/port"
trap 'kill $listener 2>/dev/null; pkill -f "$daemon_tag" 2>/dev/null' EXIT
daemon_tag="pt-sbx-daemon-$canary_b"

# The hostile "pathtracer": every path it tries is the real one on this
# machine, as a submission could find them from /proc or a search.
cat >"$work/hostile" <<EOF
#!/bin/bash
out=\$(pwd)
say() { echo "\$*"; }
# Reading the answer key: its real path, the parent's command line, a search.
cat "$secret/refs/p1_teapot/canary.txt" 2>/dev/null && say "LEAK: read the references"
cat "$secret/cases.txt" 2>/dev/null && say "LEAK: read the case list"
refs=\$(tr '\0' '\n' </proc/\$PPID/cmdline 2>/dev/null | grep -A1 -x -- --references | tail -1)
[ -n "\$refs" ] && cat "\$refs/p1_teapot/canary.txt" 2>/dev/null && say "LEAK: read the references named in the parent's command line"
for dir in \$(readlink /proc/\$PPID/exe 2>/dev/null | xargs -r dirname) "\$out/../.." "\$out/../../.."; do
  cat "\$dir/refs/p1_teapot/canary.txt" "\$dir/cases.txt" 2>/dev/null && say "LEAK: read the answer key beside \$dir"
done
c1=$canary_a c2=$canary_b
grep -rsl "\$c1\$c2" "$work" /tmp 2>/dev/null | head -3 | sed 's/^/LEAK: found the canary in /'
ls "\$out/.." 2>/dev/null | grep -q p1_teapot && say "LEAK: sees the other cases' folders"
# Writing outside its folder.
echo pwned >"$out/results.json" 2>/dev/null && say "LEAK: wrote the results"
touch "$secret/refs/p1_teapot/PWNED" 2>/dev/null && say "LEAK: wrote into the references"
touch "$work/PWNED" 2>/dev/null && say "LEAK: wrote into the test's folder"
# A daemon left behind.
( setsid bash -c 'exec -a $daemon_tag sleep 600' </dev/null >/dev/null 2>&1 & )
# A connection to loopback.
( exec 3<>/dev/tcp/127.0.0.1/$port ) 2>/dev/null && say "LEAK: connected to loopback"
# The reference offered as its image through a link.
ln -s "$secret/refs/p1_teapot/mean.pfm" "\$out/render.pfm" 2>/dev/null
ln -s /proc/self/root/etc/passwd "\$out/render.png" 2>/dev/null
say "hostile run done"
exit 0
EOF
chmod 755 "$work/hostile"

# Controls. The reference pathtracer passes through the sandbox; the
# hostile script without a sandbox (in a copy of the secret folder) leaks,
# so that the checks below can fail.
"$secret/grader" run --pathtracer "$pathtracer" --cases "$secret/cases.txt" --references "$secret/refs" \
  --scenes "$src/scenes" -q -j 1 -o "$secret/ok" --sandbox "$mode" "${accounts[@]}" >"$work/control.log" 2>&1
control=$?
check "the reference pathtracer passes p1_teapot and p8_probability_sun through the $mode sandbox (exit $control)" \
  [ "$control" = 0 ]
[ "$control" = 0 ] || grep -E "failed|error" "$work/control.log" | head -5
if [ "$(id -u)" = 0 ]; then
  make_secret "$work/open"
  sed "s#$secret#$work/open#g" "$work/hostile" >"$work/hostile_open" && chmod 755 "$work/hostile_open"
  "$work/open/grader" run --pathtracer "$work/hostile_open" --cases "$work/open/cases.txt" --references "$work/open/refs" \
    --case p1_teapot --scenes "$src/scenes" -q -j 1 -o "$work/open/out" --sandbox none >"$work/open.log" 2>&1
  check "without the sandbox the same script reads the references (the checks can fail)" \
    grep -q "LEAK: read the references" "$work/open/out/cases/p1_teapot/render/stdout.txt"
  pkill -f "$daemon_tag" 2>/dev/null
  rm -f "$work/PWNED"
  : >"$work/connections"
fi

"$secret/grader" run --pathtracer "$work/hostile" --cases "$secret/cases.txt" --references "$secret/refs" \
  --case p1_teapot --scenes "$src/scenes" -q -j 2 -o "$out" --sandbox "$mode" "${accounts[@]}" >"$work/grader.log" 2>&1
rc=$?
cat "$work/grader.log" | tail -3
check "the grader finished and failed the hostile case (exit $rc, 1 expected)" [ "$rc" = 1 ]
printed=$out/cases/p1_teapot/render/stdout.txt
check "the hostile run ran to its end" grep -q "hostile run done" "$printed"
check "it reached nothing secret (no LEAK line: $(grep -h LEAK "$printed" | head -2 | tr '\n' ';'))" \
  bash -c "! grep -q LEAK '$printed'"
check "the canary appears in nothing it wrote" bash -c "! grep -rqs '$canary' '$out/cases'"
check "results.json is the grader's" python3 -c "import json,sys; json.load(open('$out/results.json'))"
check "nothing written into the references or the test's folder" \
  bash -c "[ ! -e '$secret/refs/p1_teapot/PWNED' ] && [ ! -e '$work/PWNED' ]"
# (The pattern's [p] keeps it from matching this check's own command line.)
check "no daemon left behind" bash -c "! pgrep -f '[p]${daemon_tag#p}' >/dev/null"
check "no connection arrived at the loopback listener" bash -c "[ ! -s '$work/connections' ]"
check "the linked reference was not read as its image" \
  grep -q "not read" "$out/cases/p1_teapot/result.json"
check "no staging folder left in /tmp" bash -c "! ls -d /tmp/pt-render-* 2>/dev/null | xargs -r -n1 stat -c %U | grep -q pt-sbx-$mode"

# A copy of a hidden case's reference left readable elsewhere on the
# machine (an instructor's checkout, a test's folder): bubblewrap's view of
# the file system leaves it out; in user mode, where the accounts see every
# file others may read, the grader searches for such copies as each account
# and refuses to grade while one is there. The hidden case is of a size no
# other case has, so that its reference's bytes are its own.
if [ "$(id -u)" = 0 ]; then
  mkdir -m 700 "$secret/hidden"
  printf 'h1_stray     1 image 1 60 CBspheres_lambertian.dae -r 37 29\n' >"$secret/hidden/cases.txt"
  "$secret/grader" make-references --pathtracer "$pathtracer" --runs 2 --case h1_stray --cases "$secret/hidden/cases.txt" \
    --scenes "$src/scenes" --references "$secret/hidden/references" --work "$secret/hidden/work" -j 1 \
    >"$work/hidden_reference.log" 2>&1
  mkdir -p "$work/stray"
  cp "$secret/hidden/references/h1_stray/mean.pfm" "$work/stray/mean.pfm"
  chmod 644 "$work/stray/mean.pfm"
  hidden_run() {  # hidden_run OUT: the reference pathtracer on p1_teapot and the hidden case; its exit status
    "$secret/grader" run --pathtracer "$pathtracer" --cases "$secret/cases.txt" --references "$secret/refs" \
      --hidden-cases "$secret/hidden/cases.txt" --case p1_teapot --case h1_stray --scenes "$src/scenes" -q -j 2 \
      -o "$secret/$1" --sandbox "$mode" "${accounts[@]}" >"$work/$1.log" 2>&1
  }
  hidden_run stray_present
  rc=$?
  if [ "$mode" = user ]; then
    check "user mode refuses to grade while a hidden reference's copy is readable, naming it (exit $rc)" \
      bash -c "[ $rc != 0 ] && grep -q 'can read $work/stray/mean.pfm, a copy of a hidden case' '$work/stray_present.log'"
  else
    check "bwrap mode does not see the copy and grades (exit $rc)" [ "$rc" = 0 ]
  fi
  rm -rf "$work/stray"
  hidden_run stray_removed
  rc=$?
  check "without the copy the reference passes the public and the hidden case in the $mode sandbox (exit $rc)" [ "$rc" = 0 ]
fi

# Two graders rendering as the same accounts at once would kill each
# other's renders (each kills its account's processes after a render): a
# grader waits while another holds an account. Here the test holds the
# first account's lock; the grader says it waits (read through a fifo: the
# line is the event), has graded nothing meanwhile, and once the lock is
# let go grades the reference to full marks. (The grader must not inherit
# the test's lock: a lock is its open file, and the grader's own would
# wait for it.)
if [ "$(id -u)" = 0 ]; then
  lockdir=/run/lock
  [ -d "$lockdir" ] || lockdir=/tmp
  exec 7>"$lockdir/pt-grader-account-pt-sbx-$mode-1.lock"
  flock 7
  mkfifo "$work/wait_fifo"
  "$secret/grader" run --pathtracer "$pathtracer" --cases "$secret/cases.txt" --references "$secret/refs" \
    --case p1_teapot --scenes "$src/scenes" -q -j 2 -o "$secret/after_wait" --sandbox "$mode" "${accounts[@]}" \
    >"$work/after_wait.log" 2>"$work/wait_fifo" 7>&- &
  waiter=$!
  exec 6<"$work/wait_fifo"
  read -r first_line <&6
  check "a second grader on the same accounts says it waits ($first_line)" \
    bash -c "[[ '$first_line' == *'waiting for another grader that renders as pt-sbx-$mode-1'* ]]"
  check "and has graded nothing while it waits" bash -c "[ ! -e '$secret/after_wait/results.json' ]"
  exec 7>&-
  cat <&6 >/dev/null
  exec 6<&-
  wait "$waiter"
  rc=$?
  check "once the lock is free it grades the reference to full marks (exit $rc)" [ "$rc" = 0 ]
fi

if [ "$failures" -ne 0 ]; then
  echo "$failures check(s) failed; the grader's log: $work/grader.log"
  exit 1
fi
echo "all checks passed ($mode sandbox)"
