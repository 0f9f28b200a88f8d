"""The page's items: a grid of figures and a table of numbers, each written
into the HTML and the Markdown page at once, and each figure's entry of the
manifest."""

import html
import shlex

from .base import display_path
from .checks import problem_html, problem_md, render_problems
from .flags import FILE_FLAGS, recipe_args


def fmt_value(field, v):
    if v is None:
        return "–"
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return html.escape(str(v))
    if isinstance(v, int):
        return f"{v:,}"
    if field.endswith("_seconds"):
        return f"{v:.3f}" if v < 10 else f"{v:.1f}"
    if abs(v) >= 100:
        return f"{v:,.0f}"
    if abs(v) >= 10:
        return f"{v:.1f}"
    return f"{v:.2f}" if abs(v) >= 0.1 else f"{v:.4f}"


def shown_command(r, binary):
    """The command shown under a figure: the render's, with the figure's own output
    names (a render several figures share ran once under neutral names)."""
    j = r.job
    argv = list(j.meta["argv"]) if j.meta else [display_path(binary)] + recipe_args(r) + [display_path(r.scene)]
    out = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "-f":
            out += ["-f", f"{r.name}.png"]
            i += 2
        elif a == "--stats-json":
            out += ["--stats-json", f"{r.name}.json"]
            i += 2
        elif a in FILE_FLAGS and i + 1 < len(argv):
            out += [a, display_path(argv[i + 1])]  # -e and -c files relative to the repository, like the scene
            i += 2
        elif a == "--env-probability":
            out += ["--env-probability", f"{r.name}_env_probability.png"]
            i += 2
        else:
            out.append(a)
            i += 1
    return shlex.join(out)


def figure_info(r, img_dir_rel, binary):
    """A figure as the manifest lists it."""
    j = r.job
    base = f"{img_dir_rel}/{r.grid}/{r.name}"
    return {"grid": r.grid, "name": r.name, "label": r.label, "status": j.status,
            "command": shown_command(r, binary), "error": j.error,
            "image": f"{base}.png" if j.status != "failed" else None,
            "rate_image": f"{base}_rate.png" if j.status != "failed" and r.rate else None,
            "env_probability_image": (f"{base}_env_probability.png" if j.status != "failed" and r.env_probability
                                      else None),
            "side_images": ([(f"{base}{suffix}.png", caption) for _, suffix, caption in r.side_images()]
                            if j.status != "failed" else []),
            "render_seconds": j.stats.get("render_seconds") if j.stats else None,
            "wall_seconds": j.meta.get("wall_seconds") if j.meta else None,
            "threads": j.meta.get("threads") if j.meta else None,
            "cached": j.status == "cached",
            "expect_black": r.expect_black,
            "max_radiance": j.checks.get("max_radiance") if j.checks and j.status != "failed" else None,
            "flags": [{"kind": k, "text": t} for k, t in render_problems(r)]}


# ---------------------------------------------------------------------------
# Grids

def grid_figure_html(f, problems):
    """A figure's <figure> opening and image (the caption follows); the images
    shown beside the render (its sampling rate, where the map is sampled) side
    by side with it."""
    label = html.escape(f["label"])
    if f["status"] == "failed":
        return (f"<figure class=\"failed\" data-status=\"failed\"><div class=\"placeholder\">render failed:<br>"
                f"{html.escape(f['error'])}</div>\n")
    img = f"<a href=\"{f['image']}\"><img src=\"{f['image']}\" alt=\"{label}\"></a>"
    sides = f["side_images"]
    if sides:
        img = (f"<div class=\"pair\" style=\"--n: {1 + len(sides)}\">{img}"
               + "".join(f"<a href=\"{src}\"><img src=\"{src}\" alt=\"{label}: {html.escape(caption)}\"></a>"
                         for src, caption in sides)
               + "<span>render</span>" + "".join(f"<span>{html.escape(caption)}</span>" for _, caption in sides)
               + "</div>")
    if not problems:
        return f"<figure data-status=\"ok\">{img}\n"
    kinds = " ".join(dict.fromkeys(k for k, _ in problems))
    return (f"<figure class=\"flagged\" data-status=\"ok\" data-flagged=\"{kinds}\">"
            f"<div class=\"warning\"><b>⚠ Check this figure:</b><ul>"
            + "".join(f"<li>{problem_html(k, t)}</li>" for k, t in problems)
            + f"</ul></div>{img}\n")


