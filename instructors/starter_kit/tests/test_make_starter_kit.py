#!/usr/bin/env python3
"""The starter-kit generator (instructors/starter_kit/make_starter_kit.py)
on small made-up trees, and on a copy of this tree's stages/.

    test_make_starter_kit.py CHECK SOURCE_DIR

Each CHECK writes its trees into a temporary folder, copies the generator
into them, runs it, and exits 0 when the generator did what the check
names, 1 (with the reason) when not.
"""
import os
import sys

sys.dont_write_bytecode = True  # the shared module beside this file leaves no compiled files in the tree
from kit_test_support import (FAST_PATH, Failure, base_tree, copy_stages, dedent, expect, expect_failure,
                              expect_success, generate, line_of, load_generator, read, region_around, run_checks,
                              student_cpp)


# ------------------------------------------------------------------ checks

# Each variant: (what, file, text, the definition's first line, its name).
def unlisted_variants():
    header_inline = dedent("""
        #pragma once
        namespace pt {
        // A helper that no README lists.
        inline float lerp(float a, float b, float t) {
          return a + (b - a) * t;
        }
        }  // namespace pt
        """)
    anonymous_struct = student_cpp() + dedent("""
        namespace pt {
        namespace {
        struct PrimBox {
          float lo, hi;
          float centre() const { return 0.5f * (lo + hi); }
        };
        }  // namespace
        }  // namespace pt
        """)
    constant = student_cpp() + dedent("""
        namespace pt {
        constexpr int kSecretBins = 12;
        }  // namespace pt
        """)
    lambda_var = student_cpp() + dedent("""
        namespace pt {
        namespace {
        const auto halve = [](int x) {
          return x / 2;
        };
        }  // namespace
        }  // namespace pt
        """)
    after_student_function = student_cpp() + dedent("""
        namespace pt {
        int helper_after(int x) { return x + 1; }
        }  // namespace pt
        """)
    in_if_block = student_cpp() + dedent("""
        namespace pt {
        #if defined(__SSE2__)
        int fast_path(int x) { return x; }
        #else
        int fast_path(int x) { return x + 0; }
        #endif
        }  // namespace pt
        """)
    template_class = student_cpp() + dedent("""
        namespace pt {
        template <class T, int N = 4>
        class SmallStack {
         public:
          void push(T v) { items_[size_++] = v; }
         private:
          T items_[N];
          int size_ = 0;
        };
        }  // namespace pt
        """)
    return [
        ("inline function in a header", "stages/part1_demo/extra.h", header_inline, "inline float lerp", "lerp"),
        ("struct with member functions in an anonymous namespace", "stages/part1_demo/work.cpp", anonymous_struct,
         "struct PrimBox", "PrimBox"),
        ("constexpr constant", "stages/part1_demo/work.cpp", constant, "kSecretBins", "kSecretBins"),
        ("variable holding a lambda", "stages/part1_demo/work.cpp", lambda_var, "const auto halve", "halve"),
        ("function after the student's function", "stages/part1_demo/work.cpp", after_student_function,
         "int helper_after", "helper_after"),
        ("function in an #if block", "stages/part1_demo/work.cpp", in_if_block, "int fast_path", "fast_path"),
        ("class template", "stages/part1_demo/work.cpp", template_class, "template <class T", "SmallStack"),
    ]


def check_unlisted_code_outside_markers_fails(tmp):
    """Code outside solution markers that the README does not list stops
    the generator, which names the file, line and definition."""
    for what, rel, text, first, name in unlisted_variants():
        run = generate(base_tree({rel: text}), tmp)
        expect_failure(run, f"{rel}:{line_of(text, first)}:", f" {name} ", "not listed as given",
                       "stages/part1_demo/README.md", what=what)
    # A tree whose README has no Given code section at all.
    files = base_tree()
    files["stages/part1_demo/README.md"] = "# Part 1: demo\n\nNo list here.\n"
    run = generate(files, tmp)
    expect_failure(run, "stages/part1_demo/work.h:3:", " Options ", what="a README without Given code")


