"""The page: OUT/index.html, the same in Markdown (OUT/index.md), and
OUT/manifest.json (the run's summary, every figure and every table)."""

import html
import json
import os
import re

from .base import fmt_duration, write_atomically
from .checks import problem_html, problem_md, render_problems
from .page_items import fmt_value, page_grid, page_table

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; color: #222; background: #f6f6f4;
       max-width: 1240px; margin: 0 auto; padding: 12px 24px 48px; line-height: 1.45; }
h1 { font-size: 1.7em; margin-bottom: 0.2em; }
h2 { margin-top: 2em; border-bottom: 2px solid #ccc; padding-bottom: 4px; }
h3 { margin: 1.6em 0 0.3em; }
p.meta { color: #555; font-size: 0.92em; margin-top: 0; }
.banner { background: #fff3c4; border: 1px solid #e0c060; padding: 8px 12px; border-radius: 6px; }
.errors { background: #fde8e8; border: 1px solid #d08080; padding: 8px 12px; border-radius: 6px; }
nav ul { columns: 2; font-size: 0.95em; }
.grid { display: grid; grid-template-columns: repeat(var(--cols), minmax(0, 1fr)); gap: 14px; }
figure { margin: 0; background: #fff; border: 1px solid #ddd; border-radius: 6px; padding: 8px; }
figure img { max-width: 100%; height: auto; display: block; margin: 0 auto; background: #000; }
.quick figure img { width: 100%; max-width: 320px; image-rendering: pixelated; }
.pair { display: grid; grid-template-columns: repeat(var(--n, 2), 1fr); gap: 4px; align-items: start; }
.pair span { font-size: 0.8em; color: #666; text-align: center; }
figcaption { margin-top: 6px; font-size: 0.9em; }
figcaption .label { font-weight: 600; }
figcaption .time { color: #666; float: right; }
figcaption code, pre { display: block; font-size: 11px; white-space: pre-wrap; word-break: break-all;
                      background: #f1f1ef; padding: 4px 6px; margin-top: 4px; border-radius: 3px; }
figure.failed { border-color: #d08080; }
.warnings, .warning { background: #fff0d0; border: 1px solid #d09030; padding: 8px 12px; border-radius: 6px;
                      color: #6a3d00; }
.warning { padding: 4px 8px; margin-bottom: 6px; font-size: 0.85em; }
.warning ul, .warnings ul { margin: 2px 0; padding-left: 1.2em; }
.warning code, .warnings code { word-break: break-all; }
figure.flagged { border: 2px solid #d09030; }
table.stats td.flagged { background: #fff0d0; }
.placeholder { aspect-ratio: 4 / 3; background: #fbe3e3; color: #900; display: flex; align-items: center;
               justify-content: center; text-align: center; padding: 8px; font-size: 0.9em; }
table.stats { border-collapse: collapse; background: #fff; font-size: 0.9em; margin: 8px 0; }
table.stats th, table.stats td { border: 1px solid #ccc; padding: 4px 8px; }
table.stats th { background: #eee; }
table.stats td.num { text-align: right; font-variant-numeric: tabular-nums; }
table.stats td.failed { color: #a00; }
details { margin: 6px 0; font-size: 0.9em; }
"""

FLAGGED_INTRO = ("These renders ran to the end, but the renderer printed a TODO line (a function it has not "
                 "written yet) or wrote an all-black image, so the figure is likely not what the write-up "
                 "should show.")


def job_times(jobs):
    """Sum of wall time x threads, and of CPU time (None if a render lacks it), over successful jobs."""
    wt, cpu = 0.0, 0.0
    for j in jobs:
        if j.meta and j.status != "failed":
            wt += j.meta["wall_seconds"] * j.meta.get("threads", 1)
            c = j.meta.get("cpu_seconds")
            cpu = None if cpu is None or c is None else cpu + c
    return wt, cpu


def time_text(summary):
    cpu = summary["cpu_seconds"]
    text = (f"All renders together took {fmt_duration(summary['wall_thread_seconds'])} of wall time × threads")
    if cpu is not None:
        text += (f" and {fmt_duration(cpu)} of CPU time: from scratch, on {summary['thread_budget']} otherwise idle "
                 f"core(s), the page would take about {fmt_duration(summary['idle_estimate_seconds'])}")
    return text + "."


def inline_md(text):
    """The recipes' text: `code` spans, paragraphs split at blank lines."""
    parts = re.split(r"`([^`]*)`", " ".join(text.split()))
    return "".join(f"<code class=\"inline\">{html.escape(p)}</code>" if i % 2 else html.escape(p)
                   for i, p in enumerate(parts))


def item_renders(item):
    """A grid's or a table's renders, in page order."""
    if item["kind"] == "grid":
        return item["renders"]
    return [r for row in item["rows"] for r in row["renders"].values()]


class Page:
    """The HTML (h) and Markdown (md) page, written side by side, and the
    manifest's figures and tables."""

    def __init__(self, recipes, jobs, summary, binary, img_rel="img"):
        self.recipes = recipes
        self.jobs = jobs
        self.summary = summary
        self.binary = binary   # the binary as given, for the commands of renders that never ran
        self.img_rel = img_rel
        self.h = []
        self.md = []
        self.figures = []
        self.tables = []

    def build(self):
        self.head()
        self.failed_list()
        self.flagged_list()
        self.nav()
        for sec in self.recipes.sections:
            self.section(sec)
        self.times()
        return self

    def write(self, out_dir):
        write_atomically(os.path.join(out_dir, "index.html"), "".join(self.h))
        write_atomically(os.path.join(out_dir, "index.md"), "".join(self.md))
        manifest = {"summary": self.summary, "figures": self.figures, "tables": self.tables}
        write_atomically(os.path.join(out_dir, "manifest.json"), json.dumps(manifest, indent=1) + "\n")

    def head(self):
        recipes, summary, h, md = self.recipes, self.summary, self.h, self.md
        title = recipes.title + (" (quick check)" if recipes.quick else "")
        h.append(f"<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                 f"<title>{html.escape(title)}</title>\n<style>{CSS}</style>\n</head>\n"
                 f"<body class=\"{'quick' if recipes.quick else 'full'}\">\n<h1>{html.escape(title)}</h1>\n")
        run_text = (f"Rendered with `{summary['binary']}` (sha256 {summary['binary_sha256'][:12]}) from "
                    f"`{summary['recipes']}`, {summary['date']}: {summary['renders']} figures, "
                    f"{summary['distinct_renders']} distinct renders, {summary['rendered']} of them rendered by "
                    f"this run in {fmt_duration(summary['wall_seconds'])} with {summary['thread_budget']} "
                    f"thread(s), {summary['cached']} from the cache, {summary['failed']} failed, "
                    f"{summary['flagged']} figure(s) flagged for checking. "
                    + time_text(summary))
        h.append(f"<p class=\"meta\">{inline_md(run_text)}</p>\n")
        md.append(f"# {title}\n\n{run_text}\n\n")
        if recipes.quick:
            q = (f"Quick check (--quick): every image shows its figure's whole view, rendered at the figure's "
                 f"size with at most {recipes.quick_max_samples} camera ray(s) per pixel (unless its recipe says "
                 f"otherwise) and {recipes.quick_max_light_samples} light samples, and shrunk to at most "
                 f"{recipes.quick_size[0]}×{recipes.quick_size[1]} (the BVH's boxes are shown at full size); the "
                 f"tables' renders are the centre of the view at that size. The numbers and images are not the "
                 f"write-up's.")
            h.append(f"<p class=\"banner\">{html.escape(q)}</p>\n")
            md.append(f"> {q}\n\n")

    def failed_list(self):
        failed = [j for j in self.jobs if j.status == "failed"]
        if not failed:
            return
        self.h.append("<div class=\"errors\"><b>Failed renders</b><ul>\n")
        self.md.append("**Failed renders:**\n\n")
        for j in failed:
            names = ", ".join(f"{r.grid}/{r.name}" for r in j.renders)
            self.h.append(f"<li><a href=\"#{html.escape(j.renders[0].grid)}\">{html.escape(names)}</a>: "
                          f"{html.escape(j.error)}</li>\n")
            self.md.append(f"- {names}: {j.error}\n")
        self.h.append("</ul></div>\n")
        self.md.append("\n")

    def flagged_list(self):
        flagged = [(r, render_problems(r)) for r in self.recipes.renders]
        flagged = [(r, p) for r, p in flagged if p]
        if not flagged:
            return
        self.h.append(f"<div class=\"warnings\" id=\"flagged\"><b>Figures to check ({len(flagged)})</b>: "
                      f"{html.escape(FLAGGED_INTRO)}<ul>\n")
        self.md.append(f"**Figures to check ({len(flagged)}):** {FLAGGED_INTRO}\n\n")
        for r, problems in flagged:
            name = f"{r.grid}/{r.name}"
            self.h.append(f"<li><a href=\"#{html.escape(r.grid)}\">{html.escape(name)}</a>: "
                          + "; ".join(problem_html(k, t) for k, t in problems) + "</li>\n")
            self.md.append(f"- ⚠ {name}: " + "; ".join(problem_md(k, t) for k, t in problems) + "\n")
        self.h.append("</ul></div>\n")
        self.md.append("\n")

    def nav(self):
        self.h.append("<nav><ul>\n")
        for sec in self.recipes.sections:
            self.h.append(f"<li><a href=\"#{sec['id']}\">{html.escape(sec['title'])}</a></li>\n")
        self.h.append("<li><a href=\"#renders\">All renders and their times</a></li>\n</ul></nav>\n")

    def section(self, sec):
        h, md = self.h, self.md
        h.append(f"<section id=\"{sec['id']}\">\n<h2>{html.escape(sec['title'])}</h2>\n")
        md.append(f"## {sec['title']}\n\n")
        if sec["text"]:
            h.append(f"<p>{inline_md(sec['text'])}</p>\n")
            md.append(f"{' '.join(sec['text'].split())}\n\n")
        for item in sec["items"]:
            h.append(f"<h3 id=\"{item['id']}\">{html.escape(item['title'])}</h3>\n")
            md.append(f"### {item['title']}\n\n")
            if item["text"]:
                h.append(f"<p>{inline_md(item['text'])}</p>\n")
                md.append(f"{' '.join(item['text'].split())}\n\n")
            if item["kind"] == "grid":
                page_grid(item, h, md, self.figures, self.img_rel, self.binary)
            else:
                page_table(item, h, md, self.tables, self.binary)
        h.append("</section>\n")

    def times(self):
        self.h.append("<section id=\"renders\">\n<h2>All renders and their times</h2>\n")
        self.md.append("## All renders and their times\n\n")
        self.h.append(f"<p>{inline_md(time_text(self.summary))}</p>\n")
        self.md.append(f"{time_text(self.summary)}\n\n")
        self.set_times()
        self.render_times()
        self.h.append("</table>\n</section>\n</body>\n</html>\n")
        self.md.append("\n")

    def set_times(self):
        """Time by figure set (each distinct render counted once, where it first appears)."""
        h, md = self.h, self.md
        h.append("<table class=\"stats\" id=\"set-times\">\n<tr><th>figure set</th><th>renders</th>"
                 "<th>wall × threads</th><th>CPU</th></tr>\n")
        md.append("| figure set | renders | wall × threads | CPU |\n|---|---:|---:|---:|\n")
        seen = set()
        for sec in self.recipes.sections:
            for item in sec["items"]:
                rs = item_renders(item)
                mine = []
                for r in rs:
                    if r.job.key not in seen:
                        seen.add(r.job.key)
                        mine.append(r.job)
                wt, cpu = job_times(mine)
                cpu_text = fmt_duration(cpu) if cpu is not None else '–'
                h.append(f"<tr><td><a href=\"#{item['id']}\">{html.escape(item['title'])}</a></td>"
                         f"<td class=\"num\">{len(rs)}</td><td class=\"num\">{fmt_duration(wt)}</td>"
                         f"<td class=\"num\">{cpu_text}</td></tr>\n")
                md.append(f"| {item['title']} | {len(rs)} | {fmt_duration(wt)} | {cpu_text} |\n")
        cpu = self.summary["cpu_seconds"]
        cpu_text = fmt_duration(cpu) if cpu is not None else '–'
        total_wt = fmt_duration(self.summary['wall_thread_seconds'])
        n = len(self.recipes.renders)
        h.append(f"<tr><th>total</th><th class=\"num\">{n}</th>"
                 f"<th class=\"num\">{total_wt}</th>"
                 f"<th class=\"num\">{cpu_text}</th></tr>\n</table>\n")
        md.append(f"| **total** | {n} | {total_wt} | {cpu_text} |\n\n")

    def render_times(self):
        h, md = self.h, self.md
        h.append("<p>Per render: <i>render</i> is the renderer's own render time (without loading the scene and "
                 "building the BVH); <i>wall</i> the whole process and <i>CPU</i> its user + system time, as "
                 "measured by the generator when it ran; cached renders show the times of the run that made "
                 "them. Status <i>check</i>: the render is flagged (see the list at the head of the page).</p>\n")
        h.append("<table class=\"stats\" id=\"render-times\">\n<tr><th>figure</th><th>status</th>"
                 "<th>render s</th><th>wall s</th><th>CPU s</th><th>threads</th><th>rendered</th></tr>\n")
        md.append("| figure | status | render s | wall s | CPU s | threads | rendered |\n"
                  "|---|---|---:|---:|---:|---:|---|\n")
        for r in self.recipes.renders:
            j = r.job
            rs = j.stats.get("render_seconds") if j.stats else None
            ws = j.meta.get("wall_seconds") if j.meta else None
            cs = j.meta.get("cpu_seconds") if j.meta else None
            th = j.meta.get("threads") if j.meta else None
            when = "failed" if j.status == "failed" else ("cached" if j.status == "cached" else "this run")
            ok = "failed" if j.status == "failed" else ("check" if render_problems(r) else "ok")
            h.append(f"<tr><td><a href=\"#{r.grid}\">{html.escape(r.grid + '/' + r.name)}</a></td>"
                     f"<td class=\"{'failed' if ok == 'failed' else ('flagged' if ok == 'check' else '')}\">{ok}</td>"
                     f"<td class=\"num\">{fmt_value('render_seconds', rs)}</td>"
                     f"<td class=\"num\">{fmt_value('wall_seconds', ws)}</td>"
                     f"<td class=\"num\">{fmt_value('cpu_seconds', cs)}</td>"
                     f"<td class=\"num\">{th if th is not None else '–'}</td><td>{when}</td></tr>\n")
            md.append(f"| {r.grid}/{r.name} | {ok} | {fmt_value('render_seconds', rs)} | "
                      f"{fmt_value('wall_seconds', ws)} | {fmt_value('cpu_seconds', cs)} | "
                      f"{th if th is not None else '–'} | {when} |\n")


def write_page(out_dir, recipes, jobs, summary, binary, img_rel="img"):
    Page(recipes, jobs, summary, binary, img_rel).build().write(out_dir)