def grid_figure_md(f, problems, timing):
    """A figure's Markdown table cell."""
    if f["status"] == "failed":
        return f"**{f['label']}**<br>FAILED: {f['error']}<br>`{f['command']}`"
    imgs_md = f"![{f['label']}]({f['image']})"
    for src, caption in f["side_images"]:
        imgs_md += f" ![{f['label']}: {caption}]({src})"
    warn_md = ("**⚠ Check this figure:** " + "; ".join(problem_md(k, t) for k, t in problems) + "<br>"
               if problems else "")
    return f"{warn_md}{imgs_md}<br>**{f['label']}** ({timing})<br>`{f['command']}`"


def figure_timing(f):
    if f["status"] == "failed":
        return "failed"
    rs = f["render_seconds"]
    return (f"{fmt_value('render_seconds', rs)} s, {f['threads']} thread{'s' if f['threads'] != 1 else ''}"
            if rs is not None else "")


def page_grid(grid, h, md, figures, img_rel, binary):
    cols = grid["columns"]
    h.append(f"<div class=\"grid\" style=\"--cols: {cols}\">\n")
    cells_md = []
    for r in grid["renders"]:
        f = figure_info(r, img_rel, binary)
        f["rate"] = grid["rate"]
        f["env_probability"] = grid["env_probability"]
        figures.append(f)
        problems = render_problems(r) if f["status"] != "failed" else []
        timing = figure_timing(f)
        h.append(grid_figure_html(f, problems))
        cells_md.append(grid_figure_md(f, problems, timing))
        h.append(f"<figcaption><span class=\"label\">{html.escape(f['label'])}</span> "
                 f"<span class=\"time\">{html.escape(timing)}</span>"
                 f"<code>{html.escape(f['command'])}</code></figcaption></figure>\n")
    h.append("</div>\n")
    for i in range(0, len(cells_md), cols):
        row = cells_md[i:i + cols]
        if i == 0:
            md.append("|" + " |" * cols + "\n|" + "---|" * cols + "\n")
        md.append("| " + " | ".join(row + [""] * (cols - len(row))) + " |\n")
    md.append("\n")


# ---------------------------------------------------------------------------
# Tables

def ratio_cell(field, ra, rb):
    if "failed" in (ra.status, rb.status):
        return ("failed", False)
    va, vb = ra.stats.get(field), rb.stats.get(field)
    if isinstance(va, (int, float)) and isinstance(vb, (int, float)) and vb > 0:
        x = va / vb
        return (f"{x:,.0f}×" if x >= 100 else f"{x:.1f}×", True)
    return ("–", False)


def table_cells(table):
    """Rows of (text, numeric) for a table."""
    rows = []
    for row in table["rows"]:
        cells = [(row["scene"], False)]
        for c in table["columns"]:
            if "field" in c:
                r = row["renders"][c.get("variant", table["variants"][0])]
                if r.job.status == "failed":
                    cells.append(("failed", False))
                    continue
                v = r.job.stats.get(c["field"]) if r.job.stats else None
                cells.append((fmt_value(c["field"], v), v is not None))
            else:
                field, a, b = c["ratio"]
                cells.append(ratio_cell(field, row["renders"][a].job, row["renders"][b].job))
        rows.append(cells)
    return rows


def table_flagged(table):
    """Rows of yes/no for a table's cells: whether a render the cell reads is flagged."""
    out = []
    for row in table["rows"]:
        cells = [False]
        for c in table["columns"]:
            names = [c.get("variant", table["variants"][0])] if "field" in c else c["ratio"][1:]
            cells.append(any(render_problems(row["renders"][v]) for v in names))
        out.append(cells)
    return out


