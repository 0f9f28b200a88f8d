#!/usr/bin/env python3
"""Unit tests of submission_tools.py: what the intake takes from a
submission, what the build log's filter lets a student see, what the
manifest notices. python3 -m unittest, or run this file."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import submission_tools as st  # noqa: E402

TOOL = os.path.join(HERE, "submission_tools.py")


def write(path, text="int x;\n", mode=None):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)
    if mode is not None:
        os.chmod(path, mode)


class Intake(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        t = self.tmp.name
        self.kit = os.path.join(t, "kit")
        for part in ("part1_raytracing", "part2_bvh"):
            write(f"{self.kit}/{part}/a.cpp", "// kit a\n")
            write(f"{self.kit}/{part}/a.h", "// kit a.h\n")
            write(f"{self.kit}/{part}/CMakeLists.txt", "add_library(x a.cpp)\n")
            write(f"{self.kit}/{part}/README.md", "# part\n")
        write(f"{self.kit}/CMakeLists.txt", "add_subdirectory(part1_raytracing)\n")
        self.tree = os.path.join(t, "tree")
        subprocess.run(["cp", "-R", self.kit, self.tree], check=True)
        self.sub = os.path.join(t, "submission")
        self.report = os.path.join(t, "report.json")

    def tearDown(self):
        self.tmp.cleanup()

    def intake(self):
        rc = subprocess.run([sys.executable, TOOL, "intake", "--kit-stages", self.kit, "--submission", self.sub,
                             "--tree-stages", self.tree, "--report", self.report]).returncode
        with open(self.report) as f:
            return rc, json.load(f)

    def tree_text(self, rel):
        with open(os.path.join(self.tree, rel)) as f:
            return f.read()

    def test_takes_the_part_folders_sources_and_nothing_else(self):
        s = f"{self.sub}/kit/stages"
        write(f"{s}/part1_raytracing/a.cpp", "// mine\n")
        write(f"{s}/part1_raytracing/helper.h", "// my header\n")
        write(f"{s}/part1_raytracing/extra.cpp", "// a .cpp the kit does not have\n")
        write(f"{s}/part1_raytracing/CMakeLists.txt", "execute_process(COMMAND evil)\n")
        write(f"{s}/part1_raytracing/README.md", "# part\n")  # the kit's, unchanged: not listed
        write(f"{s}/part1_raytracing/notes.txt", "hello\n")
        write(f"{s}/part1_raytracing/sub/b.h", "// in a subfolder\n")
        write(f"{s}/CMakeLists.txt", "execute_process(COMMAND evil)\n")
        write(f"{s}/part2_bvh/a.h", "// mine too\n")
        os.symlink("/etc/passwd", f"{s}/part2_bvh/a.cpp")
        write(f"{self.sub}/kit/CMakeLists.txt", "evil\n")
        rc, r = self.intake()
        self.assertEqual(rc, 0)
        self.assertEqual(r["stages"], "kit/stages")
        self.assertEqual(sorted(r["accepted"]), ["stages/part1_raytracing/a.cpp", "stages/part1_raytracing/helper.h",
                                                 "stages/part2_bvh/a.h"])
        self.assertEqual(self.tree_text("part1_raytracing/a.cpp"), "// mine\n")
        self.assertEqual(self.tree_text("part2_bvh/a.cpp"), "// kit a\n")  # the link was not followed
        self.assertEqual(self.tree_text("part1_raytracing/CMakeLists.txt"), "add_library(x a.cpp)\n")
        self.assertEqual(self.tree_text("CMakeLists.txt"), "add_subdirectory(part1_raytracing)\n")
        self.assertFalse(os.path.exists(os.path.join(self.tree, "part1_raytracing/extra.cpp")))
        self.assertFalse(os.path.exists(os.path.join(self.tree, "part1_raytracing/sub")))
        line = r["ignored_line"]
        self.assertNotIn("\n", line)
        for what in ("build files", "links", ".cpp files the kit does not have", "files that are not .cpp or .h",
                     "subfolders", "part1_raytracing/CMakeLists.txt", "part2_bvh/a.cpp"):
            self.assertIn(what, line)
        self.assertNotIn("README.md", line)
        self.assertIn("build files: CMakeLists.txt, part1_raytracing/CMakeLists.txt;", line)

    def test_a_file_unchanged_from_the_kit_keeps_its_time_a_changed_one_is_new(self):
        # The warm build folder's objects stay valid for the kit's own bytes only.
        old = 1_000_000_000
        for rel in ("part1_raytracing/a.cpp", "part1_raytracing/a.h", "part2_bvh/a.cpp"):
            os.utime(os.path.join(self.tree, rel), (old, old))
        s = f"{self.sub}/stages"
        write(f"{s}/part1_raytracing/a.cpp", "// kit a\n")  # the kit's bytes
        write(f"{s}/part1_raytracing/a.h", "// kit a.h, changed\n")
        write(f"{s}/part2_bvh/a.cpp", "// kit a\n\n")  # one byte more
        rc, r = self.intake()
        self.assertEqual(rc, 0)
        self.assertEqual(sorted(r["accepted"]), ["stages/part1_raytracing/a.cpp", "stages/part1_raytracing/a.h",
                                                 "stages/part2_bvh/a.cpp"])
        mtime = lambda rel: os.stat(os.path.join(self.tree, rel)).st_mtime  # noqa: E731
        self.assertEqual(mtime("part1_raytracing/a.cpp"), old)
        self.assertGreater(mtime("part1_raytracing/a.h"), old)
        self.assertGreater(mtime("part2_bvh/a.cpp"), old)
        self.assertEqual(self.tree_text("part1_raytracing/a.h"), "// kit a.h, changed\n")
        self.assertEqual(self.tree_text("part2_bvh/a.cpp"), "// kit a\n\n")

    def test_size_limits(self):
        s = f"{self.sub}/stages"
        write(f"{s}/part1_raytracing/a.cpp", "x" * (st.MAX_FILE_BYTES + 1))
        for i in range(9):
            write(f"{s}/part2_bvh/big{i}.h", "y" * (st.MAX_FILE_BYTES - 10))
        rc, r = self.intake()
        self.assertEqual(rc, 0)
        self.assertNotIn("stages/part1_raytracing/a.cpp", r["accepted"])
        self.assertEqual(len(r["accepted"]), st.MAX_TOTAL_BYTES // (st.MAX_FILE_BYTES - 10))
        self.assertIn("files over 256 KB", r["ignored_line"])
        self.assertIn("past the 2 MB limit", r["ignored_line"])

    def test_the_shallowest_stages_and_no_linked_part_folder(self):
        write(f"{self.sub}/deep/er/stages/part1_raytracing/a.cpp", "// deep\n")
        write(f"{self.sub}/top/stages/part2_bvh/a.cpp", "// shallow\n")
        os.makedirs(f"{self.sub}/linked")
        os.symlink(f"{self.sub}/deep/er/stages/part1_raytracing", f"{self.sub}/linked/part1_raytracing")
        rc, r = self.intake()
        self.assertEqual(r["stages"], "top/stages")
        self.assertEqual(r["accepted"], ["stages/part2_bvh/a.cpp"])

    def test_no_stages(self):
        write(f"{self.sub}/main.cpp")
        rc, r = self.intake()
        self.assertEqual(rc, 3)
        self.assertIsNone(r["stages"])


class Feedback(unittest.TestCase):
    TREE = "/ag/sandbox/tree"
    BUILD = "/ag/sandbox/build"

    def run_filter(self, text, accepted=("stages/part1_raytracing/sphere.cpp",)):
        return st.LogFilter(self.TREE, self.BUILD, accepted).filter(text.splitlines())

    def test_quotes_only_under_the_submissions_own_diagnostics(self):
        log = f"""[ 40%] Building CXX object stages/part1_raytracing/CMakeFiles/x.dir/sphere.cpp.o
