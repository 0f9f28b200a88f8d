"""What the starter-kit generator's tests share: made-up trees, running the
generator (a copy of it, in each tree) and checking what it did.

    from kit_test_support import *        # in a test script
    sys.exit(run_checks(__doc__, globals()))

A test script's check_NAME(tmp) functions are its checks; run_checks runs
the one its command line names (CHECK SOURCE_DIR) in a temporary folder
and exits 0 when it passed, 1 (with the reason) when not, 2 for a bad
command line.
"""
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap

SOURCE = None  # the repository under test (the command line's SOURCE_DIR)
GENERATOR_DIR = os.path.join("instructors", "starter_kit")


class Failure(Exception):
    pass


def scaled_seconds(seconds):
    """`seconds` times PT_TEST_TIMEOUT_SCALE (tests/timeout_scale/timeout_scale.py)."""
    sys.path.insert(0, os.path.join(SOURCE, "tests", "timeout_scale"))
    import timeout_scale
    return timeout_scale.scaled_seconds(seconds)


def expect(condition, message):
    if not condition:
        raise Failure(message)


def dedent(text):
    return textwrap.dedent(text).lstrip("\n")


def readme(part_title, rows):
    """A stage README with a Given code table of (file, given) rows."""
    table = "".join(f"| `{f}` | {g} | |\n" for f, g in rows)
    return (f"# {part_title}\n\nWhat it teaches.\n\n## Given code\n\n| file | given | what it is |\n"
            f"|---|---|---|\n{table}\n## How to check your work\n\nRun the tests.\n")


def student_cpp(name="solve", header="work.h"):
    return dedent(f"""
        #include "{header}"
        #include "todo.h"

        namespace pt {{

        int {name}(int x) {{
          const int scale = 2;
          // BEGIN SOLUTION
          // STUB: PT_TODO(1);
          // STUB: return 0;
          const int doubled_and_offset_value = x * scale + 1;
          return doubled_and_offset_value;
          // END SOLUTION
        }}

        }}  // namespace pt
        """)


def base_tree(extra=None, given_rows=(("work.h", "whole file"),)):
    """A minimal tree: one stage with a header, a student function and a
    README listing what is given."""
    files = {
        "stages/part1_demo/work.h": dedent("""
            #pragma once
            namespace pt {
            struct Options {
              int scale = 2;
              int twice() const { return 2 * scale; }
            };
            int solve(int x);
            }  // namespace pt
            """),
        "stages/part1_demo/work.cpp": student_cpp(),
        "stages/part1_demo/README.md": readme("Part 1: demo", given_rows),
    }
    files.update(extra or {})
    return files


class Run:
    def __init__(self, code, out, err, dest):
        self.code, self.out, self.err, self.dest = code, out, err, dest


def generate(files, tmp, modes=None, options=()):
    """Writes `files` as a tree in tmp/tree with the generator, runs it (with
    `options` before DEST) to tmp/kit and returns the Run."""
    tree = os.path.join(tmp, "tree")
    shutil.rmtree(tree, ignore_errors=True)
    for rel, text in files.items():
        path = os.path.join(tree, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        if modes and rel in modes:
            os.chmod(path, modes[rel])
    os.makedirs(os.path.join(tree, GENERATOR_DIR), exist_ok=True)
    shutil.copy2(os.path.join(SOURCE, GENERATOR_DIR, "make_starter_kit.py"), os.path.join(tree, GENERATOR_DIR))
    # and the modules it runs, beside it
    shutil.copytree(os.path.join(SOURCE, GENERATOR_DIR, "kitgen"), os.path.join(tree, GENERATOR_DIR, "kitgen"),
                    ignore=shutil.ignore_patterns("__pycache__"))
    dest = os.path.join(tmp, "kit")
    shutil.rmtree(dest, ignore_errors=True)
    p = subprocess.run([sys.executable, os.path.join(tree, GENERATOR_DIR, "make_starter_kit.py"), *options, dest],
                       capture_output=True, text=True, timeout=scaled_seconds(60))
    return Run(p.returncode, p.stdout, p.stderr, dest)


def expect_failure(run, *needles, what, code=1):
    expect(run.code == code,
           f"{what}: the generator exited {run.code}, expected {code} (stderr: {run.err.strip()})")
    lines = run.err.strip().split("\n")
    expect(len(lines) == 1, f"{what}: expected one line on stderr, got: {run.err!r}")
    for n in needles:
        expect(n in lines[0], f"{what}: the message does not name {n!r}: {lines[0]}")
    expect(not os.path.exists(run.dest), f"{what}: the generator wrote {run.dest} although it failed")


def expect_success(run, what):
    expect(run.code == 0, f"{what}: the generator failed ({run.code}): {run.err.strip()}")


def line_of(text, needle):
    for number, line in enumerate(text.split("\n"), 1):
        if needle in line:
            return number
    raise Failure(f"test set-up: {needle!r} not in the text")


def read(run, rel):
    with open(os.path.join(run.dest, rel), encoding="utf-8") as f:
        return f.read()


# ------------------------------------------------------------------ checks
def load_generator():
    spec = importlib.util.spec_from_file_location("make_starter_kit",
                                                  os.path.join(SOURCE, GENERATOR_DIR, "make_starter_kit.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module

def copy_stages(tmp):
    """This tree's stages/, as a dict of files."""
    files = {}
    root = os.path.join(SOURCE, "stages")
    for dirpath, _, names in os.walk(root):
        for n in names:
            path = os.path.join(dirpath, n)
            with open(path, encoding="utf-8") as f:
                files[os.path.relpath(path, SOURCE)] = f.read()
    return files


def region_around(lines, index):
    """(BEGIN index, END index) of the solution region holding lines[index]."""
    b = max(k for k in range(index) if "// BEGIN SOLUTION" in lines[k])
    e = min(k for k in range(index, len(lines)) if "// END SOLUTION" in lines[k])
    return b, e

FAST_PATH = dedent("""
    // REFERENCE ONLY: the kit leaves this file out.
    #pragma once
    namespace pt {
    inline int fast_solve_with_vector_units(int x) { return x * 2 + 1; }
    }  // namespace pt
    """)


def run_checks(doc, namespace):
    """Runs the check the command line names among namespace's check_*."""
    global SOURCE
    checks = {name[len("check_"):]: f for name, f in namespace.items() if name.startswith("check_")}
    if len(sys.argv) != 3 or sys.argv[1] not in checks:
        print(doc.strip() + "\n\nChecks: " + ", ".join(sorted(checks)), file=sys.stderr)
        return 2
    SOURCE = os.path.abspath(sys.argv[2])
    with tempfile.TemporaryDirectory(prefix="kit-generator-") as tmp:
        try:
            checks[sys.argv[1]](tmp)
        except Failure as e:
            print(f"FAIL: {e}")
            return 1
    print(f"PASS: {checks[sys.argv[1]].__doc__.split(chr(10))[0].strip()} ...")
    return 0
