#!/usr/bin/env python3
"""docs/paper/README.md from the paper sweeps' outputs: for every value the seed paper
states in its text (examples/paper/paper_values.csv, each with its quote),
fibrodem's mean and 95 % confidence interval over the tissue seeds
(sweep_stats.csv of the sweep that reproduces that panel) with the default
models and, for Figs. 4 and 6, with the colman variant brocklehurst2022_tissue
(OUT_DIR/brocklehurst2022_tissue/SWEEP), the difference and relative error of
each, and whether they agree: potentials within 3 mV, anything else within
20 %. Plots of each Fig. 4/6 sweep against the paper's stated points are drawn
by `fibrodem plot` (FIBRODEM_BIN, default build/fibrodem). Standard library only.

    scripts/paper_report.py [OUT_DIR] [DOCS_DIR] [--title-note TEXT]
                                               (default out/paper docs/paper)
"""
import csv
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PRESET = "brocklehurst2022_tissue"
# The sweeps run with the preset too (scripts/paper.sh): the EP figures.
PRESET_SWEEPS = ("fig4_fm_ratio", "fig4_D_f", "fig6_fm_ratio", "fig6_D_f")


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")


def grid_axes(rows):
    """The sweep's grid paths: the columns before seeds_completed."""
    columns = list(rows[0].keys())
    return columns[: columns.index("seeds_completed")]


def axis_rows(rows, axis):
    """The rows along `axis` (a grid path; else the first grid axis), the other
    grid axes at their first values."""
    axes = grid_axes(rows)
    x = axis if axis in axes else axes[0]
    first = {a: rows[0][a] for a in axes}
    return [r for r in rows if all(r[a] == first[a] for a in axes if a != x)]


def pick(rows, axis, at):
    """The grid point at `at` on `axis` (a grid path, or "fm_ratio": the tissue's
    measured F-M ratio, nearest, along the first grid axis), the other grid
    axes at their first values."""
    candidates = axis_rows(rows, axis)
    if axis in grid_axes(rows):
        matches = [r for r in candidates if abs(number(r[axis]) - at) <= 1e-9 * max(1.0, abs(at))]
        return matches[0] if matches else None
    return min(candidates, key=lambda r: abs(number(r[axis + "_mean"]) - at), default=None)


def fmt(v, digits=3):
    return "" if v != v else f"{v:.{digits}g}" if abs(v) < 1 else f"{v:.{digits + 1}g}"


def is_potential(metric):
    return metric.endswith("_mV")


def agrees(metric, mean, paper):
    if mean != mean:
        return False
    return abs(mean - paper) <= 3.0 if is_potential(metric) else abs(mean - paper) <= 0.2 * abs(paper)


def load_stats(out, sweep, cache):
    if sweep not in cache:
        path = os.path.join(out, sweep, "sweep_stats.csv")
        cache[sweep] = read_csv(path) if os.path.exists(path) else None
    return cache[sweep]


def cell(rows, v, metric):
    """(mean, low, high, nearest F-M) of the metric at the stated point, or None."""
    row = pick(rows, v["axis"], number(v["at"])) if rows else None
    if row is None:
        return None
    return (number(row[metric + "_mean"]), number(row[metric + "_ci95_low"]),
            number(row[metric + "_ci95_high"]), number(row.get("fm_ratio_mean")))


def comparison(result, metric, paper):
    """The table cells for one model: mean [CI], difference, relative error, agrees."""
    if result is None:
        return ["(not run)", "", "", ""]
    mean, low, high, _ = result
    diff = mean - paper
    rel = diff / abs(paper) if paper else float("nan")
    ok = agrees(metric, mean, paper)
    ci = f" [{fmt(low)}, {fmt(high)}]" if low == low and high == high else ""  # none from one seed
    return [fmt(mean) + ci, fmt(diff), f"{100 * rel:+.0f} %" if rel == rel else "",
            "yes" if ok else "**no**"]


