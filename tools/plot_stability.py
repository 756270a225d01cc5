#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Draws the stability heat maps of `softbench stability` from its stability.json with matplotlib.

Usage: plot_stability.py stability.json [--out DIR]

Writes into DIR (default: the folder of stability.json), atomically (temporary + rename), one
stability_<model>.png per model: the model's stiffness axis (Young's modulus, or its own
unitless stiffness) across, the time step down, each cell coloured by the outcome of its run
(stable, unstable with NaN, unstable by the speed or displacement limit, timed out, or not run
because a larger time step was already stable). Prints the path of every file written, one per
line (softbench reads them).
"""

import os
import sys
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_common import plt, read_input, safe_name, save  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402


# (code, label, colour, text in the cell)
OUTCOMES = [
    ("stable", "stable", "#2ca02c", "S"),
    ("assumed", "not run: a larger dt was stable", "#b7e4b0", ""),
    ("unstable_nan", "unstable: NaN/Inf", "#7f0000", "NaN"),
    ("unstable", "unstable: speed/displacement limit", "#d62728", "X"),
    ("timed_out", "timed out (wall-clock budget)", "#9e9e9e", "T"),
    ("not_run", "not run", "#ffffff", ""),
]
CODES = {code: index for index, (code, _, _, _) in enumerate(OUTCOMES)}


def dt_label(dt):
    inverse = 1.0 / dt
    if abs(inverse - round(inverse)) < 1e-6 * inverse:
        return "1/%d" % round(inverse)
    return "%g" % dt


def cell_code(cell, row):
    status = cell["status"]
    if status == "stable":
        return "stable"
    if status == "unstable":
        return "unstable_nan" if cell["verdict"]["nan"] else "unstable"
    if status == "timed_out":
        return "timed_out"
    stable_dt = row.get("max_stable_dt")
    if stable_dt is not None and cell["dt"] < stable_dt:
        return "assumed"
    return "not_run"


def plot_model(model, time_steps, out):
    axis = model["axis"]
    values = [row["value"] for row in model["map"]]
    if not values:
        return
    grid = [[CODES["not_run"]] * len(values) for _ in time_steps]
    texts = [[""] * len(values) for _ in time_steps]
    for column, row in enumerate(model["map"]):
        for cell in row["cells"]:
            line = time_steps.index(cell["dt"]) if cell["dt"] in time_steps else None
            if line is None:
                continue
            code = cell_code(cell, row)
            grid[line][column] = CODES[code]
            texts[line][column] = OUTCOMES[CODES[code]][3]
            if code == "stable" and cell["verdict"]["max_inverted_tets"] > 0:
                texts[line][column] += "\n%d inv." % cell["verdict"]["max_inverted_tets"]
    figure, axes = plt.subplots(figsize=(max(6.0, 1.1 * len(values) + 3.5),
                                         max(4.0, 0.45 * len(time_steps) + 2.0)))
    colours = ListedColormap([outcome[2] for outcome in OUTCOMES])
    axes.imshow(grid, cmap=colours, vmin=-0.5, vmax=len(OUTCOMES) - 0.5, aspect="auto")
    for line in range(len(time_steps)):
        for column in range(len(values)):
            if texts[line][column]:
                axes.text(column, line, texts[line][column], ha="center", va="center",
                          fontsize=8, color="white" if grid[line][column] in
                          (CODES["unstable_nan"], CODES["unstable"], CODES["stable"]) else "black")
    axes.set_xticks(range(len(values)))
    unit = (" (" + axis["unit"] + ")") if axis["unit"] else ""
    axes.set_xticklabels(["%g" % value for value in values])
    axes.set_xlabel(("Young's modulus" if axis["material"] else axis["parameter"]) + unit)
    axes.set_yticks(range(len(time_steps)))
    axes.set_yticklabels([dt_label(dt) for dt in time_steps])
    axes.set_ylabel("time step (s)")
    axes.set_xticks([x - 0.5 for x in range(1, len(values))], minor=True)
    axes.set_yticks([y - 0.5 for y in range(1, len(time_steps))], minor=True)
    axes.grid(which="minor", color="black", linewidth=0.5)
    axes.tick_params(which="minor", length=0)
    axes.set_title("Stability map: " + model["model"] + "\n" + textwrap.fill(axis["note"], 60),
                   fontsize=9)
    used = sorted({code for line in grid for code in line})
    handles = [Patch(facecolor=OUTCOMES[code][2], edgecolor="black", label=OUTCOMES[code][1])
               for code in used]
    axes.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    figure.tight_layout()
    save(figure, os.path.join(out, "stability_" + safe_name(model["model"]) + ".png"))


def main():
    data, out = read_input(__doc__.splitlines()[0], "stability_json")
    time_steps = data["settings"]["time_steps"]
    for model in data["models"]:
        plot_model(model, time_steps, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
