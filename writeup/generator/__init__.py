"""The write-up figure generator (run as writeup/make_figures.py).

Modules, in the order a run uses them:
  base       repository root, the program name, InputError, path/time formatting
  flags      the pathtracer's flags: parsing a recipe's args, merging, the generated ones
  recipes    writeup/figures.toml: checked and expanded into renders (Recipes, Render)
  cache      cache keys, entries, the timing history, the private binary copy, pruning
  scheduler  jobs, their order and threads within -t, running and storing renders
  preview    --quick: a render's PFM shrunk into the figure's PNG, and whether it is one flat colour
  progress   progress lines and the ETA
  checks     TODO lines, the all-black check (max_radiance from --stats-json), a flat preview
  page_items a grid or a table in HTML and Markdown, a figure's manifest entry
  page       index.html, index.md and manifest.json
  cli        the command line and the run from recipes to page
"""
