#!/usr/bin/env bash
# The function checks (pathtracer/probe.h) on a catalogue of patched builds:
# the mutants (every classic bug should make its own function's checks
# disagree), the held-out bugs, or the legal variants (every correct
# variant must agree everywhere). Builds each patched pathtracer as the
# grading scripts do (instructors/patch_catalogue.sh), runs `grader
# functions` on it, and writes which functions disagree: a Markdown table
# and, for the mutants, instructors/mutants/probes.json, which
# make_catalogue.py puts into the catalogue of known bugs (the hints'
# leave-one-out measure uses each bug's own answers).
#
#   instructors/check_functions.sh mutants|held_out|legal_variants [--build-root DIR] [--table FILE] [-j N] [--only NAME]...
#                                  [--tables-only]
#
# About 15 s of CPU a patch (an incremental build; the checks take about a
# second): a command to run on purpose. --tables-only writes the tables
# again from an earlier run's answers (nothing is built). Exit status: 0
# when every mutant (or held-out bug) of a function with checks makes its
# own function disagree, and every legal variant makes none; 1 otherwise;
# 2 for bad usage.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
tool=check_functions.sh
which=${1:-}
[ $# -gt 0 ] && shift
case "$which" in
  mutants) noun=mutant; list=instructors/mutants/mutants.txt; patches=instructors/mutants/patches ;;
  held_out) noun=bug; list=instructors/mutants/held_out/held_out.txt; patches=instructors/mutants/held_out/patches ;;
  legal_variants) noun=variant; list=instructors/legal_variants/variants.txt; patches=instructors/legal_variants/patches ;;
  *) echo "$tool: say which catalogue: mutants, held_out or legal_variants" >&2; exit 2 ;;
esac
build_root="$root/build/functions_$which"
table="$root/$(dirname "$list")/functions.md"
jobs=$(nproc 2>/dev/null || echo 2)
only=()
mode=grade
plant_name="" plant_dir=""
tables_only=0
. instructors/patch_catalogue.sh
while [ $# -gt 0 ]; do
  case "$1" in
    -h|--help) sed -n '2,21p' "$0"; exit 0 ;;
    --tables-only) tables_only=1; shift ;;
    *) catalogue_option "$@" || exit 2; shift "$catalogue_shift" ;;
  esac