def plot_sweep(sweep, values, default_rows, preset_rows, out, docs, fibrodem):
    """One PNG per sweep: each metric the paper states on it against the sweep's
    axis, default and preset (mean, 95 % CI) with the paper's stated points."""
    metrics = []
    for v in values:
        if v["metric"] not in metrics:
            metrics.append(v["metric"])
    axis = values[0]["axis"]
    panels = []
    for metric in metrics:
        series = []
        for label, rows in (("fibrodem default", default_rows), (f"fibrodem {PRESET}", preset_rows)):
            if not rows:
                continue
            line = axis_rows(rows, axis)
            x_key = axis if axis in grid_axes(rows) else axis + "_mean"
            series.append({"label": label,
                           "x": [number(r[x_key]) for r in line],
                           "y": [number(r[metric + "_mean"]) for r in line],
                           "y_low": [number(r[metric + "_ci95_low"]) for r in line],
                           "y_high": [number(r[metric + "_ci95_high"]) for r in line]})
        stated = [v for v in values if v["metric"] == metric]
        # The paper's points as markers alone: a null between two points breaks the line.
        xs, ys = [], []
        for v in stated:
            xs += [number(v["at"]), None]
            ys += [number(v["paper"]), None]
        series.append({"label": "paper (stated in the text)", "x": xs[:-1], "y": ys[:-1]})
        for s in series:
            for key in ("x", "y", "y_low", "y_high"):
                if key in s:
                    s[key] = [None if (x is None or x != x) else x for x in s[key]]
        panels.append({"title": metric, "x_label": axis, "y_label": metric, "series": series})
    spec = {"title": f"{sweep}: fibrodem (default, {PRESET}) against the paper's stated values",
            "columns": 2, "width_px": 1200, "height_px": 420 * ((len(panels) + 1) // 2), "panels": panels}
    spec_file = os.path.join(out, f"{sweep}_vs_paper.json")
    with open(spec_file, "w") as f:
        json.dump(spec, f)
    png = os.path.join(docs, f"{sweep}_vs_paper.png")
    result = subprocess.run([fibrodem, "plot", spec_file, "--out", png], capture_output=True, text=True)
    if result.returncode != 0:
        print(f"{png}: not drawn: {result.stderr.strip()}", file=sys.stderr)
        return None
    return os.path.basename(png)


def main():
    args = [a for a in sys.argv[1:]]
    note = ""
    if "--title-note" in args:
        i = args.index("--title-note")
        note = args[i + 1]
        del args[i:i + 2]
    out = args[0] if len(args) > 0 else os.path.join(ROOT, "out", "paper")
    docs = args[1] if len(args) > 1 else os.path.join(ROOT, "docs", "paper")
    fibrodem = os.environ.get("FIBRODEM_BIN", os.path.join(ROOT, "build", "fibrodem"))
    os.makedirs(docs, exist_ok=True)
    values = read_csv(os.path.join(ROOT, "examples", "paper", "paper_values.csv"))
    default_stats, preset_stats = {}, {}
    lines = ["# The seed paper's numbers, reproduced", "",
             "Generated by `scripts/paper.sh` (the sweeps of `examples/paper/`, then "
             "`scripts/paper_report.py`). Every value the paper (Brocklehurst, Zhang & Ye 2022, section 3) "
             "states in its text, beside fibrodem's mean and 95 % confidence interval over 5 random tissues "
             "(seeds) at the same point (`solver.method` auto), with the default models and, for the "
             f"electrophysiology of Figs. 4 and 6, with the myocyte variant `colman` `{PRESET}` (a "
             "stretch-activated current active at rest, its one conductance calibrated to the paper's "
             "myocyte RMP of -65.2 mV at F-M 0.11, D_f 0.3 nS, in-series: that value is a fit, every other "
             "one a prediction; see the notes below). Agreement: potentials within 3 mV, anything else "
             "within 20 %. Where the paper's axis is the F-M ratio of an interstitial tissue, the grid "
             "point whose measured F-M ratio is nearest is used." + (" " + note if note else ""), ""]
    # (the counts of agreeing values go here, at index 4, once known)
    counts = {"default": [0, 0], "preset": [0, 0]}
    figure = None
    by_sweep = {}
    for v in values:
        sweep = v["sweep"]
        by_sweep.setdefault(sweep, []).append(v)
        if v["figure"][0] != figure:
            figure = v["figure"][0]
            lines += ["", f"## Figure {figure}", ""]
            lines += ["| panel | at | metric | paper | default mean [95 % CI] | default - paper | rel. | agrees "
                      f"| {PRESET} mean [95 % CI] | {PRESET} - paper | rel. | agrees |",
                      "|---|---|---|---:|---:|---:|---:|---|---:|---:|---:|---|"]
        paper = number(v["paper"])
        metric = v["metric"]
        d = cell(load_stats(out, sweep, default_stats), v, metric)
        p = cell(load_stats(os.path.join(out, PRESET), sweep, preset_stats), v, metric) \
            if sweep in PRESET_SWEEPS else None
        at = f'{v["axis"]} = {v["at"]}'
        if v["axis"] == "fm_ratio":
            near = [fmt(r[3]) for r in (d, p) if r is not None]
            if near:
                at += f' (nearest: {" / ".join(near)})'
        for key, r in (("default", d), ("preset", p)):
            if r is not None:
                counts[key][1] += 1
                counts[key][0] += agrees(metric, r[0], paper)
        preset_cells = comparison(p, metric, paper) if sweep in PRESET_SWEEPS else ["(mechanics: not run)", "", "", ""]
        lines.append("| " + " | ".join([v["figure"], at, metric, fmt(paper)] + comparison(d, metric, paper) +
                                       preset_cells) + " |")
    # The plots: each sweep's sweep.png, and for Figs. 4/6 the sweep against the paper.
    lines += ["", "## Plots", ""]
    for sweep in default_stats:
        png = os.path.join(out, sweep, "sweep.png")
        drawn = None
        if sweep in PRESET_SWEEPS and (default_stats.get(sweep) or preset_stats.get(sweep)):
            drawn = plot_sweep(sweep, by_sweep[sweep], default_stats.get(sweep), preset_stats.get(sweep),
                               out, docs, fibrodem)
        if drawn or os.path.exists(png):
            lines += [f"### {sweep}", ""]
        if drawn:
            lines += [f"Against the paper's stated values (default and {PRESET}, bars the 95 % CI):", "",
                      f"![{sweep} against the paper]({drawn})", ""]
        if os.path.exists(png):
            shutil.copyfile(png, os.path.join(docs, sweep + ".png"))
            lines += ["Every metric of the default sweep:", "", f"![{sweep}]({sweep}.png)", ""]
    summary = (f"**Default: {counts['default'][0]} of {counts['default'][1]} stated values agree. "
               f"`{PRESET}` (Figs. 4 and 6): {counts['preset'][0]} of {counts['preset'][1]} agree "
               "(one of them, the myocyte RMP at F-M 0.11, is its calibration).**")
    lines.insert(4, summary)
    lines.insert(5, "")
    notes = os.path.join(ROOT, "examples", "paper", "NOTES.md")
    if os.path.exists(notes):
        with open(notes) as f:
            lines += ["", f.read()]
    with open(os.path.join(docs, "README.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"{os.path.join(docs, 'README.md')}: default {counts['default'][0]} of {counts['default'][1]} "
          f"stated values agree; {PRESET} {counts['preset'][0]} of {counts['preset'][1]}")


if __name__ == "__main__":
    main()
