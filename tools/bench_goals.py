# SPDX-License-Identifier: MIT
"""The speed goals of bench/goals.json judged against one benchmark run (tools/dashboard's Run:
its benchmarks by name, each with median CPU and wall times and counter medians).

A goal measures one figure of the run and bounds it (`at_least` or `at_most`, and optionally a
`floor`, a weaker bound in the same direction that a goal short of its target may still meet).
The figure is one of:
  {"rate": NAME}                      steps per CPU second: 1 / the median CPU time of an
                                      iteration (the benchmarks that time one step an iteration)
  {"counter": KEY, "of": NAME}        a counter's median
  {"ratio": [A, B], "clock": C}       the median time of A over B's, both of the same run; C is
                                      "cpu" (the default) or "real" (wall time: what a second
                                      thread buys shows there, not in one thread's CPU time)
  {"exponent": TEMPLATE, "meshes": M} the least-squares slope of log CPU time on log size over
                                      the meshes M ("{mesh}" in TEMPLATE): sizes are the tets
                                      the run's fem_bench or mesh_bench report, else the
                                      nominal factor in the mesh's name
Figures shown beside it (`beside`: counters of the goal's benchmark, or of `of`) may carry
bounds of their own: a goal is met only when they are too (the accuracy a speed was bought
with). Verdicts: "met", "floor" (the floor met, the goal not), "unmet", "no data" (a benchmark
or counter the goal needs is not in the run: a quick or filtered run)."""

import json
import math
import os
import re

HERE = os.path.dirname(os.path.abspath(__file__))
GOALS_FILE = os.path.join(os.path.dirname(HERE), "bench", "goals.json")
MESH_FACTOR = re.compile(r"^liver(?:_x(\d+))?\.msh$")
MEASURE_KINDS = ("rate", "counter", "ratio", "exponent")


class GoalsError(Exception):
    """A goals file that cannot be used: the message names the file and the goal's key."""


def fit_exponent(xs, ys):
    """Least-squares slope of log y against log x: the cost's exponent in the size."""
    logs = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0]
    if len(logs) < 2:
        return None
    mean_x = sum(x for x, _ in logs) / len(logs)
    mean_y = sum(y for _, y in logs) / len(logs)
    spread = sum((x - mean_x) ** 2 for x, _ in logs)
    if spread == 0:
        return None
    return sum((x - mean_x) * (y - mean_y) for x, y in logs) / spread


def mesh_tets(run):
    """Tets per shipped liver from any benchmark that reports a "tets" counter for it
    (fem_bench, mesh_bench)."""
    found = {}
    for name, bench in run.benches.items():
        value = bench.counter("tets")
        if not value:
            continue
        for part in name.split("/"):
            if MESH_FACTOR.match(part):
                found.setdefault(part, value)
    return found


# ----------------------------------------------------------------------------------------------
# Reading the goals


