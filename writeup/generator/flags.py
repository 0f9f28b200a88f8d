"""The pathtracer's command line as the recipes write it: flags, their
values, and which flags the generator sets itself."""

import shlex
from types import MappingProxyType

from .base import InputError

# The pathtracer's flags and how many values each takes (pathtracer --help).
FLAG_ARITY = MappingProxyType({
    "-s": 1, "-l": 1, "-t": 1, "-m": 1, "-o": 1, "-e": 1, "-b": 1, "-d": 1,
    "-f": 1, "-r": 2, "-c": 1, "-a": 2, "-H": 0, "--bsdf-hemisphere": 0, "-p": 4, "--part": 1,
    "--seed": 1, "--pfm": 1, "--stats-json": 1, "--bvh-leaf": 1,
    "--bvh-bins": 1, "--bvh-boxes": 1, "--bvh-node": 1, "--no-rr": 0, "--direct-only": 0, "--indirect-only": 0,
    "--course-area-pdf": 0, "--no-progress": 0, "--env-probability": 1,
})
# Set by the generator itself (from size, seed, the scheduler and the cache).
GENERATED_FLAGS = MappingProxyType({"-r": "size", "--seed": "seed", "-t": "threads",
                                   "-f": None, "--stats-json": None, "--no-progress": None,
                                   "--pfm": None, "--env-probability": "env_probability"})
FILE_FLAGS = ("-e", "-c")  # their files' bytes are part of the cache key


def parse_flags(text, where):
    """pathtracer arguments as a list of (flag, [values])."""
    if not isinstance(text, str):
        raise InputError(f"{where}: 'args' must be a string of pathtracer flags")
    try:
        tokens = shlex.split(text)
    except ValueError as e:
        raise InputError(f"{where}: cannot split args '{text}': {e}")
    flags = []
    i = 0
    while i < len(tokens):
        tok = tokens[i]
        if tok not in FLAG_ARITY:
            raise InputError(f"{where}: unknown pathtracer flag '{tok}' in args '{text}'")
        if tok in GENERATED_FLAGS:
            field = GENERATED_FLAGS[tok]
            hint = f" (use the recipe's '{field}' field)" if field else ""
            raise InputError(f"{where}: the generator sets {tok} itself{hint}")
        n = FLAG_ARITY[tok]
        vals = tokens[i + 1:i + 1 + n]
        if len(vals) != n or any(v in FLAG_ARITY for v in vals):
            raise InputError(f"{where}: {tok} needs {n} value(s) in args '{text}'")
        flags.append((tok, list(vals)))
        i += 1 + n
    return flags


def merge_flags(base, extra):
    """base's flags with extra's: a flag in both takes extra's values in base's place."""
    out = [(f, list(v)) for f, v in base]
    for flag, vals in extra:
        for i, (f, _) in enumerate(out):
            if f == flag:
                out[i] = (flag, list(vals))
                break
        else:
            out.append((flag, list(vals)))
    return out


def get_flag(flags, flag, default=None):
    for f, v in flags:
        if f == flag:
            return v
    return default


def set_flag(flags, flag, vals):
    return merge_flags(flags, [(flag, vals)])


def flat(flags):
    out = []
    for f, v in flags:
        out.append(f)
        out.extend(v)
    return out


def recipe_args(r):
    """The render's arguments that decide the image (no threads, no output paths)."""
    return flat(r.flags) + ["-r", str(r.size[0]), str(r.size[1]), "--seed", str(r.seed)]
