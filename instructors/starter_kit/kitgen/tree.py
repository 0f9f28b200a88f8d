"""The kit in memory: the files of the reference tree, stripped, left out or
replaced by the overlay, after every check.
"""
import os
import subprocess

from kitgen.base import SOURCE_EXTENSIONS, KitError
from kitgen.checks import check_doc_names, check_leaks, check_left_out_references, check_links, check_todo_parts
from kitgen.given import check_given_code
from kitgen.markers import mark_empty_helper_namespaces, strip_regions
from kitgen.solved import SOLVED_PARTS_FILE, add_note, check_solved_parts, notes, part_of, solved_parts_file


REFERENCE_ONLY = "// REFERENCE ONLY"
REFERENCE_ONLY_DOC = "<!-- REFERENCE ONLY"
# Left out of the kit: everything students do not get lives in the
# instructors' folder; CI runs on the reference tree only.
LEFT_OUT = (".ci/", "instructors/")
OVERLAY_DIR = "instructors/starter_kit/overlay"
# The part check a note may point to (scripts/check.sh N), when the kit has it.
CHECK_COMMAND = "scripts/check.sh"
# Overlay file (in OVERLAY_DIR) -> the kit file it becomes.
OVERLAY = {
    "README.md": "README.md",
    "grader_README.md": "grader/README.md",
    "run.sh": "scripts/run.sh",
    "stages_README.md": "stages/README.md",
}


def listed_files(root):
    files = None
    try:
        top = subprocess.run(["git", "-C", root, "rev-parse", "--show-toplevel"], check=True,
                             capture_output=True).stdout.decode().strip()
        if os.path.realpath(top) == os.path.realpath(root):
            listed = subprocess.run(["git", "-C", root, "ls-files", "-z", "--cached", "--others",
                                     "--exclude-standard"], check=True, capture_output=True).stdout
            files = sorted({f for f in listed.decode().split("\0") if f})
    except (OSError, subprocess.CalledProcessError):
        pass
    if files is None:
        files = []
        for dirpath, dirnames, filenames in os.walk(root):
            dirnames[:] = [d for d in dirnames
                           if d != ".git" and not (dirpath == root and d.startswith("build"))]
            files += [os.path.relpath(os.path.join(dirpath, f), root) for f in filenames]
    return sorted(f for f in files if os.path.isfile(os.path.join(root, f)))


def is_text(path):
    return path.endswith(SOURCE_EXTENSIONS + (".txt", ".cmake", ".md", ".sh", ".py"))


def is_source(path):
    # Only C++ sources carry solution regions; documents show the markers
    # as examples and are copied unchanged.
    return path.endswith(SOURCE_EXTENSIONS)


def make_kit(root, solved=frozenset()):
    """{kit path: lines, or None to copy the file as is}, {kit path: source
    path}, the reference-only files left out and the number of regions
    stubbed, after every check. The stage folders of the `solved` parts keep
    their solution regions (without the markers) and their reference-only
    files: the solution needs them."""
    files = listed_files(root)
    stubbed_parts = check_solved_parts(solved, files) if solved else []
    kit, origin = {}, {}
    solution_lines, outside_lines = set(), set()
    stage_sources, left_out, regions_stubbed = {}, [], 0
    for rel in files:
        if rel.startswith(LEFT_OUT):
            continue
        src = os.path.join(root, rel)
        if not is_text(rel):
            kit[rel], origin[rel] = None, src  # copied as is
            continue
        with open(src, encoding="utf-8") as f:
            lines = f.readlines()
        keep = part_of(rel) in solved
        reference_only = is_source(rel) and lines and lines[0].startswith(REFERENCE_ONLY)
        if reference_only and not keep:
            left_out.append(rel)
            solution_lines.update(l.strip() for l in lines)
            continue
        if rel.endswith(".md") and lines and lines[0].startswith(REFERENCE_ONLY_DOC):
            continue  # check_links stops any kit document that links to it
        if is_source(rel):
            check_todo_parts(rel, lines)
            out, solution, regions = strip_regions(rel, lines, keep=keep)
            if regions and not keep:
                out = mark_empty_helper_namespaces(out)
                regions_stubbed += len(regions)
            if rel.startswith("stages/") and not reference_only:
                stage_sources[rel] = ("".join(lines), regions)
        else:
            out, solution = lines, []
        kit[rel], origin[rel] = out, src
        solution_lines.update(l.strip() for l in solution)
        if is_source(rel):
            # Code outside the regions; a document quoting a solution line
            # does not make it given (it leaks it).
            outside_lines.update(l.strip() for l in out)

    check_given_code(root, stage_sources)
    check_left_out_references(kit, left_out)

    overlay = os.path.join(root, OVERLAY_DIR)
    if os.path.isdir(overlay):
        for name in sorted(os.listdir(overlay)):
            if name not in OVERLAY:
                raise KitError(f"{OVERLAY_DIR}/{name}: not an overlay file the generator knows (OVERLAY)")
        for name, target in sorted(OVERLAY.items()):
            src = os.path.join(overlay, name)
            if not os.path.isfile(src):
                raise KitError(f"{OVERLAY_DIR}/{name}: overlay file missing")
            with open(src, encoding="utf-8") as f:
                kit[target], origin[target] = f.readlines(), src

    if solved:
        say = notes(solved, stubbed_parts, CHECK_COMMAND if CHECK_COMMAND in kit else None)
        for rel in sorted(kit):
            if rel in ("README.md", "stages/README.md"):
                kit[rel] = add_note(kit[rel], say[rel])
            elif part_of(rel) is not None and rel.count("/") == 2 and rel.endswith("/README.md"):
                part = part_of(rel)
                kit[rel] = add_note(kit[rel], say["stage"] if part in solved else say[f"stage {part}"])
    # Which parts the kit gives solved, for the programs that read it
    # (scripts/run.sh chooses its first scene by it).
    kit[SOLVED_PARTS_FILE], origin[SOLVED_PARTS_FILE] = solved_parts_file(solved), None
    check_leaks(kit, solution_lines, outside_lines)
    check_links(kit)
    left_out_cmake = []
    for rel in files:
        if rel.startswith(LEFT_OUT) and rel.endswith(("CMakeLists.txt", ".cmake")):
            with open(os.path.join(root, rel), encoding="utf-8") as f:
                left_out_cmake.append(f.read())
    check_doc_names(kit, left_out_cmake)
    return kit, origin, left_out, regions_stubbed