def check_listed_given_code_and_student_functions_pass(tmp):
    """Listed given code, student functions (whose lines around the region
    are scaffolding) and definitions inside regions pass; the kit holds the
    given code and the stubs, not the solution."""
    mixed = dedent("""
        #include "work.h"
        #include "todo.h"

        namespace pt {
        namespace {
        // Given: what the builder knows of an item.
        struct Item {
          int value;
          int twice() const { return 2 * value; }
        };
        // BEGIN SOLUTION
        constexpr int kSolutionOnlyConstant = 96;
        struct SolutionBuilder {
          int build(int x) const { return x * kSolutionOnlyConstant; }
        };
        // END SOLUTION
        }  // namespace

        int solve(int x) {
          Item item{x};
          // BEGIN SOLUTION
          // STUB: PT_TODO(1);
          // STUB: return item.value;
          return SolutionBuilder{}.build(item.twice());
          // END SOLUTION
        }

        Glue::Glue(int x) : value_{x}, other_(x) { (void)solve(x); }
        int glue(int x) { return solve(x) + 1; }

        }  // namespace pt
        """)
    files = base_tree({"stages/part1_demo/work.cpp": mixed},
                      given_rows=(("work.h", "whole file"), ("work.cpp", "`Item`, `Glue::Glue`, `glue`")))
    files["stages/part1_demo/work.h"] = files["stages/part1_demo/work.h"].replace(
        "int solve(int x);", "int solve(int x);\nstruct Glue { explicit Glue(int x); int value_, other_; };")
    run = generate(files, tmp)
    expect_success(run, "listed given code")
    kit = read(run, "stages/part1_demo/work.cpp")
    expect("struct Item {" in kit and "int glue(int x)" in kit, "the given code is missing from the kit")
    expect("  PT_TODO(1);\n  return item.value;\n" in kit, f"the stub is missing from the kit:\n{kit}")
    expect("SolutionBuilder" not in kit and "kSolutionOnlyConstant" not in kit and "SOLUTION" not in kit,
           "solution code or markers left in the kit")


def check_untrue_given_list_fails(tmp):
    """A Given code list must be true: no names that are not there, no
    whole file that holds a region, no student function, no missing file,
    and a given column the generator can read."""
    cases = [
        ("a listed name the file does not define", (("work.h", "whole file"), ("work.cpp", "`Vanished`")),
         ["README.md:", "`Vanished`", "work.cpp defines no Vanished"]),
        ("a whole file with a solution region", (("work.h", "whole file"), ("work.cpp", "whole file")),
         ["README.md:", "`work.cpp`", "solution region"]),
        ("a student function listed as given", (("work.h", "whole file"), ("work.cpp", "`solve`")),
         ["README.md:", "`solve`", "holds a solution region"]),
        ("a file that does not exist", (("work.h", "whole file"), ("gone.h", "whole file")),
         ["README.md:", "`gone.h`"]),
        ("a given column in prose", (("work.h", "the whole header, really"),),
         ["README.md:", "the given column"]),
    ]
    for what, rows, needles in cases:
        run = generate(base_tree(given_rows=rows), tmp)
        expect_failure(run, *needles, what=what)



