# The machinery shared by the two catalogues of patched builds: the
# mutants (mutants/: classic student bugs the grader must catch) and the
# legal variants (legal_variants/: correct solutions that differ from the
# reference, which the grader must pass). Sourced, not run, by
# mutants/grade_mutants.sh and legal_variants/grade_variants.sh.
#
# A catalogue is a list, one entry a line ("name part description"; # and
# blank lines ignored), and a folder of patches, <name>.patch, each against
# the reference tree and touching only stages/ and common/. This file
# checks a catalogue (--check), plants one patch in a copy of the tree
# (--plant), builds every listed patch's pathtracer (one copy of the tree,
# each patch applied, built incrementally, its binary kept, the patch
# reverted) and summarises a grading run's results.json. What is graded,
# at which seeds, and the table written stay with each script.
#
# The caller sets, before catalogue_option and the rest:
#   tool      its name, for messages (grade_mutants.sh)
#   noun      what an entry is, for messages (mutant)
#   list      the list file, relative to the root (instructors/mutants/mutants.txt)
#   patches   the patch folder, relative to the root
#   root      the tree's root (absolute); the caller has cd'ed there
#   build_root, table, jobs   defaults of --build-root, --table, -j
# and declares: only=() mode=grade plant_name="" plant_dir="".

# Reads one of the options every catalogue script takes: --build-root DIR,
# --table FILE, -j N, --only NAME, --check, --plant NAME DIR. Sets
# catalogue_shift to the number of words it used; returns 1 (after a
# message) for an option it does not know or one missing its value.
catalogue_option() {
  catalogue_shift=0
  case "$1" in
    --build-root|--table|-j|--only)
      [ $# -ge 2 ] || { echo "$tool: $1 needs a value" >&2; return 1; }
      case "$1" in
        --build-root) build_root=$(realpath -m "$2") ;;
        --table) table=$2 ;;
        -j) jobs=$2 ;;
        --only) only+=("$2") ;;
      esac
      catalogue_shift=2 ;;
    --check) mode=check; catalogue_shift=1 ;;
    --plant)
      [ $# -ge 3 ] || { echo "$tool: --plant NAME DIR" >&2; return 1; }
      mode=plant; plant_name=$2; plant_dir=$(realpath -m "$3"); catalogue_shift=3 ;;
    *) echo "$tool: unknown argument $1" >&2; return 1 ;;
  esac
}

# name part description, one per line, from the list.
catalogue_lines() { grep -vE '^[[:space:]]*(#|$)' "$list"; }

# Copies the tracked source tree (without the reference images) to $1.
copy_tree() {
  local dest=$1
  rm -rf "$dest"
  mkdir -p "$dest"
  if git -C "$root" rev-parse --git-dir > /dev/null 2>&1; then
    git -C "$root" ls-files -z | grep -zv '^reference_images/' | (cd "$root" && xargs -0 cp --parents -t "$dest")
  else
    (cd "$root" && find . -path ./build -prune -o -path './build-*' -prune -o -path ./reference_images -prune \
       -o -type f -print0 | xargs -0 cp --parents -t "$dest")
  fi
}

# Applies (or with -R reverts) patch $2 inside folder $1 (absolute). Git
# must not take $1 for a subfolder of the checkout it lies in (the default
# build roots are under build/): there it would skip every path outside $1,
# which is all of them, and say so only with --verbose. The ceiling stops
# its search for a repository at $1, so it patches $1 as a plain folder.
apply_patch() {
  local dir=$1 patch=$2
  shift 2
  (cd "$dir" && GIT_CEILING_DIRECTORIES=$(dirname "$dir") git apply "$@" "$patch")
}

