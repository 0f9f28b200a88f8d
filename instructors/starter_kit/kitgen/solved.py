"""Parts given solved (--solved-parts): which they are, which files belong to
a part, and the notes that tell students what the kit gives them.
"""
import re

from kitgen.base import KitError


# stages/partK_<name>/...: the files of part K.
PART_FOLDER = re.compile(r"^stages/part(\d+)_[^/]+/")
PART_LIST = re.compile(r"^\d+(?:-\d+)?(?:,\d+(?:-\d+)?)*$")


# The kit's record of its solved parts, at its root.
SOLVED_PARTS_FILE = "solved_parts.txt"


class SolvedPartsError(KitError):
    """A --solved-parts value the generator cannot use (a usage error)."""


def parse_parts(text):
    """'1-5', '1,2,3' or '1-3,5' -> frozenset of part numbers."""
    value = text.replace(" ", "")
    if not PART_LIST.match(value):
        raise SolvedPartsError(f"--solved-parts {text!r}: expected part numbers such as 1-5 or 1,2,3")
    parts = set()
    for item in value.split(","):
        first, _, last = item.partition("-")
        a, b = int(first), int(last or first)
        if a < 1 or b < a:
            raise SolvedPartsError(f"--solved-parts {text!r}: {item} is not a range of parts (1-5: parts 1 to 5)")
        parts.update(range(a, b + 1))
    return frozenset(parts)


def part_of(rel):
    """The part a file of stages/partK_*/ belongs to, or None."""
    m = PART_FOLDER.match(rel)
    return int(m.group(1)) if m else None


def check_solved_parts(solved, files):
    """Every solved part has a stage folder, and at least one part is left to
    write (a kit with every part solved is the reference)."""
    parts = {p for p in map(part_of, files) if p is not None}
    missing = sorted(solved - parts)
    if missing:
        raise SolvedPartsError(f"--solved-parts: no stage folder for part {missing[0]} (the tree's stages are "
                               f"{describe(parts)}: stages/partK_*/)")
    if parts and parts <= solved:
        raise SolvedPartsError(f"--solved-parts: every part ({describe(parts)}) would be solved: the kit would be "
                               f"the reference")
    return sorted(parts - solved)


def describe(parts):
    """{1, 2, 3, 5} -> 'parts 1-3 and 5'; {4} -> 'part 4'."""
    runs = []
    for p in sorted(parts):
        if runs and p == runs[-1][1] + 1:
            runs[-1][1] = p
        else:
            runs.append([p, p])
    items = [f"{a}" if a == b else f"{a}-{b}" for a, b in runs]
    if len(items) == 1 and runs[0][0] == runs[0][1]:
        return f"part {items[0]}"
    return "parts " + (items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1])


# What a solved part gives a stubbed part beyond its own functions, said in
# the stubbed part's README of a kit that gives the first part solved:
# {(solved part, stubbed part): the sentence}.
GIVEN_FOR = {
    (4, 6): "Part 4's `at_least_one_bounce_radiance` already treats mirror and glass as the course's Task 0 "
            "asks (no light sampling at a delta surface, the emission its bounce reaches instead, `|cos θ|` "
            "in the bounce's weight): \"Part 4's share\" below is written for you, nothing of it is yours to add.",
}


def notes(solved, stubbed, check=None):
    """{kit document: the note it gets} for a kit with `solved` parts; the
    key "stage" is the note of a solved part's README, "stage N" that of
    stubbed part N's. check: the kit's part check command (scripts/check.sh),
    None when it has none."""
    given, yours = describe(solved), describe(stubbed)
    say = {
        "README.md":
            f"> **This kit gives {given} solved.** Their code in `stages/` is complete (the\n"
            f"> reference solution), so their tests and grading cases pass and {yours},\n"
            f"> yours to write, build on a renderer that works. The TODO lines, failing\n"
            f"> tests and failing cases this README speaks of are those of {yours}"
            + (f"; your\n> first part's check is `{check} {min(stubbed)}`.\n" if check else ".\n"),
        "stages/README.md":
            f"> **In this kit {given} {'is' if len(solved) == 1 else 'are'} given solved:** "
            f"{'its folder holds' if len(solved) == 1 else 'their folders hold'}\n"
            f"> complete code, with no stand-ins and no TODO lines. You write {yours}.\n",
        "stage":
            f"> **Given solved in this kit.** The functions this README asks for are\n"
            f"> written (the reference solution) and its tests pass: read them and use\n"
            f"> them; {yours}, yours to write, build on them. What this README says of\n"
            f"> stand-ins and TODO lines does not apply to this kit.\n",
    }
    for part in stubbed:
        extra = [GIVEN_FOR[(p, part)] for p in sorted(solved) if (p, part) in GIVEN_FOR]
        text = (f"**In this kit {given} {'is' if len(solved) == 1 else 'are'} given solved** (the reference "
                f"solution): what this README says {'that part gives' if len(solved) == 1 else 'they give'} is "
                f"written. You write this part's functions. " + " ".join(extra))
        say[f"stage {part}"] = "".join(f"> {line}\n" for line in wrap(text))
    return say


def wrap(text, width=76):
    """Lines of at most `width` characters (words kept whole)."""
    lines, line = [], ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    return lines + ([line] if line else [])


def add_note(lines, note):
    """The note as a paragraph after the document's first heading (at the
    top when it has none)."""
    at = next((k + 1 for k, l in enumerate(lines) if l.startswith("# ")), 0)
    block = note.splitlines(keepends=True)
    before = ["\n"] if at else []
    after = [] if lines[at:at + 1] == ["\n"] else ["\n"]
    return lines[:at] + before + block + after + lines[at:]


def solved_parts_file(solved):
    """The lines of the kit's solved_parts.txt: comments, then one part
    number a line (none in a kit where every part is the students')."""
    return ["# The parts this starter kit gives solved: their code in stages/ is the\n",
            "# reference solution. One part number a line; every part not listed is\n",
            "# the students' to write (none listed: every part is). scripts/run.sh\n",
            "# reads it. Lines starting with # are comments.\n"] + [f"{p}\n" for p in sorted(solved)]