def check_scanner_finds_every_namespace_level_definition(tmp):
    """The brace-matching scanner on code written to mislead it: braces in
    comments, strings, raw strings and character literals, digit
    separators, attributes, templates, constructor initializer lists,
    extern "C", operators and #if branches with uneven braces."""
    m = load_generator()
    text = dedent(r'''
        // A { in a comment, and /* another } here */
        #include <functional>
        #define BLOCK(x) { x }
        namespace pt {
        namespace {
        const char* kText = "a { string } with \" quotes";
        constexpr char kBrace = '{';
        constexpr long kBig = 1'000'000;
        struct alignas(16) Aligned {
          int f() const { return 1; }
          struct Inner { int g() { return 2; } };
        };
        template <class T, int N = 3>
        inline T twice(T x) { return x + x; }
        auto add = [](int a, int b) { return a + b; };
        int table[] = {1, 2, 3};
        using Fn = std::function<int(int)>;
        enum class Color : int { Red, Green };
        class Derived final : public Aligned {
         public:
          Derived() : a_{1}, b_(2) {}
          int a_, b_;
        };
        bool operator==(const Aligned&, const Aligned&) { return true; }
        static_assert(sizeof(int) == 4, "int");
        int declared_only(int x = 3);
        [[nodiscard]] Fn make() { return [](int x) { return x; }; }
        #if defined(__SSE2__)
        int simd() { return 4; }
        #else
        int simd() { return 5; }
        #endif
        #if defined(FOO)
        int branches(int x) {
        #else
        int branches(long x) {
        #endif
          return int(x);
        }
        const char* raw = R"x(a } raw { string)x";
        }  // namespace
        Derived::Derived(int v) : a_(v), b_{v} { if (v) { a_ = 0; } }
        std::vector<int> vec(int n) { return std::vector<int>(n); }
        extern "C" {
        int c_function(void) { return 0; }
        }
        }  // namespace pt
        ''')
    found = [(d.kind, d.name, d.first_line) for d in m.definitions("tricky.cpp", text)]
    wanted = [
        ("constant", "kText", 6), ("constant", "kBrace", 7), ("constant", "kBig", 8), ("struct", "Aligned", 9),
        ("function", "twice", 13), ("variable", "add", 15), ("variable", "table", 16), ("alias", "Fn", 17),
        ("enum", "Color", 18), ("class", "Derived", 19), ("function", "operator==", 24), ("function", "make", 27),
        ("function", "simd", 29), ("function", "simd", 31), ("function", "branches", 34), ("constant", "raw", 40),
        ("function", "Derived::Derived", 42), ("function", "vec", 43), ("function", "c_function", 45),
    ]
    expect(found == wanted, "the scanner found\n  " + "\n  ".join(map(str, found)) + "\nexpected\n  " +
           "\n  ".join(map(str, wanted)))
    try:
        m.definitions("broken.cpp", "namespace pt {\nint f() { return 1;\n}  // namespace pt\n")
    except m.KitError as e:
        expect("broken.cpp" in str(e), f"the unbalanced-brace error does not name the file: {e}")
    else:
        raise Failure("a file with an unclosed brace was accepted")



def check_this_tree_passes_and_would_catch_builder_and_nearest_lane(tmp):
    """This tree's stages pass (their READMEs list all given code), and the
    check catches the BVH builder (struct Builder) and the traversal's
    helper nearest_lane when they are outside their solution regions."""
    stages = copy_stages(tmp)
    run = generate(stages, tmp)
    expect_success(run, "this tree's stages")
    for ref in ("bvh_wide.h", "bvh_binning.h"):
        expect(not os.path.exists(os.path.join(run.dest, "stages/part2_bvh", ref)),
               f"{ref} (REFERENCE ONLY) is in the kit")

    # Builder is the last definition of its region: close the region before it.
    rel = "stages/part2_bvh/bvh_build.cpp"
    lines = stages[rel].split("\n")
    at = next(k for k, l in enumerate(lines) if l.startswith("struct Builder {"))
    b, e = region_around(lines, at)
    moved = lines[:at] + ["// END SOLUTION", ""] + lines[at:e] + lines[e + 1:]
    text = "\n".join(moved)
    run = generate(dict(stages, **{rel: text}), tmp)
    expect_failure(run, f"{rel}:{line_of(text, 'struct Builder {')}:", "struct Builder", "not listed as given",
                   what="Builder outside its region")

    # nearest_lane is the first definition of its region: open the region after it.
    rel = "stages/part2_bvh/bvh_traverse.cpp"
    lines = stages[rel].split("\n")
    at = next(k for k, l in enumerate(lines) if "int nearest_lane(" in l)
    b, e = region_around(lines, at)
    end_of_function = next(k for k in range(at, e) if lines[k] == "}")
    moved = lines[:b] + lines[b + 1:end_of_function + 1] + ["// BEGIN SOLUTION"] + lines[end_of_function + 1:]
    text = "\n".join(moved)
    run = generate(dict(stages, **{rel: text}), tmp)
    expect_failure(run, f"{rel}:{line_of(text, 'int nearest_lane(')}:", "function nearest_lane", "not listed as given",
                   what="nearest_lane outside its region")

    # A given definition dropped from its README's list.
    rel = "stages/part2_bvh/README.md"
    expect("`PrimInfo`, " in stages[rel], "test set-up: part 2's README does not list `PrimInfo`")
    run = generate(dict(stages, **{rel: stages[rel].replace("`PrimInfo`, ", "")}), tmp)
    expect_failure(run, "stages/part2_bvh/bvh_build.cpp:", "struct PrimInfo", what="PrimInfo not listed")


