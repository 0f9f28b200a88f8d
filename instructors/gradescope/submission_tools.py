#!/usr/bin/env python3
"""What run_autograder does with a submission's files and logs (python3
standard library only; runs as root, outside the sandbox).

  intake    takes the submission's sources: the regular .cpp and .h files of
            the kit's part folders, nothing else, into the build tree
  feedback  the build log as the student may see it: only the submission's
            own lines quoted, paths outside the submission shortened
  result    writes results.json (score, message, the build log's first errors)
  manifest  sha256, mode and owner of every file under some folders (the
            tamper check compares two of these)
  listing   the first entries of a folder (what a submission without code holds)

Each subcommand's options: submission_tools.py SUBCOMMAND --help.
"""
import argparse
import hashlib
import json
import os
import re
import stat
import sys

# A submitted file is taken only when all of this holds.
MAX_FILE_BYTES = 256 * 1024
MAX_TOTAL_BYTES = 2 * 1024 * 1024
SOURCE_SUFFIXES = (".cpp", ".h")
NAME_OK = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$")
SKIP_DIRS = {"__MACOSX", ".git"}
MAX_DEPTH = 6


def is_real_dir(path):
    try:
        return stat.S_ISDIR(os.lstat(path).st_mode)
    except OSError:
        return False


def has_code(folder):
    try:
        entries = os.listdir(folder)
    except OSError:
        return False
    for name in entries:
        if name.endswith(SOURCE_SUFFIXES):
            try:
                if stat.S_ISREG(os.lstat(os.path.join(folder, name)).st_mode):
                    return True
            except OSError:
                pass
    return False


def find_stages(submission, parts):
    """The shallowest folder of the submission holding one of the kit's part
    folders with code in it (the submission itself when it holds them).
    Symbolic links are never followed."""
    best = None
    best_depth = None
    for dirpath, dirnames, _ in os.walk(submission, followlinks=False):
        depth = os.path.relpath(dirpath, submission).count(os.sep) + (dirpath != submission)
        dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIRS and is_real_dir(os.path.join(dirpath, d)))
        if best_depth is not None and depth >= best_depth:
            dirnames[:] = []
            continue
        candidates = list(dirnames)
        if depth >= MAX_DEPTH - 1:
            dirnames[:] = []
        for d in candidates:
            if d in parts and has_code(os.path.join(dirpath, d)):
                best, best_depth = dirpath, depth
                break
    return best


def read_regular(path, limit):
    """The bytes of a regular file, opened without following a link; None
    when it is not one (or changed under us)."""
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(path, flags)
    except OSError:
        return None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_size > limit:
            return None
        chunks = []
        total = 0
        while True:
            b = os.read(fd, 65536)
            if not b:
                break
            total += len(b)
            if total > limit:
                return None
            chunks.append(b)
        return b"".join(chunks)
    finally:
        os.close(fd)


def holds(path, data):
    """path is a regular file (not a link) holding exactly data."""
    try:
        st_ = os.lstat(path)
        if not stat.S_ISREG(st_.st_mode) or st_.st_size != len(data):
            return False
        with open(path, "rb") as f:
            return f.read() == data
    except OSError:
        return False


def same_as_kit(path, kit_path):
    """A regular file with the same bytes as the kit's file of that name."""
    try:
        if os.lstat(path).st_size != os.lstat(kit_path).st_size:
            return False
    except OSError:
        return False
    mine = read_regular(path, MAX_TOTAL_BYTES)
    return mine is not None and holds(kit_path, mine)


def group_line(ignored):
    """ONE line: the ignored files grouped by reason, a few names each."""
    if not ignored:
        return ""
    groups = {}
    for path, reason in ignored:
        groups.setdefault(reason, []).append(path)
    parts = []
    for reason, paths in groups.items():
        shown = ", ".join(paths[:3]) + (f" and {len(paths) - 3} more" if len(paths) > 3 else "")
        parts.append(f"{reason}: {shown}")
    return "Ignored from your stages/: " + "; ".join(parts) + "."


