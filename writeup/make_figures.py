#!/usr/bin/env python3
"""Render the write-up's figures and lay them out as a page.

    python3 writeup/make_figures.py [--quick] [--pathtracer PATH] [-t N] [--out DIR]

Reads the figure recipes (writeup/figures.toml), renders every figure with a
pathtracer binary (default build/bin/pathtracer), several renders at once
within the -t thread budget, and writes OUT/index.html and OUT/index.md
(default OUT: writeup/out). Each render is cached under OUT/cache by a hash
of its command line, of the binary's bytes and of the scene file's bytes,
so a second run renders only what changed. See writeup/README.md; the code
is the package writeup/generator/ (its __init__.py lists the modules).

Exit status: 0 when every render succeeded and no figure is flagged; 1
when some render failed (the page is still written and shows them); 2 for
bad input (recipes, binary, options); 3 when every render ran but some
figure is flagged: the renderer printed a "TODO:" line for it (a function
not written yet) or its image is all black (the page shows which and why).
A failed render takes precedence: 1 even if some figure is flagged too.
"""

import os
import sys

if sys.version_info < (3, 11):  # tomllib
    sys.stderr.write("make_figures.py: error: Python 3.11 or newer is needed (tomllib)\n")
    sys.exit(2)

sys.dont_write_bytecode = True  # nothing written into the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from generator.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