def check_reference_only_file_is_left_out(tmp):
    """A source whose first line starts with "// REFERENCE ONLY" is not in
    the kit; an #include of it inside a solution region goes with the
    region."""
    cpp = student_cpp().replace('#include "todo.h"\n',
                                '#include "todo.h"\n// BEGIN SOLUTION\n#include "fast_path.h"\n// END SOLUTION\n')
    run = generate(base_tree({"stages/part1_demo/fast_path.h": FAST_PATH, "stages/part1_demo/work.cpp": cpp}), tmp)
    expect_success(run, "a reference-only file")
    expect(not os.path.exists(os.path.join(run.dest, "stages/part1_demo/fast_path.h")),
           "the reference-only file is in the kit")
    expect("fast_path.h" not in read(run, "stages/part1_demo/work.cpp"), "the kit still includes the left-out file")
    expect(os.path.exists(os.path.join(run.dest, "stages/part1_demo/work.h")), "an ordinary header went missing")


def check_reference_only_document_is_left_out(tmp):
    """A Markdown file whose first line starts with "<!-- REFERENCE ONLY" is
    not in the kit (a document of the reference's own code, such as
    docs/benchmarks.md); a kit document that links to it stops the
    generator; the same text without the marker is copied."""
    doc = "<!-- REFERENCE ONLY: about the reference's fast path -->\n# Benchmarks\n\nfast_solve 2x\n"
    run = generate(base_tree({"docs/benchmarks.md": doc, "docs/other.md": "# Other\n"}), tmp)
    expect_success(run, "a reference-only document")
    expect(not os.path.exists(os.path.join(run.dest, "docs/benchmarks.md")), "the reference-only document is in the kit")
    expect(os.path.exists(os.path.join(run.dest, "docs/other.md")), "an ordinary document went missing")
    run = generate(base_tree({"docs/benchmarks.md": doc.split("\n", 1)[1]}), tmp)
    expect_success(run, "the same document without the marker")
    expect(os.path.exists(os.path.join(run.dest, "docs/benchmarks.md")), "a document without the marker was left out")
    readme = "# Kit\n\nSpeed: [benchmarks](docs/benchmarks.md).\n"
    run = generate(base_tree({"docs/benchmarks.md": doc, "README.md": readme}), tmp)
    expect_failure(run, "README.md:3:", "docs/benchmarks.md", what="a link to a reference-only document")


def check_kit_including_left_out_file_fails(tmp):
    """A kit file that #includes a left-out file, or a CMake file of the
    kit that names one, stops the generator with the file and line."""
    cpp = student_cpp().replace('#include "todo.h"\n', '#include "todo.h"\n#include "fast_path.h"\n')
    run = generate(base_tree({"stages/part1_demo/fast_path.h": FAST_PATH, "stages/part1_demo/work.cpp": cpp}), tmp)
    expect_failure(run, f"stages/part1_demo/work.cpp:{line_of(cpp, 'fast_path.h')}:",
                   "stages/part1_demo/fast_path.h", "leaves out", what="an #include of a left-out file")
    cmake = "add_library(demo STATIC work.cpp fast_path.h)\n"
    run = generate(base_tree({"stages/part1_demo/fast_path.h": FAST_PATH,
                              "stages/part1_demo/CMakeLists.txt": cmake}), tmp)
    expect_failure(run, "stages/part1_demo/CMakeLists.txt:1:", "fast_path.h", what="a CMake file naming it")


OVERLAY = "instructors/starter_kit/overlay/"
INSTRUCTOR_FILES = [".ci/run", "instructors/README.md", "instructors/CMakeLists.txt",
                    "instructors/gradescope/make_autograder.sh", "instructors/batch/grade_folder.sh",
                    "instructors/mutants/grade_mutants.sh", "instructors/mutants/patches/flip.patch",
                    "instructors/mutants/mutants.txt", "instructors/fuzz/fuzz_cli.cpp",
                    "instructors/fake_student/fake_student.cpp", "instructors/starter_kit/tests/test_starter_kit.sh",
                    OVERLAY + "README.md", OVERLAY + "grader_README.md", OVERLAY + "run.sh"]