def cmd_intake(a):
    kit_stages = a.kit_stages
    parts = sorted(d for d in os.listdir(kit_stages) if is_real_dir(os.path.join(kit_stages, d)))
    report = {"stages": None, "accepted": [], "ignored": [], "ignored_line": ""}
    submission = os.path.realpath(a.submission) if os.path.isdir(a.submission) else None
    stages = find_stages(submission, set(parts)) if submission else None
    if stages is None:
        with open(a.report, "w") as f:
            json.dump(report, f, indent=1)
        return 3
    report["stages"] = os.path.relpath(stages, submission)
    accepted, ignored = [], []
    total = 0
    for entry in sorted(os.listdir(stages)):
        path = os.path.join(stages, entry)
        if entry in SKIP_DIRS:
            continue
        if entry in parts and is_real_dir(path):
            continue
        try:
            st = os.lstat(path)
        except OSError:
            continue
        if stat.S_ISLNK(st.st_mode):
            ignored.append((entry, "links"))
        elif stat.S_ISDIR(st.st_mode):
            ignored.append((entry + "/", "folders that are not part folders"))
        elif same_as_kit(path, os.path.join(kit_stages, entry)):
            continue
        elif entry == "CMakeLists.txt" or entry.endswith(".cmake"):
            ignored.append((entry, "build files"))
        else:
            ignored.append((entry, "files outside the part folders"))
    for part in parts:
        folder = os.path.join(stages, part)
        if not is_real_dir(folder):
            continue
        kit_files = set(os.listdir(os.path.join(kit_stages, part)))
        for name in sorted(os.listdir(folder)):
            rel = f"{part}/{name}"
            path = os.path.join(folder, name)
            try:
                st = os.lstat(path)
            except OSError:
                continue
            if stat.S_ISLNK(st.st_mode):
                ignored.append((rel, "links"))
                continue
            if not name.endswith(SOURCE_SUFFIXES) and same_as_kit(path, os.path.join(kit_stages, part, name)):
                continue  # the kit's own README.md or CMakeLists.txt, unchanged
            if stat.S_ISDIR(st.st_mode):
                if name not in SKIP_DIRS:
                    ignored.append((rel + "/", "subfolders"))
                continue
            if not stat.S_ISREG(st.st_mode):
                ignored.append((rel, "special files"))
                continue
            if name == "CMakeLists.txt" or name.endswith(".cmake"):
                ignored.append((rel, "build files"))
                continue
            if not name.endswith(SOURCE_SUFFIXES):
                ignored.append((rel, "files that are not .cpp or .h"))
                continue
            if not NAME_OK.match(name):
                ignored.append((rel, "files with unusual names"))
                continue
            if name.endswith(".cpp") and name not in kit_files:
                ignored.append((rel, ".cpp files the kit does not have"))
                continue
            if st.st_size > MAX_FILE_BYTES:
                ignored.append((rel, f"files over {MAX_FILE_BYTES // 1024} KB"))
                continue
            if total + st.st_size > MAX_TOTAL_BYTES:
                ignored.append((rel, f"files past the {MAX_TOTAL_BYTES // (1024 * 1024)} MB limit of all files"))
                continue
            data = read_regular(path, MAX_FILE_BYTES)
            if data is None:
                ignored.append((rel, "special files"))
                continue
            total += len(data)
            dest_dir = os.path.join(a.tree_stages, part)
            dest = os.path.join(dest_dir, name)
            if os.path.islink(dest):
                os.unlink(dest)
            elif holds(dest, data):
                # The kit's own bytes: the file keeps the kit's time, so the
                # warm build folder's object for it stays valid (make
                # recompiles only what the submission changed).
                accepted.append(f"stages/{rel}")
                continue
            tmp = dest + ".intake-tmp"
            with open(tmp, "wb") as f:
                f.write(data)
            os.chmod(tmp, 0o644)
            os.replace(tmp, dest)
            accepted.append(f"stages/{rel}")
    report["accepted"] = accepted
    report["ignored"] = [list(i) for i in ignored]
    report["ignored_line"] = group_line(ignored)
    with open(a.report, "w") as f:
        json.dump(report, f, indent=1)
    return 0


# ---- The build log as the student sees it ----

