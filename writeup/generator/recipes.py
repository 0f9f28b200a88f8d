"""The figure recipes (writeup/figures.toml): parsed, checked, and expanded
into the renders of the page. Any unknown field or bad value is an
InputError naming the file and the recipe."""

import fnmatch
import math
import os
import re
import shlex
import tomllib

from .base import ROOT, InputError, display_path
from .flags import FILE_FLAGS, get_flag, merge_flags, parse_flags, set_flag

SETTINGS_KEYS = frozenset({"title", "scenes_dir", "size", "seed", "quick_size",
                           "quick_max_samples", "quick_max_light_samples"})
SECTION_KEYS = frozenset({"id", "title", "text", "grid", "table"})
GRID_KEYS = frozenset({"id", "title", "text", "scene", "args", "size", "quick_size", "quick_max_samples", "seed",
                       "columns", "rate", "env_probability", "vary", "cells", "expect_black"})
CELL_KEYS = frozenset({"label", "name", "scene", "args", "size", "quick_size", "quick_max_samples", "seed",
                       "expect_black"})
# Flags that draw over the PNG, which the preview made from the PFM would
# not show: a figure with one is rendered at its full size in --quick.
OVERLAY_FLAGS = ("--bvh-boxes", "--bvh-node")
VARY_KEYS = frozenset({"flag", "values"})
TABLE_KEYS = frozenset({"id", "title", "text", "scene", "scenes", "args", "size", "quick_size",
                        "seed", "threads", "exclusive", "variants", "columns"})
VARIANT_KEYS = frozenset({"label", "args"})
COLUMN_KEYS = frozenset({"title", "field", "variant", "ratio"})


def check_keys(table, known, where):
    if not isinstance(table, dict):
        raise InputError(f"{where}: expected a table, got {type(table).__name__}")
    for k in table:
        if k not in known:
            raise InputError(f"{where}: unknown field '{k}' (known fields: {', '.join(sorted(known))})")


def want(value, types, where, what):
    """value if it has one of the types (a bool is not taken for an int)."""
    types = types if isinstance(types, tuple) else (types,)
    if not isinstance(value, types) or (isinstance(value, bool) and bool not in types):
        names = " or ".join({str: "a string", int: "an integer", bool: "true or false",
                             list: "a list", dict: "a table"}.get(t, t.__name__) for t in types)
        raise InputError(f"{where}: '{what}' must be {names}, got {value!r}")
    return value


def want_size(value, where, what="size"):
    if (not isinstance(value, list) or len(value) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in value)):
        raise InputError(f"{where}: '{what}' must be [width, height] with positive integers, got {value!r}")
    return (value[0], value[1])


def slug(text):
    s = re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_").lower()
    return s or "render"


# The images a grid may show beside each render: (recipe field, the file
# in the render's cache entry, the suffix of the figure's copy, caption).
SIDE_IMAGES = (
    ("rate", "render_rate.png", "_rate", "sampling rate"),
    ("env_probability", "render_env_probability.png", "_env_probability", "where the map is sampled"),
)


class Render:
    """One image of the page (a grid cell or a table entry)."""

    def __init__(self, **kw):
        self.__dict__.update(kw)
        self.job = None
        self.rate = False
        self.env_probability = False
        self.expect_black = False
        self.preview = 1  # --quick: the image is shrunk this many times from the render (preview.py)

    def side_images(self):
        """The (cache file, figure file suffix, caption) of each image shown beside the render."""
        return [(f, suffix, caption) for field, f, suffix, caption in SIDE_IMAGES if getattr(self, field)]