def check_instructor_files_left_out_and_overlay_installed(tmp):
    """The instructors' folder (the generator, its overlay and tests among
    its files) and CI stay out whole; the overlay files replace README.md,
    stages/README.md, grader/README.md and scripts/run.sh (executable)."""
    files = base_tree({rel: "#!/bin/sh\n" for rel in INSTRUCTOR_FILES})
    files.update({
        "grader/tables/calibration.md": "# Calibration\n",
        "grader/cases.txt": "p1_demo 1 CBempty.dae\n",
        "tests/instructors_notes.md": "# Not the instructors' folder\n",
        "README.md": "# The reference\n",
        "grader/README.md": "# The grader, for instructors\n",
        "scripts/run.sh": "#!/bin/sh\necho reference\n",
        OVERLAY + "README.md": "# Starter kit: for students\n",
        OVERLAY + "grader_README.md": "# The grader, for students\n",
        OVERLAY + "run.sh": "#!/bin/sh\necho your build\n",
        OVERLAY + "stages_README.md": "# stages/, for students\n",
    })
    run = generate(files, tmp, modes={"instructors/starter_kit/overlay/run.sh": 0o755, "scripts/run.sh": 0o755})
    expect_success(run, "a tree with instructor files and an overlay")
    for rel in INSTRUCTOR_FILES:
        expect(not os.path.exists(os.path.join(run.dest, rel)), f"{rel} is in the kit")
    expect(not os.path.exists(os.path.join(run.dest, "instructors")), "instructors/ is in the kit")
    expect(not os.path.exists(os.path.join(run.dest, ".ci")), ".ci/ is in the kit")
    for rel in ("grader/tables/calibration.md", "grader/cases.txt", "tests/instructors_notes.md"):
        expect(os.path.exists(os.path.join(run.dest, rel)), f"an ordinary file went missing: {rel}")
    expect(read(run, "README.md") == "# Starter kit: for students\n", "README.md is not the overlay's")
    expect(read(run, "grader/README.md") == "# The grader, for students\n", "grader/README.md is not the overlay's")
    expect(read(run, "scripts/run.sh") == "#!/bin/sh\necho your build\n", "scripts/run.sh is not the overlay's")
    expect(read(run, "stages/README.md") == "# stages/, for students\n", "stages/README.md is not the overlay's")
    expect(os.access(os.path.join(run.dest, "scripts/run.sh"), os.X_OK), "the kit's scripts/run.sh is not executable")

    # An overlay file the generator does not know is an error, not ignored.
    run = generate(dict(files, **{OVERLAY + "NOTES.md": "notes\n"}), tmp)
    expect_failure(run, OVERLAY + "NOTES.md", what="an unknown overlay file")


def check_broken_markdown_link_fails(tmp):
    """A relative link of a kit Markdown file to something the kit does not
    hold (e.g. a left-out folder) stops the generator; links that resolve,
    web links, anchors and links in code are fine."""
    good = dedent("""
        # Kit

        See [the demo](stages/part1_demo/README.md), [its folder](stages/part1_demo/),
        [a section](#kit), [the web](https://example.org/x.md) and `[code](nowhere.md)`.

        ```
        [in a code block](nowhere/at/all.md)
        ```
        """)
    run = generate(base_tree({"README.md": good}), tmp)
    expect_success(run, "good links")
    bad = good + "\nThe bugs are in [the mutant list](instructors/mutants/mutants.txt).\n"
    run = generate(base_tree({"README.md": bad, "instructors/mutants/mutants.txt": "flip 1\n"}), tmp)
    expect_failure(run, f"README.md:{line_of(bad, 'mutant list')}:", "instructors/mutants/mutants.txt", what="a link to a left-out file")
    bad = good + "\n[Gradescope](instructors/gradescope/README.md#zip)\n"
    run = generate(base_tree({"stages/part1_demo/notes.md": bad.replace("stages/part1_demo/", "")}), tmp)
    expect_failure(run, "stages/part1_demo/notes.md:", "instructors/gradescope/README.md", what="a missing link target")


