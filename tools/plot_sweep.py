"""Draws the speed-accuracy plot of `softbench sweep` (or merge) from its sweep.json.

Usage: plot_sweep.py sweep.json [--out DIR]

Writes DIR/sweep.png (default DIR: the folder of sweep.json): each stable run's position error
against the reference (relative RMS, log) over its steps per second (log), one colour per model,
each model's Pareto front joined by a line, and the 1%, 5% and 20% error budgets marked. Against
a reference that did not converge (sweep.json's ranking_refused) there is no front, and the
title says the errors are not ranked.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_common import finite_pairs, plt, read_input, save  # noqa: E402


def main():
    data, out = read_input(__doc__.splitlines()[0], "sweep_json")
    records = [r for r in data["records"] if r["stable"]]
    pareto = set(data.get("pareto", []))
    figure, axes = plt.subplots(figsize=(7.5, 5.2))
    models = sorted({r["model"] for r in records})
    for index, model in enumerate(models):
        colour = "C%d" % index
        runs = [r for r in records if r["model"] == model]
        xs, ys = finite_pairs([r["steps_per_second"] for r in runs], [r["rms_error"] for r in runs])
        axes.scatter(xs, ys, color=colour, label=model, s=22)
        front = sorted((r for r in runs if r["id"] in pareto), key=lambda r: r["steps_per_second"])
        fx, fy = finite_pairs([r["steps_per_second"] for r in front], [r["rms_error"] for r in front])
        if len(fx) > 1:
            axes.plot(fx, fy, color=colour, linewidth=1.0)
    for budget in (0.01, 0.05, 0.2):
        axes.axhline(budget, color="grey", linestyle=":", linewidth=0.8)
        axes.annotate("%g%%" % (100 * budget), (1.0, budget), xycoords=("axes fraction", "data"),
                      fontsize=7, color="grey", ha="right", va="bottom")
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("steps per second")
    axes.set_ylabel("position error vs reference (relative RMS)")
    title = "Speed and accuracy: " + str(data.get("scene", ""))
    if data.get("ranking_refused"):
        title += "\n(not ranked: the reference has not converged)"
    axes.set_title(title, fontsize=10)
    axes.grid(True, which="both", alpha=0.3)
    if models:
        axes.legend(fontsize=8)
    figure.tight_layout()
    save(figure, os.path.join(out, "sweep.png"))


if __name__ == "__main__":
    main()
