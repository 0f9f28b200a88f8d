"""PT_TEST_TIMEOUT_SCALE for the tests written in Python (README, "Tests"):
a number > 0 such as 2 or 2.5, default 1, that multiplies every timeout a
test gives the programs it runs, as it multiplies the tests' own TIMEOUT in
ctest."""

import math
import os
import re


def timeout_scale():
    """The scale; ValueError naming the variable when it is not such a number."""
    s = os.environ.get("PT_TEST_TIMEOUT_SCALE", "") or "1"
    if not re.fullmatch(r"[0-9]+(\.[0-9]*)?", s) or float(s) <= 0:
        raise ValueError(f"PT_TEST_TIMEOUT_SCALE={s}: not a number > 0 such as 2 or 2.5")
    return float(s)


def scaled_seconds(seconds):
    """`seconds` times the scale, rounded up to a second."""
    return math.ceil(seconds * timeout_scale())