def check_documents_name_only_what_the_kit_has(tmp):
    """A kit document that names a repository path the kit does not hold (a
    left-out file, a file that does not exist), a `--target` that the kit's
    CMake files do not define, or a test of a left-out CMake file by its name
    stops the generator, one line naming the document and line; what the kit
    holds, what its commands write (build/, out/) and its own targets pass."""
    cmake = "add_executable(demo main.cpp)\nadd_executable(pathtracer main.cpp)\n"
    left_out = ("add_executable(make_sky make_sky.cpp)\nadd_custom_target(regenerate_sky COMMAND make_sky)\n"
                "add_test(NAME sky_maps_up_to_date COMMAND make_sky --check)\n")
    good = dedent("""
        # Kit

        Run `scripts/run.sh`, then `cmake --build build --target demo pathtracer`; your code is in
        `stages/part1_demo/work.cpp`, the image in `out/image.png`, the binary `build/bin/demo`.

        ```sh
        scripts/run.sh
        ```
        """)
    tree = {"CMakeLists.txt": cmake, "scripts/run.sh": "#!/bin/sh\n", "instructors/CMakeLists.txt": left_out,
            "instructors/scene_generator/make_sky.cpp": "int main() {}\n", "README.md": good}
    run = generate(base_tree(tree), tmp)
    expect_success(run, "a document naming what the kit has")
    bad = {
        "a left-out file": ("The maps come from `instructors/scene_generator/make_sky.cpp`.",
                            "instructors/scene_generator/make_sky.cpp"),
        "a file that does not exist": ("See stages/part1_demo/missing.cpp.", "stages/part1_demo/missing.cpp"),
        "a left-out target": ("Regenerate: `cmake --build build --target regenerate_sky`.", "regenerate_sky"),
        "a left-out test": ("The test `sky_maps_up_to_date` checks them.", "sky_maps_up_to_date"),
    }
    for what, (line, needle) in bad.items():
        text = good + "\n" + line + "\n"
        run = generate(base_tree(dict(tree, **{"README.md": text})), tmp)
        expect_failure(run, f"README.md:{line_of(text, line)}:", needle, what=what)


def check_overlay_quoting_solution_line_fails(tmp):
    """An overlay file that quotes a solution line, of a region or of a
    reference-only file, leaks it, and so does a document of the tree: the
    generator refuses."""
    overlay = {"instructors/starter_kit/overlay/README.md": "# Kit\n\n    const int doubled_and_offset_value = x * scale + 1;\n",
               "instructors/starter_kit/overlay/grader_README.md": "# Grader\n", "instructors/starter_kit/overlay/run.sh": "#!/bin/sh\n",
               "instructors/starter_kit/overlay/stages_README.md": "# Stages\n"}
    run = generate(base_tree(overlay), tmp)
    expect_failure(run, "README.md:3:", "solution line leaked", what="an overlay quoting a solution line")
    # And reference-only files count as solution.
    overlay["instructors/starter_kit/overlay/README.md"] = "# Kit\n\n    inline int fast_solve_with_vector_units(int x) { return x * 2 + 1; }\n"
    run = generate(base_tree(dict(overlay, **{"stages/part1_demo/fast_path.h": FAST_PATH})), tmp)
    expect_failure(run, "README.md:3:", "solution line leaked", what="an overlay quoting a reference-only file")
    # A document of the reference copied into the kit leaks the line as well.
    notes = "# Notes\n\n    const int doubled_and_offset_value = x * scale + 1;\n"
    run = generate(base_tree({"stages/part1_demo/notes.md": notes}), tmp)
    expect_failure(run, "stages/part1_demo/notes.md:3:", "solution line leaked", what="a document quoting a solution line")