class Recipes:
    """A recipe file: settings, sections of grids and tables, and every render
    they ask for (quick caps applied when quick)."""

    def __init__(self, path, quick):
        self.path = path
        self.display = display_path(path)
        try:
            with open(path, "rb") as f:
                data = tomllib.load(f)
        except FileNotFoundError:
            raise InputError(f"{self.display}: recipe file not found")
        except tomllib.TOMLDecodeError as e:
            raise InputError(f"{self.display}: not valid TOML: {e}")
        self.quick = quick
        check_keys(data, {"settings", "section"}, self.display)
        self._settings(data.get("settings", {}))
        self.sections = []
        self.renders = []
        ids = set()
        sections = data.get("section", [])
        if not isinstance(sections, list) or not sections:
            raise InputError(f"{self.display}: no [[section]]")
        for n, sec in enumerate(sections, 1):
            self.sections.append(self._section(sec, n, ids))

    def _settings(self, s):
        where = f"{self.display}: [settings]"
        check_keys(s, SETTINGS_KEYS, where)
        self.title = want(s.get("title", "PathTracer write-up figures"), str, where, "title")
        scenes_dir = want(s.get("scenes_dir", "../scenes"), str, where, "scenes_dir")
        self.scenes_dir = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(self.path)), scenes_dir))
        self.size = want_size(s.get("size", [480, 360]), where)
        self.seed = want(s.get("seed", 1), int, where, "seed")
        self.quick_size = want_size(s.get("quick_size", [120, 90]), where, "quick_size")
        self.quick_max_samples = want(s.get("quick_max_samples", 1), int, where, "quick_max_samples")
        self.quick_max_light_samples = want(s.get("quick_max_light_samples", 4), int, where,
                                            "quick_max_light_samples")

    def _section(self, sec, n, ids):
        where = f"{self.display}: section {n}"
        check_keys(sec, SECTION_KEYS, where)
        sid = want(sec.get("id", f"section{n}"), str, where, "id")
        where = f"{self.display}: section '{sid}'"
        section = {"id": sid, "title": want(sec.get("title", sid), str, where, "title"),
                   "text": want(sec.get("text", ""), str, where, "text"), "items": []}
        for g in want(sec.get("grid", []), list, where, "grid"):
            section["items"].append(self._grid(g, ids, where))
        for t in want(sec.get("table", []), list, where, "table"):
            section["items"].append(self._table(t, ids, where))
        return section

    def select(self, only):
        """Keep only the grids and tables whose ids match one of the comma-separated
        shell patterns of `only` (--only); a pattern matching none is an error."""
        pats = [p.strip() for p in only.split(",") if p.strip()]
        all_ids = [it["id"] for s in self.sections for it in s["items"]]
        for p in pats:
            if not any(fnmatch.fnmatchcase(i, p) for i in all_ids):
                raise InputError(f"--only: no grid or table matches '{p}' in {self.display}")
        for s in self.sections:
            s["items"] = [it for it in s["items"] if any(fnmatch.fnmatchcase(it["id"], p) for p in pats)]
        self.sections = [s for s in self.sections if s["items"]]
        keep = {it["id"] for s in self.sections for it in s["items"]}
        self.renders = [r for r in self.renders if r.grid in keep]

    def _id(self, item, ids, where, kind):
        if "id" not in item:
            raise InputError(f"{where}: a {kind} has no 'id'")
        gid = want(item["id"], str, where, "id")
        if not re.fullmatch(r"[A-Za-z0-9_-]+", gid):
            raise InputError(f"{where}: {kind} id '{gid}' may only hold letters, digits, '_' and '-'")
        if gid in ids:
            raise InputError(f"{where}: {kind} id '{gid}' is used twice")
        ids.add(gid)
        return gid

    def _scene(self, name, where):
        if not isinstance(name, str) or not name:
            raise InputError(f"{where}: no 'scene'")
        path = name if os.path.isabs(name) else os.path.join(self.scenes_dir, name)
        if not os.path.isfile(path):
            raise InputError(f"{where}: scene file not found: {display_path(path)}")
        return os.path.abspath(path)

    def _quick_caps(self, flags, quick_max_samples):
        """A quick render's flags: -s, -l and the -a batch capped (a batch at
        most a quarter of -s, so that a pixel can still stop early)."""
        s = get_flag(flags, "-s")
        if s is not None and int(s[0]) > quick_max_samples:
            flags = set_flag(flags, "-s", [str(quick_max_samples)])
        l = get_flag(flags, "-l")
        if l is not None and int(l[0]) > self.quick_max_light_samples:
            flags = set_flag(flags, "-l", [str(self.quick_max_light_samples)])
        a = get_flag(flags, "-a")
        if a is not None:
            batch = max(1, int(get_flag(flags, "-s", ["1"])[0]) // 4)
            if int(a[0]) > batch:
                flags = set_flag(flags, "-a", [str(batch), a[1]])
        return flags

    def _render(self, where, gid, name, label, scene, flags, size, quick_size, seed, threads=None, exclusive=False,
                quick_max_samples=None, image=True):
        """One render. In --quick, an image (a grid's) is rendered at its full
        size, the whole view, with few samples and shown shrunk to at most
        quick_size (preview); a table's render, whose numbers are all that is
        shown, is rendered at quick_size (the centre of the view)."""
        scene_path = self._scene(scene, where)
        quick_exclusive, preview = False, 1
        if self.quick:
            # Quick renders are checks, not timings: no render needs to run alone.
            quick_exclusive, exclusive = exclusive, False
            flags = self._quick_caps(flags, quick_max_samples or self.quick_max_samples)
            if not image:
                size = (min(size[0], quick_size[0]), min(size[1], quick_size[1]))
            elif not any(get_flag(flags, f) is not None for f in OVERLAY_FLAGS):
                preview = max(1, math.ceil(max(size[0] / quick_size[0], size[1] / quick_size[1])))
        for flag in FILE_FLAGS:
            v = get_flag(flags, flag)
            if v is not None:
                p = v[0] if os.path.isabs(v[0]) else os.path.join(ROOT, v[0])
                if not os.path.isfile(p):
                    raise InputError(f"{where}: {flag} file not found: {v[0]}")
                flags = set_flag(flags, flag, [os.path.abspath(p)])
        r = Render(where=where, grid=gid, name=name, label=label, scene=scene_path,
                   flags=flags, size=size, seed=seed, threads=threads, exclusive=exclusive,
                   quick_exclusive=quick_exclusive)
        r.preview = preview
        self.renders.append(r)
        return r

    def _shared_fields(self, x, where):
        """The fields grids and tables share: args, size, quick_size, seed."""
        base = parse_flags(x.get("args", ""), where)
        size = want_size(x["size"], where) if "size" in x else self.size
        qsize = want_size(x["quick_size"], where, "quick_size") if "quick_size" in x else self.quick_size
        seed = want(x.get("seed", self.seed), int, where, "seed")
        return base, size, qsize, seed

    def _expect_black(self, value, where):
        """A recipe's expect_black (true, false or "quick") as a yes or no for this run."""
        if value not in (True, False, "quick"):
            raise InputError(f"{where}: 'expect_black' must be true, false or \"quick\", got {value!r}")
        return value is True or (value == "quick" and self.quick)

    def _grid(self, g, ids, where):
        gid = self._id(g, ids, where, "grid")
        where = f"{self.display}: grid '{gid}'"
        check_keys(g, GRID_KEYS, where)
        base, size, qsize, seed = self._shared_fields(g, where)
        qmax = g.get("quick_max_samples")
        if qmax is not None:
            want(qmax, int, where, "quick_max_samples")
        columns = want(g.get("columns", 0), int, where, "columns")
        rate = want(g.get("rate", False), bool, where, "rate")
        env_probability = want(g.get("env_probability", False), bool, where, "env_probability")
        black = g.get("expect_black", False)
        self._expect_black(black, where)
        grid = {"kind": "grid", "id": gid, "title": want(g.get("title", gid), str, where, "title"),
                "text": want(g.get("text", ""), str, where, "text"),
                "rate": rate, "env_probability": env_probability, "renders": []}
        names = set()
        for n, c in enumerate(self._grid_cells(g, where), 1):
            cw = f"{where}, cell {n}"
            check_keys(c, CELL_KEYS, cw)
            label = want(c.get("label", f"{n}"), str, cw, "label")
            cw = f"{where}, cell '{label}'"
            name = self._cell_name(c, label, names, cw)
            flags = merge_flags(base, parse_flags(c.get("args", ""), cw))
            csize = want_size(c["size"], cw) if "size" in c else size
            cqsize = want_size(c["quick_size"], cw, "quick_size") if "quick_size" in c else qsize
            cseed = want(c.get("seed", seed), int, cw, "seed")
            cqmax = c.get("quick_max_samples", qmax)
            if cqmax is not None and want(cqmax, int, cw, "quick_max_samples") < 1:
                raise InputError(f"{cw}: 'quick_max_samples' must be at least 1")
            r = self._render(cw, gid, name, label, c.get("scene", g.get("scene")), flags, csize, cqsize, cseed,
                             quick_max_samples=cqmax)
            r.rate = rate
            r.env_probability = env_probability
            if env_probability and get_flag(flags, "-e") is None:
                raise InputError(f"{cw}: 'env_probability' shows where the environment map is sampled: "
                                 f"the render needs -e")
            r.expect_black = self._expect_black(c.get("expect_black", black), cw)
            grid["renders"].append(r)
        sides = rate or env_probability
        grid["columns"] = columns if columns > 0 else min(len(grid["renders"]), 2 if sides else 4)
        return grid

    @staticmethod
    def _grid_cells(g, where):
        """A grid's cells: its 'cells', or one per value of its 'vary'."""
        if ("vary" in g) == ("cells" in g):
            raise InputError(f"{where}: give either 'vary' or 'cells'")
        if "cells" in g:
            cells = want(g["cells"], list, where, "cells")
            if not cells:
                raise InputError(f"{where}: 'cells' is empty")
            return cells
        v = g["vary"]
        check_keys(v, VARY_KEYS, f"{where}: vary")
        flag = want(v.get("flag"), str, f"{where}: vary", "flag")
        values = want(v.get("values"), list, f"{where}: vary", "values")
        if not values:
            raise InputError(f"{where}: vary has no values")
        cells = []
        for val in values:
            vals = [str(x) for x in val] if isinstance(val, list) else [str(val)]
            cells.append({"label": f"{flag} {' '.join(vals)}", "name": slug(flag + "_" + "_".join(vals)),
                          "args": shlex.join([flag] + vals)})
        return cells

    @staticmethod
    def _cell_name(c, label, names, where):
        """A cell's image file name, unique in its grid (default: the label
        without ".dae" and without parentheses)."""
        default = re.sub(r"\([^)]*\)|\.dae\b", "", label) if "name" not in c else c["name"]
        name = slug(want(default, str, where, "name"))
        base_name, k = name, 2
        while name in names:
            name, k = f"{base_name}_{k}", k + 1
        names.add(name)
        return name

    def _table_columns(self, t, vlabels, where):
        columns = want(t.get("columns", []), list, where, "columns")
        if not columns:
            raise InputError(f"{where}: no 'columns'")
        for n, c in enumerate(columns, 1):
            cw = f"{where}, column {n}"
            check_keys(c, COLUMN_KEYS, cw)
            if ("field" in c) == ("ratio" in c):
                raise InputError(f"{cw}: give either 'field' (with 'variant') or 'ratio'")
            if "field" in c:
                want(c["field"], str, cw, "field")
                if c.get("variant", vlabels[0]) not in vlabels:
                    raise InputError(f"{cw}: unknown variant '{c.get('variant')}' (variants: {', '.join(vlabels)})")
            else:
                r = c["ratio"]
                if not (isinstance(r, list) and len(r) == 3 and all(isinstance(x, str) for x in r)
                        and r[1] in vlabels and r[2] in vlabels):
                    raise InputError(f"{cw}: 'ratio' must be [field, variant, variant] with variants among "
                                     f"{', '.join(vlabels)}")
        return columns

    def _table(self, t, ids, where):
        tid = self._id(t, ids, where, "table")
        where = f"{self.display}: table '{tid}'"
        check_keys(t, TABLE_KEYS, where)
        base, size, qsize, seed = self._shared_fields(t, where)
        threads = t.get("threads")
        if threads is not None and (not isinstance(threads, int) or threads < 1):
            raise InputError(f"{where}: 'threads' must be a positive integer")
        exclusive = want(t.get("exclusive", False), bool, where, "exclusive")
        scenes = want(t.get("scenes", [t["scene"]] if "scene" in t else []), list, where, "scenes")
        if not scenes:
            raise InputError(f"{where}: no 'scenes'")
        variants = want(t.get("variants", [{"label": "render"}]), list, where, "variants")
        vlabels = []
        for n, v in enumerate(variants, 1):
            check_keys(v, VARIANT_KEYS, f"{where}, variant {n}")
            vlabels.append(want(v.get("label", f"variant {n}"), str, f"{where}, variant {n}", "label"))
        columns = self._table_columns(t, vlabels, where)
        table = {"kind": "table", "id": tid, "title": want(t.get("title", tid), str, where, "title"),
                 "text": want(t.get("text", ""), str, where, "text"), "columns": columns,
                 "variants": vlabels, "rows": []}
        for scene in scenes:
            want(scene, str, where, "scenes")
            row = {"scene": scene, "renders": {}}
            for v, vl in zip(variants, vlabels):
                vw = f"{where}, scene '{scene}', variant '{vl}'"
                flags = merge_flags(base, parse_flags(v.get("args", ""), vw))
                row["renders"][vl] = self._render(vw, tid, slug(f"{os.path.splitext(scene)[0]}_{vl}"),
                                                  f"{scene}, {vl}", scene, flags, size, qsize, seed,
                                                  threads=threads, exclusive=exclusive, image=False)
            table["rows"].append(row)
        return table