def is_number(value):
    """A finite int or float, not a bool: what a JSON figure must be to be judged or drawn."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _check_bounds(entry, where, require):
    bounds = [key for key in ("at_least", "at_most") if key in entry]
    if require and len(bounds) != 1:
        raise GoalsError(f"{where}: give exactly one of \"at_least\" and \"at_most\"")
    if len(bounds) > 1:
        raise GoalsError(f"{where}: give at most one of \"at_least\" and \"at_most\"")
    for key in bounds + (["floor"] if "floor" in entry else []):
        if not is_number(entry[key]):
            raise GoalsError(f"{where}.{key}: expected a number")
    if "floor" in entry:
        if not bounds:
            raise GoalsError(f"{where}.floor: a floor needs \"at_least\" or \"at_most\"")
        target = entry[bounds[0]]
        weaker = entry["floor"] <= target if bounds[0] == "at_least" else entry["floor"] >= target
        if not weaker:
            raise GoalsError(f"{where}.floor: must be weaker than {bounds[0]} ({target})")


def _check_string(value, where):
    if not isinstance(value, str) or not value:
        raise GoalsError(f"{where}: expected a non-empty string")


def _check_measure(measure, where):
    if not isinstance(measure, dict):
        raise GoalsError(f"{where}: expected an object")
    kinds = [kind for kind in MEASURE_KINDS if kind in measure]
    if len(kinds) != 1:
        raise GoalsError(f"{where}: expected exactly one of " + ", ".join(MEASURE_KINDS))
    kind = kinds[0]
    if kind == "rate":
        _check_string(measure["rate"], f"{where}.rate")
    elif kind == "counter":
        _check_string(measure["counter"], f"{where}.counter")
        _check_string(measure.get("of"), f"{where}.of")
    elif kind == "ratio":
        pair = measure["ratio"]
        if not isinstance(pair, list) or len(pair) != 2:
            raise GoalsError(f"{where}.ratio: expected [numerator, denominator] benchmark names")
        for index, name in enumerate(pair):
            _check_string(name, f"{where}.ratio[{index}]")
        if measure.get("clock", "cpu") not in ("cpu", "real"):
            raise GoalsError(f"{where}.clock: expected \"cpu\" or \"real\"")
    else:
        template = measure["exponent"]
        _check_string(template, f"{where}.exponent")
        if "{mesh}" not in template:
            raise GoalsError(f"{where}.exponent: the name needs a {{mesh}} placeholder")
        meshes = measure.get("meshes")
        if (not isinstance(meshes, list) or len(meshes) < 2
                or not all(isinstance(m, str) and MESH_FACTOR.match(m) for m in meshes)):
            raise GoalsError(f"{where}.meshes: expected two or more shipped livers "
                             "(liver.msh, liver_x4.msh, ...)")
    return kind


def _objects(items, where):
    """(where[index], item) for each item of a list, each checked to be an object."""
    for index, item in enumerate(items):
        if not isinstance(item, dict):
            raise GoalsError(f"{where}[{index}]: expected an object")
        yield f"{where}[{index}]", item


def load_goals(path=GOALS_FILE):
    """The goals of a goals file, checked; GoalsError names the file and the bad key."""
    try:
        with open(path, encoding="utf-8") as handle:
            data = json.load(handle)
    except FileNotFoundError:
        raise GoalsError(f"{path}: no such file") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise GoalsError(f"{path}: not JSON ({error})") from None
    except OSError as error:
        raise GoalsError(f"{path}: cannot read it ({error.strerror})") from None
    goals = data.get("goals") if isinstance(data, dict) else None
    if not isinstance(goals, list) or not goals:
        raise GoalsError(f"{path}: expected an object with a non-empty \"goals\" list")
    for where, goal in _objects(goals, f"{path}: goals"):
        _check_string(goal.get("workload"), f"{where}.workload")
        _check_string(goal.get("unit"), f"{where}.unit")
        if "measure" not in goal:
            raise GoalsError(f"{where}.measure: missing")
        _check_measure(goal["measure"], f"{where}.measure")
        _check_bounds(goal, where, require=True)
        beside = goal.get("beside", [])
        if not isinstance(beside, list):
            raise GoalsError(f"{where}.beside: expected a list")
        one_benchmark = "rate" in goal["measure"] or "counter" in goal["measure"]
        for at, entry in _objects(beside, f"{where}.beside"):
            _check_string(entry.get("label"), f"{at}.label")
            _check_string(entry.get("counter"), f"{at}.counter")
            if "of" in entry or not one_benchmark:
                # A ratio's or an exponent's figures come from several benchmarks: name one.
                _check_string(entry.get("of"), f"{at}.of")
            _check_bounds(entry, at, require=False)
    return goals


def benchmark_names(goals):
    """Every benchmark the goals read, in order, once each."""
    names = []
    for goal in goals:
        measure = goal["measure"]
        if "rate" in measure:
            found = [measure["rate"]]
        elif "counter" in measure:
            found = [measure["of"]]
        elif "ratio" in measure:
            found = list(measure["ratio"])
        else:
            found = [measure["exponent"].replace("{mesh}", mesh) for mesh in measure["meshes"]]
        found += [entry["of"] for entry in goal.get("beside", []) if "of" in entry]
        names += [name for name in found if name not in names]
    return names


def filter_regex(goals):
    """A --benchmark_filter (Google Benchmark's extended regex) that runs exactly the goals'
    benchmarks: each name anchored at both ends, its special characters escaped."""
    special = set(".[](){}*+?|^$\\")

    def escaped(name):
        return "".join("\\" + c if c in special else c for c in name)

    return "^(" + "|".join(escaped(name) for name in benchmark_names(goals)) + ")$"


# ----------------------------------------------------------------------------------------------
# Judging a run


def _within(value, entry, key):
    """Whether value meets entry[key], in the direction of the entry's bound (a floor's too)."""
    return value >= entry[key] if "at_least" in entry else value <= entry[key]


def _bound_key(entry):
    return "at_least" if "at_least" in entry else "at_most" if "at_most" in entry else None


def measure_value(run, measure):
    """(the figure or None, the benchmark names it reads, the names missing from the run)."""
    benches = run.benches

    def timed(name, clock="cpu"):
        bench = benches.get(name)
        if bench is None:
            return None
        seconds = bench.median_real() if clock == "real" else bench.median_cpu()
        return seconds if seconds and seconds > 0 else None

    if "rate" in measure:
        name = measure["rate"]
        seconds = timed(name)
        return (1.0 / seconds if seconds else None), [name], ([] if seconds else [name])
    if "counter" in measure:
        name = measure["of"]
        bench = benches.get(name)
        if bench is None:
            return None, [name], [name]
        value = bench.counter(measure["counter"])
        return value, [name], ([] if value is not None else [f"{name} ({measure['counter']})"])
    if "ratio" in measure:
        clock = measure.get("clock", "cpu")
        names = list(measure["ratio"])
        times = [timed(name, clock) for name in names]
        missing = [name for name, time in zip(names, times) if time is None]
        return (times[0] / times[1] if not missing else None), names, missing
    template = measure["exponent"]
    names = [template.replace("{mesh}", mesh) for mesh in measure["meshes"]]
    times = [timed(name) for name in names]
    missing = [name for name, time in zip(names, times) if time is None]
    if missing:
        return None, names, missing
    tets = mesh_tets(run)
    if all(mesh in tets for mesh in measure["meshes"]):
        sizes = [tets[mesh] for mesh in measure["meshes"]]
    else:
        sizes = [float(MESH_FACTOR.match(mesh).group(1) or 1) for mesh in measure["meshes"]]
    return fit_exponent(sizes, times), names, []


def bound_text(entry, percent=False):
    """The bound of a goal or beside entry as text, e.g. ">= 1000 (floor 700)", "<= 1%"."""
    key = _bound_key(entry)
    if key is None:
        return ""

    text = (">= " if key == "at_least" else "<= ") + format_value(entry[key], percent)
    if "floor" in entry:
        text += f" (floor {format_value(entry['floor'], percent)})"
    return text


def format_value(value, percent=False):
    """A figure as the tables show it ("-" for none); `percent`: a fraction shown in percent."""
    if value is None:
        return "-"
    if percent:
        return f"{format_value(100.0 * value)}%"
    magnitude = abs(value)
    if float(value).is_integer() and magnitude < 1e15:
        return f"{int(value):,}"  # a bound as written: 15, not 15.0
    if magnitude >= 1000:
        return f"{value:,.0f}"
    if magnitude >= 100:
        return f"{value:.0f}"
    if magnitude >= 10:
        return f"{value:.1f}"
    if magnitude >= 0.01 or value == 0:
        return f"{value:.3g}"
    return f"{value:.2g}"


def judge(run, goal):
    """One goal against the run: a dict with workload, value, unit, bound, beside (label, the
    figure as shown, bound text, whether within it: None when unbounded), verdict, sources and
    missing."""
    value, sources, missing = measure_value(run, goal["measure"])
    default_source = sources[-1] if "counter" in goal["measure"] or "rate" in goal["measure"] \
        else None
    beside = []
    beside_ok = True
    for entry in goal.get("beside", []):
        name = entry.get("of", default_source)
        bench = run.benches.get(name) if name else None
        figure = bench.counter(entry["counter"]) if bench is not None else None
        key = _bound_key(entry)
        within = None
        if key is not None:
            if figure is None:
                if name not in missing:  # a benchmark missing altogether is named once
                    missing.append(f"{name} ({entry['counter']})" if bench else name)
            else:
                within = _within(figure, entry, key)
                beside_ok = beside_ok and within
        percent = entry.get("percent", False)
        beside.append({"label": entry["label"], "shown": format_value(figure, percent),
                       "bound": bound_text(entry, percent), "within": within})
    key = _bound_key(goal)
    if value is None or missing:
        verdict = "no data"
    elif _within(value, goal, key) and beside_ok:
        verdict = "met"
    elif "floor" in goal and _within(value, goal, "floor") and beside_ok:
        verdict = "floor"
    else:
        verdict = "unmet"
    return {"workload": goal["workload"], "value": value, "unit": goal["unit"],
            "bound": bound_text(goal), "beside": beside, "verdict": verdict,
            "sources": sources, "missing": missing}


def judge_all(run, goals):
    return [judge(run, goal) for goal in goals]


VERDICT_TEXT = {"met": "met", "floor": "floor met", "unmet": "not met", "no data": "no data"}


def verdict_text(result):
    """The verdict in words, with what the run lacked for a goal without data."""
    text = VERDICT_TEXT[result["verdict"]]
    if result["missing"]:
        text += " (" + ", ".join(result["missing"]) + " not in the run)"
    return text


def beside_text(item):
    text = f"{item['label']} {item['shown']}"
    if item["bound"]:
        text += f" ({item['bound']}{'' if item['within'] is not False else ', not met'})"
    return text


def measured_text(result):
    return f"{format_value(result['value'])} {result['unit']}" if result["value"] is not None \
        else "-"


def markdown_table(results, run_label, before=None, before_label=None):
    """The goals table as the issue notes give it: one row a goal. With `before` (the same goals
    judged against an earlier run), a column of its figures beside the newest's."""
    lines = [f"Goals (bench/goals.json) against {run_label}"
             + (f", before: {before_label}" if before is not None else "") + ":", ""]
    if before is None:
        lines += ["| workload | measured | goal | beside | verdict |", "|---|---|---|---|---|"]
    else:
        lines += ["| workload | before | after | goal | beside (after) | verdict (after) |",
                  "|---|---|---|---|---|---|"]
    for number, result in enumerate(results):
        beside = "; ".join(beside_text(item) for item in result["beside"]) or "-"
        figures = measured_text(result)
        if before is not None:
            figures = f"{measured_text(before[number])} | {figures}"
        lines.append(f"| {result['workload']} | {figures} | {result['bound']} | {beside} "
                     f"| {verdict_text(result)} |")
    met = sum(result["verdict"] == "met" for result in results)
    lines += ["", f"{met} of {len(results)} goals met"
              + (f" ({sum(r['verdict'] == 'met' for r in before)} before)."
                 if before is not None else ".")]
    return "\n".join(lines) + "\n"