done
catalogue_start
t0=$SECONDS
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
if [ "$tables_only" = 1 ]; then
  names=()
  while read -r name _; do
    if [ ${#only[@]} -gt 0 ] && [[ ! " ${only[*]} " =~ " $name " ]]; then continue; fi
    names+=("$name")
  done < <(catalogue_lines)
else
catalogue_build_all

# The unpatched copy first: it must agree everywhere (else the reference's
# answers, reference_images/probes.json, are stale).
"$grader" functions --pathtracer "$build_root/unpatched.pathtracer" -o "$build_root/unpatched.functions" \
  > "$build_root/unpatched.functions.txt" 2>&1 || {
  echo "$tool: the unpatched build does not agree with reference_images/probes.json (make it again:" \
       "build/bin/pathtracer --probe reference_images/probes.json); see $build_root/unpatched.functions.txt" >&2
  exit 1
}
for name in "${names[@]}"; do
  [ -n "${built[$name]:-}" ] || continue
  "$grader" functions --pathtracer "$build_root/bin/$name" -o "$build_root/$name.functions" \
    > "$build_root/$name.functions.txt" 2>&1 || true
done
# What the tables say they were made from, for --tables-only.
echo "$commit $((SECONDS - t0))" > "$build_root/built.txt"
fi
read -r commit seconds < "$build_root/built.txt" || { echo "$tool: no earlier run in $build_root" >&2; exit 2; }

status=0
python3 - "$which" "$list" "$build_root" "$table" "$commit" "$seconds" "${names[@]}" <<'PY' || status=1
import json, os, re, sys
which, listfile, root, table, commit, seconds = sys.argv[1:7]
names = sys.argv[7:]
functions_of = {}
if which != "legal_variants":
    # The function each bug lives in (hints.txt for the mutants, the list's
    # third column for the held-out bugs).
    if which == "mutants":
        for line in open("instructors/mutants/hints.txt"):
            f = [x.strip() for x in line.split("|")]
            if len(f) == 5 and not line.startswith("#"):
                functions_of[f[0]] = f[1]
    else:
        for line in open(listfile):
            if line.strip() and not line.startswith("#"):
                w = line.split()
                functions_of[w[0]] = w[2]
parts = {}
for line in open(listfile):
    if line.strip() and not line.lstrip().startswith("#"):
        w = line.split()
        parts[w[0]] = int(w[1])
rows, probes, probed = [], {}, []
ok_count = 0
for n in names:
    path = os.path.join(root, n + ".functions.txt")
    if not os.path.exists(path):
        rows.append((n, functions_of.get(n, ""), "build failed"))
        continue
    differ, seen = [], []
    for line in open(path):
        m = re.match(r"part (\d+)\s+(\S+)\s+(agrees|DIFFERS)", line)
        if m:
            seen.append((m.group(2), int(m.group(1))))
            if m.group(3) == "DIFFERS":
                differ.append(m.group(2))
    if len(seen) > len(probed):
        probed = seen
    probes[n] = differ
    own = functions_of.get(n, "")
    rows.append((n, own, differ))
probed_names = {fn for fn, _ in probed}
table_rows = []
for n, own, differ in rows:
    if isinstance(differ, str):  # build failed
        table_rows.append(f"| {n} | {parts[n]} | {own} | build failed | |")
        continue
    if which == "legal_variants":
        ok = not differ
        verdict = "yes" if ok else "no"
    elif own in probed_names:
        ok = own in differ
        verdict = "its own" if ok else ("others only" if differ else "none")
    else:
        ok = True  # a function without checks: what the signatures must name
        verdict = "its function has no checks"
    ok_count += ok
    table_rows.append(f"| {n} | {parts[n]} | {own} | {', '.join(differ) or '-'} | {verdict} |")
if which == "mutants":
    with open("instructors/mutants/probes.json", "w") as f:
        json.dump({"about": "Which functions each mutant's build answers the function checks differently from the "
                            "reference's (instructors/check_functions.sh mutants); read by make_catalogue.py.",
                   "commit": commit,
                   "probed_functions": [{"function": fn, "part": p} for fn, p in probed],
                   "bugs": probes}, f, indent=1)
        f.write("\n")
own = sum(1 for n in names if functions_of.get(n) in probes.get(n, []))
head = {
    "mutants": "does each classic bug make its own function's checks disagree?",
    "held_out": "do the held-out bugs make their own function's checks disagree?",
    "legal_variants": "does every correct variant answer every check as the reference does?",
}[which]
last = "agree everywhere" if which == "legal_variants" else "what is disagreeing"
with open(table, "w") as f:
    f.write(f"<!-- REFERENCE ONLY: measured on the catalogue; the starter kit leaves this table out -->\n")
    f.write(f"# Function checks: {head}\n\n")
    f.write("Each patched build's `grader functions` (its functions called on fixed inputs, `pathtracer --probe`, "
            "compared with `reference_images/probes.json`). Made by `instructors/check_functions.sh "
            f"{which}` at commit {commit} ({int(seconds) // 60} min).\n\n")
    f.write(f"| {'variant' if which == 'legal_variants' else 'bug'} | part | function | functions whose checks disagree | "
            f"{'all agree' if which == 'legal_variants' else 'names'} |\n|---|---:|---|---|---|\n")
    f.write("\n".join(table_rows) + "\n\n")
    if which == "legal_variants":
        f.write(f"{ok_count} of {len(names)} variants agree on every function.\n")
    else:
        checked = [n for n in names if functions_of.get(n) in probed_names]
        unchecked = sorted({functions_of.get(n, "?") for n in names if functions_of.get(n) not in probed_names})
        f.write(f"{own} of the {len(checked)} {'mutants' if which == 'mutants' else 'bugs'} of functions with checks "
                f"make their own function disagree. The other {len(names) - len(checked)} are bugs of the "
                f"functions without checks ({', '.join(unchecked)}: they need a scene, lights and paths), which "
                "only the signatures can name.\n")
if which == "legal_variants":
    print(f"{table}: {ok_count} of {len(names)} agree everywhere")
else:
    checked = [n for n in names if functions_of.get(n) in probed_names]
    print(f"{table}: {own} of {len(checked)} bugs of checked functions make their own function disagree")
sys.exit(0 if ok_count == len(names) else 1)
PY
exit $status