# --check: the list and the folder agree, every entry has a part and a
# description, every patch touches only stages/ or common/, and applies to
# this tree.
catalogue_check() {
  local status=0 name part rest err
  err=$(mktemp)
  declare -A listed=()
  while read -r name part rest; do
    [ -z "${listed[$name]:-}" ] || { echo "$list: $name: listed twice"; status=1; }
    listed[$name]=1
    [[ "$part" =~ ^[1-9]$ ]] || { echo "$list: $name: part '$part' is not 1-9"; status=1; }
    [ -n "$rest" ] || { echo "$list: $name: no description"; status=1; }
    local p="$patches/$name.patch"
    if [ ! -f "$p" ]; then echo "$list: $name: no patch $p"; status=1; continue; fi
    local touched
    touched=$(grep -E '^\+\+\+ ' "$p" | sed -E 's#^\+\+\+ b/##; s#\t.*##')
    [ -n "$touched" ] || { echo "$p: not a patch (no +++ lines)"; status=1; continue; }
    while read -r f; do
      case "$f" in stages/*|common/*) ;; *) echo "$p: changes $f (only stages/ and common/ may change)"; status=1 ;; esac
    done <<< "$touched"
    (cd "$root" && git apply --check "$p" 2> "$err") \
      || { echo "$p: does not apply: $(head -1 "$err")"; status=1; }
  done < <(catalogue_lines)
  rm -f "$err"
  for p in "$patches"/*.patch; do
    [ -e "$p" ] || continue
    local n
    n=$(basename "$p" .patch)
    [ -n "${listed[$n]:-}" ] || { echo "$p: not listed in $list"; status=1; }
  done
  local count=${#listed[@]}
  [ $status -eq 0 ] && echo "$tool: $count ${noun}s listed; every patch applies"
  return $status
}

# --plant NAME DIR: a copy of the tree with one patch applied, in DIR.
catalogue_plant() {
  [ -n "$plant_name" ] && [ -n "$plant_dir" ] || { echo "$tool: --plant NAME DIR" >&2; return 2; }
  [ -f "$patches/$plant_name.patch" ] || { echo "$tool: no $noun $plant_name ($patches/$plant_name.patch)" >&2; return 2; }
  [ ! -e "$plant_dir" ] || [ -z "$(ls -A "$plant_dir")" ] || { echo "$tool: $plant_dir exists and is not empty" >&2; return 2; }
  copy_tree "$plant_dir"
  apply_patch "$plant_dir" "$root/$patches/$plant_name.patch"
  echo "Planted $plant_name in $plant_dir: cmake -S $plant_dir -B $plant_dir/build && cmake --build $plant_dir/build --target pathtracer"
}

# Runs --check or --plant when asked (and exits); otherwise checks the
# catalogue quietly (exit 2 with the messages when it is broken), checks
# that every --only name is listed, and that the grader is built.
catalogue_start() {
  if [ "$mode" = check ]; then
    catalogue_check && exit 0 || exit 2
  fi
  if [ "$mode" = plant ]; then
    catalogue_plant && exit 0 || exit 2
  fi
  catalogue_check > /dev/null || { catalogue_check; exit 2; }
  local n
  for n in "${only[@]}"; do
    catalogue_lines | awk '{print $1}' | grep -qxF "$n" || { echo "$tool: --only $n: no such $noun in $list" >&2; exit 2; }
  done
  mkdir -p "$build_root"
  grader="$root/build/bin/grader"
  [ -x "$grader" ] || { echo "$tool: build the grader first (scripts/build.sh)" >&2; exit 2; }
}

# build_pathtracer DIR SOURCE: configure DIR (once), then build the
# pathtracer only; logs in DIR.configure.log and DIR.build.log.
build_pathtracer() {
  local dir=$1 src=$2
  [ -f "$dir/CMakeCache.txt" ] || cmake -S "$src" -B "$dir" -DCMAKE_BUILD_TYPE=Release -DPT_BUILD_TESTS=OFF > "$dir.configure.log" 2>&1
  cmake --build "$dir" -j "$jobs" --target pathtracer > "$dir.build.log" 2>&1
}

# One copy of the tree ($build_root/src), built once; each listed entry
# (those of --only, if any) is applied, built (incrementally: only what the
# patch touches recompiles), its binary kept as $build_root/bin/<name>, and
# the patch reverted. Fills names (in list order), part_of, description_of
# and built (1 when it built; else its log is $build_root/<name>.build.log).
catalogue_build_all() {
  local src="$build_root/src" name part description
  copy_tree "$src"
  mkdir -p "$build_root/tree.build" "$build_root/bin"
  build_pathtracer "$build_root/tree.build" "$src" || { echo "$tool: the unpatched copy does not build" >&2; exit 2; }
  cp "$build_root/tree.build/bin/pathtracer" "$build_root/unpatched.pathtracer"
  names=()
  declare -gA part_of=() description_of=() built=()
  while read -r name part description; do
    if [ ${#only[@]} -gt 0 ] && [[ ! " ${only[*]} " =~ " $name " ]]; then continue; fi
    names+=("$name")
    part_of[$name]=$part
    description_of[$name]=$description
    echo "== build $name"
    apply_patch "$src" "$root/$patches/$name.patch"
    if ! build_pathtracer "$build_root/tree.build" "$src"; then
      cp "$build_root/tree.build.build.log" "$build_root/$name.build.log"
    elif cmp -s "$build_root/tree.build/bin/pathtracer" "$build_root/unpatched.pathtracer"; then
      # A patch that changes code always changes the binary: the same bytes
      # mean it was not applied or not rebuilt, and grading it would grade
      # the reference under the patch's name.
      echo "$tool: $name: the built pathtracer is the unpatched one, byte for byte" | tee "$build_root/$name.build.log" >&2
    else
      cp "$build_root/tree.build/bin/pathtracer" "$build_root/bin/$name"
      built[$name]=1
    fi
    apply_patch "$src" "$root/$patches/$name.patch" -R
  done < <(catalogue_lines)
}

# results.json -> "score max cases failed-case-names" ("0.00 0 0
# no-results" when the grader wrote none: see the run's log).
summarise() {
  python3 - "$1" <<'PY'
import json, sys
try:
    r = json.load(open(sys.argv[1]))
except (OSError, ValueError):
    print("0.00 0 0 no-results")
    sys.exit(0)
tests = [t for t in r["tests"] if "max_score" in t]  # the staff's hidden-case tests carry no points
lost = [t["name"].split(": ", 1)[1] for t in tests if t["score"] < t["max_score"]]
print(f'{r["score"]:.2f} {sum(t["max_score"] for t in tests):g} {len(tests)} {",".join(lost) or "-"}')
PY
}

# The parts of a comma-separated list of case names (p3_x -> 3).
parts_of() { echo "$1" | tr ',' '\n' | sed -nE 's/^p([1-9])_.*/\1/p' | sort -u | tr '\n' ' '; }

# grade BINARY OUT [grader run options...]: every case, reports in OUT;
# the grader's own output in OUT.log. Never fails (the verdicts are in
# OUT/results.json).
# More `grader run` options for every grading (e.g. --hidden-cases FILE).
grade_extra=()
grade() {
  local binary=$1 out=$2
  shift 2
  "$grader" run -q -j "$jobs" --pathtracer "$binary" -o "$out" ${grade_extra[@]+"${grade_extra[@]}"} "$@" > "$out.log" 2>&1 || true
}

# The lowest part whose stage folder PATCH touches (stages/partN_...), or 1
# when it touches anything else (common/ reaches every part).
first_part_of_patch() {
  awk '/^\+\+\+ b\// {
         f = substr($2, 3); k = 1
         if (match(f, /^stages\/part[0-9]+_/)) k = substr(f, 12, RLENGTH - 12) + 0
         if (min == "" || k < min) min = k
       }
       END { print (min == "" ? 1 : min) }' "$1"
}