DIAG = re.compile(r"^(?P<path>[^\s:][^:\s]*):(?P<line>\d+):(?:(?P<col>\d+):)?(?P<rest>.*)$")
IN_FUNCTION = re.compile(r"^(?P<path>[^\s:][^:]*): (?P<rest>(In |At global scope|In instantiation).*)$")
INCLUDED = re.compile(r"^(?P<lead>In file included from|\s+from) (?P<path>[^:]+):(?P<line>\d+)(?::\d+)?(?P<end>[:,])$")
LINKER_LOC = re.compile(r"^(?P<path>[^\s:][^:]*):\((?P<rest>.*)$")
SAFE = re.compile(r"^(g?make(\[\d+\])?: |\[\s*\d+%\]|-- |/usr/bin/ld: |collect2: |cc1plus: |g\+\+: |c\+\+: |"
                  r"compilation terminated\.|Scanning dependencies|Consolidate compiler|Built target|"
                  r"CMake (Error|Warning)|ninja: |FAILED: )")
ABS_PATH = re.compile(r"(?<![\w.])/(?:[\w.+-]+/)*[\w.+-]+")


class LogFilter:
    """Decides, line by line, what of a build log the student may see. A
    compiler quotes source lines under a diagnostic; they are kept only under
    one located in an accepted submission file."""

    def __init__(self, tree, build, accepted):
        self.tree = tree.rstrip("/")
        self.build = build.rstrip("/")
        self.accepted = set(accepted)

    def where(self, path):
        """(kind, shown): kind is submission, kit, system or other."""
        p = path if os.path.isabs(path) else os.path.normpath(os.path.join(self.build, path))
        p = os.path.normpath(p)
        if p.startswith(self.tree + "/"):
            rel = p[len(self.tree) + 1:]
            return ("submission" if rel in self.accepted else "kit"), rel
        if p.startswith(self.build + "/"):
            return "kit", "build/" + p[len(self.build) + 1:]
        if p.startswith("/usr/"):
            return "system", "<system>/" + os.path.basename(p)
        return "other", "<elsewhere>"

    def shorten(self, text):
        def repl(m):
            return self.where(m.group(0))[1]
        return ABS_PATH.sub(repl, text)

    def filter(self, lines):
        out = []
        quoting = False
        hidden = 0
        for line in lines:
            m = INCLUDED.match(line)
            if m:
                quoting = False
                kind, shown = self.where(m.group("path"))
                out.append(f"{m.group('lead')} {shown}:{m.group('line')}{m.group('end')}")
                continue
            m = DIAG.match(line)
            if m:
                kind, shown = self.where(m.group("path"))
                quoting = kind == "submission"
                if kind == "other":
                    hidden += 1
                    continue
                col = f"{m.group('col')}:" if m.group("col") else ""
                rest = m.group("rest") if kind == "submission" else self.shorten(m.group("rest"))
                out.append(f"{shown}:{m.group('line')}:{col}{rest}")
                continue
            m = IN_FUNCTION.match(line)
            if m:
                quoting = False
                kind, shown = self.where(m.group("path"))
                if kind == "other":
                    hidden += 1
                    continue
                rest = m.group("rest") if kind == "submission" else self.shorten(m.group("rest"))
                out.append(f"{shown}: {rest}")
                continue
            m = LINKER_LOC.match(line)
            if m and not line.startswith("/usr/bin/ld"):
                quoting = False
                out.append(self.shorten(line))
                continue
            if SAFE.match(line):
                quoting = False
                out.append(self.shorten(line))
                continue
            if quoting:
                out.append(line)
            elif line.strip():
                hidden += 1
        if hidden:
            out.append(f"[{hidden} lines about files outside your submission are not shown]")
        return out


def filtered_log(log, tree, build, accepted):
    try:
        with open(log, errors="replace") as f:
            lines = f.read().splitlines()
    except OSError:
        return []
    return LogFilter(tree, build, accepted).filter(lines)


def accepted_files(report):
    if not report:
        return []
    try:
        with open(report) as f:
            return json.load(f).get("accepted", [])
    except (OSError, ValueError):
        return []


def first_errors(lines):
    """The log's first errors (with the compiler's "In function" and "In file
    included from" lines before them), or its end when it has none."""
    lines = [l for l in lines if not re.match(r"(\[\s*\d+%\]|-- |Scanning dependencies|Consolidate compiler|Built target)", l)]
    first = None
    for pattern in (r": (fatal )?error:|CMake Error|undefined reference|No such file", r"\berror\b"):
        first = next((i for i, l in enumerate(lines) if re.search(pattern, l, re.I)), None)
        if first is not None:
            break
    if first is None:
        return lines[-60:]
    start = first
    while start > 0 and re.search(r"(: In |In file included from|^\s+from )", lines[start - 1]):
        start -= 1
    return lines[start:first + 120]


