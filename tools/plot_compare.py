#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Draws the plots of `softbench compare` from its compare.json with matplotlib.

Usage: plot_compare.py compare.json [--out DIR]

Writes into DIR (default: the folder of compare.json), each atomically (temporary + rename):
  steps_per_second.png            steps/s per model and scene, simulation only and with
                                  collision, log scale, the thesis's FPS marked
  force_displacement_<scene>.png  instrument (or grasp) force against its displacement, per model
  recovery_<scene>.png            recovery residual over time after the release, per model, log y
  equal_accuracy.png              real-time factor against error per model and setting, the
                                  error budgets marked (when compare.json has the trade)
A scene with no tool load has no force plot, one with no release no recovery plot. Prints the
path of every file written, one per line (softbench reads them).
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_common import finite_pairs, plt, read_input, safe_name, save  # noqa: E402


def plot_steps_per_second(data, out):
    scenes = data["scenes"]
    labels = []
    for scene in scenes:
        for run in scene["runs"]:
            if run["model"] not in labels:
                labels.append(run["model"])
    if not labels:
        return
    series = []  # (legend, values per label, colour, with collision)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for index, scene in enumerate(scenes):
        by_label = {run["model"]: run for run in scene["runs"]}
        colour = colours[index % len(colours)]
        for key, what in (("steps_per_second", "simulation"),
                          ("steps_per_second_with_collision", "with collision")):
            values = [by_label[label]["timing"][key] if label in by_label else 0.0 for label in labels]
            series.append((scene["name"] + ", " + what, values, colour, key != "steps_per_second"))
    width = 0.8 / len(series)
    figure, axes = plt.subplots(figsize=(max(8.0, 1.4 * len(labels) + 4.5), 5.0))
    for index, (legend, values, colour, collision) in enumerate(series):
        positions = [i - 0.4 + width * (index + 0.5) for i in range(len(labels))]
        heights = [v if v and v > 0 else float("nan") for v in values]
        axes.bar(positions, heights, width, label=legend, color=colour,
                 alpha=0.55 if collision else 1.0, hatch="//" if collision else None,
                 edgecolor="black", linewidth=0.5)
    thesis = {}
    for scene in scenes:
        for run in scene["runs"]:
            if run.get("thesis_steps_per_second"):
                thesis.setdefault(run["model"], run["thesis_steps_per_second"])
    thesis_x = [i for i, label in enumerate(labels) if label in thesis]
    thesis_y = [thesis[labels[i]] for i in thesis_x]
    if thesis_x:
        axes.scatter(thesis_x, thesis_y, marker="D", s=70, color="black", zorder=5,
                     label="thesis (i3-2100, FPS with rendering)")
    axes.axhline(50.0, color="grey", linestyle=":", linewidth=1)
    axes.text(-0.45, 50.0, "50 steps/s", va="bottom", ha="left", color="grey", fontsize=8)
    axes.set_yscale("log")
    axes.set_xticks(range(len(labels)))
    axes.set_xticklabels(labels, rotation=20, ha="right")
    axes.set_ylabel("steps per second")
    axes.set_title("Speed per model (" + data.get("machine", "") + ")", fontsize=10)
    axes.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes.grid(True, axis="y", which="both", alpha=0.3)
    figure.tight_layout()
    save(figure, os.path.join(out, "steps_per_second.png"))


def release_time(scene):
    """When the tool lets go (scene JSON as metrics.json echoes it); infinity if never."""
    settings = scene["scene"]
    instrument = settings.get("instrument")
    if instrument:
        grasp = instrument.get("grasp")
        return grasp["release"] if grasp else instrument.get("release", math.inf)
    grasp = settings.get("grasp")
    return grasp.get("release", math.inf) if grasp else math.inf