def check_emptied_helper_namespace_gets_a_hint(tmp):
    """An unnamed namespace that held only solution helpers is left with a
    comment saying the student's helpers go there; one that keeps given
    code, and a namespace in a file without regions, are unchanged."""
    emptied = dedent("""
        #include "work.h"
        #include "todo.h"

        namespace pt {

        namespace {
        // BEGIN SOLUTION
        int helper_that_triples_its_argument(int x) { return 3 * x; }
        // END SOLUTION
        }  // namespace

        int solve(int x) {
          // BEGIN SOLUTION
          // STUB: PT_TODO(1);
          // STUB: return 0;
          return helper_that_triples_its_argument(x) + 1;
          // END SOLUTION
        }

        }  // namespace pt
        """)
    run = generate(base_tree({"stages/part1_demo/work.cpp": emptied}), tmp)
    expect_success(run, "a file whose helper namespace is all solution")
    text = read(run, "stages/part1_demo/work.cpp")
    expect("namespace {\n\n// Your helper functions go here.\n\n}  // namespace" in text,
           f"the emptied namespace has no hint:\n{text}")
    expect(text.count("Your helper functions go here.") == 1, "the hint is there more than once")

    kept = emptied.replace("namespace {\n", "namespace {\nconst int kGivenScale = 2;\n", 1)
    given = (("work.h", "whole file"), ("work.cpp", "`kGivenScale`"))
    run = generate(base_tree({"stages/part1_demo/work.cpp": kept}, given_rows=given), tmp)
    expect_success(run, "a helper namespace that keeps given code")
    expect("Your helper functions go here." not in read(run, "stages/part1_demo/work.cpp"),
           "a namespace holding given code got the hint")


def check_stripped_file_keeps_the_project_layout(tmp):
    """A kit file reads like the project's: a helper region between blank
    lines leaves one blank line, stubs are indented like their region and
    keep their own inner indentation."""
    text = dedent("""
        #include "work.h"
        #include "todo.h"

        namespace pt {

        namespace {

        struct Given {
          int v;
        };

        // BEGIN SOLUTION
        int solution_helper_that_doubles(int x) { return 2 * x; }
        // END SOLUTION

        }  // namespace

        int solve(int x) {
          if (x > 0) {
            // BEGIN SOLUTION
            // STUB: PT_TODO(1);
            // STUB: for (int i = 0; i < x; ++i) {
            // STUB:   unused(i);
            // STUB: }
            return solution_helper_that_doubles(x) + Given{x}.v;
            // END SOLUTION
          }
          return 0;
        }

        }  // namespace pt
        """)
    run = generate(base_tree({"stages/part1_demo/work.cpp": text},
                             given_rows=(("work.h", "whole file"), ("work.cpp", "`Given`"))), tmp)
    expect_success(run, "a file with a helper region between blank lines")
    kit = read(run, "stages/part1_demo/work.cpp")
    expect("};\n\n}  // namespace\n" in kit, f"the removed region left extra blank lines:\n{kit}")
    expect("\n\n\n" not in kit, f"two blank lines in a row:\n{kit}")
    expect("  if (x > 0) {\n    PT_TODO(1);\n    for (int i = 0; i < x; ++i) {\n      unused(i);\n    }\n  }\n" in kit,
           f"the stub is not indented like its region:\n{kit}")


def check_todo_part_must_match_its_folder(tmp):
    """A stub's PT_TODO in stages/partK_*/ must name part K: the grader
    reads the part from the line it prints."""
    run = generate(base_tree(), tmp)
    expect_success(run, "PT_TODO(1) in part 1")
    wrong = student_cpp().replace("PT_TODO(1);", "PT_TODO(3);")
    run = generate(base_tree({"stages/part1_demo/work.cpp": wrong}), tmp)
    expect_failure(run, f"stages/part1_demo/work.cpp:{line_of(wrong, 'PT_TODO(3)')}:", "part 3", "part 1 folder",
                   what="PT_TODO(3) in part 1")
    named = student_cpp().replace("PT_TODO(1);", 'PT_TODO_AS(2, "Work::solve", "a note");')
    run = generate(base_tree({"stages/part1_demo/work.cpp": named}), tmp)
    expect_failure(run, "stages/part1_demo/work.cpp:", "part 2", what="PT_TODO_AS(2, ...) in part 1")



if __name__ == "__main__":
    sys.exit(run_checks(__doc__, globals()))