def cmd_feedback(a):
    for line in filtered_log(a.log, a.tree, a.build, accepted_files(a.intake_report)):
        print(line)
    return 0


def cmd_result(a):
    text = a.message
    if a.log:
        excerpt = first_errors(filtered_log(a.log, a.tree, a.build, accepted_files(a.intake_report)))
        text += "\n\n" + "\n".join(excerpt)
    if len(text) > 50000:
        text = text[:50000] + "\n[... cut ...]"
    out = a.out
    with open(out + ".tmp", "w") as f:
        json.dump({"score": float(a.score), "output": text, "visibility": "visible",
                   "stdout_visibility": "hidden"}, f, indent=2)
        f.write("\n")
    os.replace(out + ".tmp", out)
    return 0


def describe(p):
    st = os.lstat(p)
    if stat.S_ISREG(st.st_mode):
        h = hashlib.sha256()
        with open(p, "rb") as f:
            for chunk in iter(lambda: f.read(1 << 20), b""):
                h.update(chunk)
        digest = h.hexdigest()
    elif stat.S_ISLNK(st.st_mode):
        digest = "link:" + os.readlink(p)
    elif stat.S_ISDIR(st.st_mode):
        digest = "dir"
    else:
        digest = "special"
    return f"{digest} {stat.S_IMODE(st.st_mode):o} {st.st_uid}:{st.st_gid} {p}"


def cmd_manifest(a):
    """One line per file, folder and link under each PATH (links are not
    followed): content hash, mode, owner, path; sorted by path."""
    rows = []
    for top in a.paths:
        if not os.path.lexists(top):
            rows.append(f"missing - - {top}")
            continue
        rows.append(describe(top))
        if not os.path.isdir(top) or os.path.islink(top):
            continue
        for dirpath, dirnames, filenames in os.walk(top, followlinks=False):
            for n in dirnames + filenames:
                rows.append(describe(os.path.join(dirpath, n)))
    rows.sort(key=lambda r: r.split(" ", 3)[3])
    sys.stdout.write("\n".join(rows) + "\n")
    return 0


def cmd_listing(a):
    shown = 0
    for dirpath, dirnames, filenames in os.walk(a.folder, followlinks=False):
        dirnames[:] = sorted(d for d in dirnames if d != ".git")
        depth = os.path.relpath(dirpath, a.folder).count(os.sep) + (dirpath != a.folder)
        if depth >= 3:
            dirnames[:] = []
        for n in sorted(dirnames) + sorted(filenames):
            print("./" + os.path.relpath(os.path.join(dirpath, n), a.folder))
            shown += 1
            if shown >= a.limit:
                return 0
    return 0


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("intake", help="take the submission's sources into the build tree")
    p.add_argument("--kit-stages", required=True, help="the kit's stages/ (which part folders and .cpp files exist)")
    p.add_argument("--submission", required=True)
    p.add_argument("--tree-stages", required=True, help="the build tree's stages/, written into")
    p.add_argument("--report", required=True, help="JSON written: stages, accepted, ignored, ignored_line")
    p = sub.add_parser("feedback", help="the build log, filtered")
    for q in (p, sub.add_parser("result", help="write results.json")):
        q.add_argument("--log", default="")
        q.add_argument("--tree", default="/nonexistent")
        q.add_argument("--build", default="/nonexistent")
        q.add_argument("--intake-report", default="")
    sub.choices["result"].add_argument("--score", required=True)
    sub.choices["result"].add_argument("--message", required=True)
    sub.choices["result"].add_argument("--out", required=True)
    p = sub.add_parser("manifest", help="sha256, mode and owner of every file under PATHS")
    p.add_argument("paths", nargs="+")
    p = sub.add_parser("listing", help="the first entries of a folder")
    p.add_argument("folder")
    p.add_argument("--limit", type=int, default=40)
    a = ap.parse_args(argv)
    return {"intake": cmd_intake, "feedback": cmd_feedback, "result": cmd_result,
            "manifest": cmd_manifest, "listing": cmd_listing}[a.command](a)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