# grade_from_part BINARY OUT PART REFERENCE_OUT: as grade, but the build is
# rendered only on the cases of parts PART and later. `pathtracer --part N`
# runs the stages up to N only, so a bug in part PART's stage renders the
# earlier parts' cases exactly as the reference build does (same seeds,
# same code): their results are copied from REFERENCE_OUT (the reference
# build's grading) and the reports are made again over every case.
grade_from_part() {
  local binary=$1 out=$2 first=$3 ref=$4
  if [ "$first" -le 1 ] || [ ! -d "$ref/cases" ]; then grade "$binary" "$out"; return; fi
  local args=() p name part
  for p in $(seq "$first" 9); do args+=(--part "$p"); done
  grade "$binary" "$out" "${args[@]}"
  [ -d "$out/cases" ] || return 0
  while read -r name part; do
    if [ "$part" -lt "$first" ] && [ -d "$ref/cases/$name" ]; then cp -r "$ref/cases/$name" "$out/cases/"; fi
  done < <(awk '!/^#/ && NF >= 2 {print $1, $2}' grader/cases.txt)
  "$grader" merge -o "$out.all" "$out" > "$out.merge.log" 2>&1 || true
  for f in results.json report.txt report.html timing.md; do
    if [ -f "$out.all/$f" ]; then mv "$out.all/$f" "$out/$f"; fi
  done
  rm -rf "$out.all"
}