In file included from {self.TREE}/stages/part1_raytracing/sphere.cpp:3:
/autograder/source/project/reference_images/p1_teapot/meta.json:1:1: error: 'CANARY_ONE' does not name a type
    1 | CANARY_ONE p1_teapot 12
      | ^~~~~~~~~~
/autograder/source/project/grader/cases.txt:2:1: error: expected unqualified-id
    2 | CANARY_TWO p1_empty
/etc/passwd:1:5: error: found ':' in nested-name-specifier
    1 | root:x:0:0:CANARY_THREE
{self.TREE}/stages/part1_raytracing/sphere.cpp:10:3: error: 'foo' was not declared in this scope
   10 |   foo();
      |   ^~~
{self.TREE}/common/vec3.h:5:8: note: candidate: 'bar'
    5 | struct CANARY_KIT {{}};
gmake[2]: *** [stages/part1_raytracing/CMakeFiles/x.dir/build.make:76: sphere.cpp.o] Error 1
"""
        out = "\n".join(self.run_filter(log))
        for canary in ("CANARY_ONE p1_teapot", "CANARY_TWO", "CANARY_THREE", "CANARY_KIT", "/autograder", "/etc/passwd",
                       self.TREE, "cases.txt", "root:x"):
            self.assertNotIn(canary, out)
        self.assertIn("stages/part1_raytracing/sphere.cpp:10:3: error: 'foo' was not declared in this scope", out)
        self.assertIn("   10 |   foo();", out)
        self.assertIn("In file included from stages/part1_raytracing/sphere.cpp:3:", out)
        self.assertIn("common/vec3.h:5:8: note: candidate: 'bar'", out)
        self.assertIn("lines about files outside your submission are not shown", out)

    def test_first_errors_of_a_filtered_log(self):
        log = f"{self.TREE}/stages/part1_raytracing/sphere.cpp:2:1: error: expected ';'\n    2 | int x\n"
        lines = st.first_errors(self.run_filter(log))
        self.assertEqual(lines[0], "stages/part1_raytracing/sphere.cpp:2:1: error: expected ';'")
        self.assertEqual(lines[1], "    2 | int x")


class Manifest(unittest.TestCase):
    def manifest(self, d):
        return subprocess.run([sys.executable, TOOL, "manifest", d], check=True, capture_output=True, text=True).stdout

    def test_notices_content_mode_and_new_files(self):
        with tempfile.TemporaryDirectory() as d:
            write(f"{d}/refs/p1/mean.pfm", "PF\n")
            before = self.manifest(d)
            self.assertEqual(before, self.manifest(d))
            write(f"{d}/refs/p1/mean.pfm", "PG\n")
            changed = self.manifest(d)
            self.assertNotEqual(before, changed)
            os.chmod(f"{d}/refs/p1/mean.pfm", 0o666)
            self.assertNotEqual(changed, self.manifest(d))
            mode = self.manifest(d)
            write(f"{d}/refs/p2/meta.json", "{}")
            self.assertNotEqual(mode, self.manifest(d))


if __name__ == "__main__":
    unittest.main()