def table_conditions(table):
    """How a table's renders ran, from the renders themselves: size, threads, alone or not."""
    rs = [r for row in table["rows"] for r in row["renders"].values() if r.job.status != "failed"]
    if not rs:
        return ""
    sizes = sorted({r.size for r in rs})
    threads = sorted({r.job.meta["threads"] for r in rs if r.job.meta and r.job.meta.get("threads")})
    text = "Rendered at " + ", ".join(f"{w} × {h}" for w, h in sizes)
    if threads:
        n = f"{threads[0]}" if len(threads) == 1 else f"{threads[0]} to {threads[-1]}"
        text += f", on {n} thread{'s' if threads[-1] != 1 else ''} each"
    if all(r.exclusive for r in rs):
        text += ", each render alone (no other render of the generator running beside it)."
    else:
        text += (", beside other renders of the generator"
                 + (" (--quick does not run timing renders alone)" if any(r.quick_exclusive for r in rs) else "")
                 + ": the times are rougher.")
    return text


def table_grid(table, h, md, tables):
    """The table itself, in HTML and Markdown, and its manifest entry."""
    heads = ["scene"] + [c["title"] for c in table["columns"]]
    rows = table_cells(table)
    marks = table_flagged(table)
    tables.append({"id": table["id"], "title": table["title"], "columns": heads,
                   "rows": [[t for t, _ in row] for row in rows],
                   "numeric": [[n for _, n in row] for row in rows]})
    h.append(f"<table class=\"stats\" id=\"table-{table['id']}\">\n<tr>"
             + "".join(f"<th>{html.escape(x)}</th>" for x in heads) + "</tr>\n")
    for row, flags in zip(rows, marks):
        h.append("<tr>" + "".join(
            f"<td class=\"{'num' if n else ('failed' if t == 'failed' else '')}{' flagged' if x else ''}\">"
            f"{html.escape(t)}</td>"
            for (t, n), x in zip(row, flags)) + "</tr>\n")
    h.append("</table>\n")
    md.append("| " + " | ".join(heads) + " |\n|---|" + "---:|" * (len(heads) - 1) + "\n")
    for row, flags in zip(rows, marks):
        md.append("| " + " | ".join(t + (" ⚠" if x else "") for (t, _), x in zip(row, flags)) + " |\n")
    md.append("\n")


def page_table(table, h, md, tables, binary):
    table_grid(table, h, md, tables)
    cmds = []
    errors = []
    checks = []
    for row in table["rows"]:
        for r in row["renders"].values():
            cmds.append(shown_command(r, binary))
            if r.job.status == "failed":
                errors.append(f"{row['scene']}, {r.label}: {r.job.error}")
            problems = render_problems(r)
            if problems:
                checks.append((r, problems))
    conditions = table_conditions(table)
    if conditions:
        h.append(f"<p class=\"meta\">{html.escape(conditions)}</p>\n")
        md.append(f"{conditions}\n\n")
    for e in errors:
        h.append(f"<p class=\"errors\">render failed: {html.escape(e)}</p>\n")
        md.append(f"- render failed: {e}\n")
    for r, problems in checks:
        h.append(f"<p class=\"warning\" data-flagged=\"{' '.join(dict.fromkeys(k for k, _ in problems))}\">"
                 f"<b>⚠ Check</b> {html.escape(r.label)}: "
                 + "; ".join(problem_html(k, t) for k, t in problems) + "</p>\n")
        md.append(f"- ⚠ Check {r.label}: " + "; ".join(problem_md(k, t) for k, t in problems) + "\n")
    if errors or checks:
        md.append("\n")
    h.append(f"<details><summary>The {len(cmds)} commands</summary><pre>"
             + html.escape("\n".join(cmds)) + "</pre></details>\n")
    md.append("<details><summary>The commands</summary>\n\n```\n" + "\n".join(cmds) + "\n```\n\n</details>\n\n")