def plot_force_displacement(scene, out):
    """Left: the loading curve, force against the tool's travel past first contact, up to the
    release (each model meets the tissue where its own sag put it). Right: force over time."""
    figure, (loading, history) = plt.subplots(1, 2, figsize=(11.0, 4.6))
    release = release_time(scene)
    drawn = False
    for run in scene["runs"]:
        samples = run["series"]
        times = samples["time"]
        forces = samples["tool_force"]
        travel = samples["tool_displacement"]
        contact = next((i for i, f in enumerate(forces) if f is not None and f > 0.0), None)
        if contact is None:
            continue
        drawn = True
        pressing = [i for i in range(contact, len(times)) if times[i] <= release]
        xs, ys = finite_pairs([1000.0 * (travel[i] - travel[contact]) for i in pressing],
                              [forces[i] for i in pressing])
        loading.plot(xs, ys, label=run["model"], linewidth=1.2)
        ts, fs = finite_pairs(times, forces)
        history.plot(ts, fs, label=run["model"], linewidth=1.0)
    if not drawn:
        plt.close(figure)
        return
    loading.set_xlabel("tool travel past first contact (mm)")
    loading.set_ylabel("force on the tool (N)")
    loading.set_title("Loading until release: " + scene["name"], fontsize=10)
    loading.grid(True, alpha=0.3)
    loading.legend(fontsize=8)
    history.set_xlabel("time (s)")
    history.set_ylabel("force on the tool (N)")
    history.set_title("Force over time", fontsize=10)
    if math.isfinite(release):
        history.axvline(release, color="grey", linestyle="--", linewidth=0.8)
    history.grid(True, alpha=0.3)
    figure.tight_layout()
    save(figure, os.path.join(out, "force_displacement_" + safe_name(scene["name"]) + ".png"))


def plot_recovery(scene, out):
    figure, axes = plt.subplots(figsize=(7.0, 5.0))
    drawn = False
    for run in scene["runs"]:
        samples = run["series"]
        ts, rs = finite_pairs(samples["time"], samples["recovery_residual"])
        points = [(t, 100.0 * r) for t, r in zip(ts, rs) if r > 0.0]  # log axis: positive only
        if points:
            axes.plot([p[0] for p in points], [p[1] for p in points], label=run["model"],
                      linewidth=1.2)
            drawn = True
    if not drawn:
        plt.close(figure)
        return
    axes.axhline(1.0, color="grey", linestyle=":", linewidth=1)
    axes.set_yscale("log")
    axes.set_xlabel("time (s)")
    axes.set_ylabel("recovery residual (% of bounding-box diagonal)")
    axes.set_title("Recovery after release: " + scene["name"])
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    save(figure, os.path.join(out, "recovery_" + safe_name(scene["name"]) + ".png"))


def plot_equal_accuracy(trade, out):
    """Each setting a point (error, simulated s per wall s), each model's front joined."""
    if not trade or not trade.get("settings"):
        return
    figure, axes = plt.subplots(figsize=(8.5, 5.5))
    models = []
    for setting in trade["settings"]:
        if setting["model"] not in models:
            models.append(setting["model"])
    for model in models:
        points = sorted((100.0 * s["error"], s["realtime_factor"]) for s in trade["settings"]
                        if s["model"] == model and s["stable"] and s["error"] is not None
                        and s["realtime_factor"] > 0)
        if not points:
            continue
        # The front: the fastest point at or below each error.
        front, fastest = [], 0.0
        for error, speed in points:
            if speed > fastest:
                front.append((error, speed))
                fastest = speed
        line = axes.plot([p[0] for p in front], [p[1] for p in front], "-", linewidth=1.2)[0]
        axes.scatter([p[0] for p in points], [p[1] for p in points], color=line.get_color(),
                     label=model, s=30, zorder=4)
    for budget in trade["budgets"]:
        axes.axvline(100.0 * budget, color="grey", linestyle=":", linewidth=1)
        axes.text(100.0 * budget, 1.0, " %g%%" % (100.0 * budget), color="grey", fontsize=8,
                  transform=axes.get_xaxis_transform(), va="top")
    axes.axhline(1.0, color="black", linestyle="--", linewidth=0.8)
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("RMS position error against the reference (% of its displacement)")
    axes.set_ylabel("real-time factor (simulated s per wall s)")
    axes.set_title("Speed at equal accuracy: " + trade["scene"] + " (every model matched to the tissue)",
                   fontsize=10)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    save(figure, os.path.join(out, "equal_accuracy.png"))


def main():
    data, out = read_input(__doc__.splitlines()[0], "compare_json")
    plot_steps_per_second(data, out)
    for scene in data["scenes"]:
        plot_force_displacement(scene, out)
        plot_recovery(scene, out)
    plot_equal_accuracy(data.get("equal_accuracy"), out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
