# SPDX-License-Identifier: MIT
"""What the tests of bench/run and tools/dashboard share: the tools' paths, the skip rule, and
Google-Benchmark-shaped run files made in code (the benchmark names, units, counters and
aggregate rules of softbench's executables, with seeded noise), so the tests need no benchmark
run and give the same files every time."""

import importlib.machinery
import importlib.util
import json
import os
import random
import statistics
import subprocess
import sys

REPOSITORY = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DASHBOARD = os.path.join(REPOSITORY, "tools", "dashboard")
BENCH_RUN = os.path.join(REPOSITORY, "bench", "run")
SKIP = 77  # ctest's SKIP_RETURN_CODE for these tests


def require_modules(*names):
    """Exits with the skip status when a module the tools need is not installed."""
    for name in names:
        try:
            importlib.import_module(name)
        except ImportError:
            print(f"SKIP: {sys.executable} has no {name} (Debian: python3-{name})")
            sys.exit(SKIP)


def load_dashboard():
    """tools/dashboard as a module (it has no .py suffix, so it needs an explicit loader)."""
    loader = importlib.machinery.SourceFileLoader("dashboard", DASHBOARD)
    spec = importlib.util.spec_from_loader("dashboard", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def load_goals_module():
    """tools/bench_goals.py, the goals that bench/run and tools/dashboard share."""
    sys.path.insert(0, os.path.join(REPOSITORY, "tools"))
    return importlib.import_module("bench_goals")


def run_tool(tool, *arguments, environment=None, timeout=300):
    """Runs a tool with this interpreter (the one whose modules were checked)."""
    return subprocess.run([sys.executable, tool, *arguments], capture_output=True, text=True,
                          timeout=timeout, env=environment, check=False)

MODELS = {  # ms per step on liver.msh, exponent in the size
    "corotational_fem": (1.8, 1.2),
    "mass_spring": (2.2, 1.1),
    "shape_matching": (0.26, 1.0),
    "bullet_softbody": (3.5, 1.05),
    "bullet_deformable": (9.0, 1.3),
    "mass_spring:thesis_springs": (2.0, 1.1),
}
MESHES = {"liver.msh": (1, 1215, 4777), "liver_x4.msh": (4, 4091, 22861),
          "liver_x16.msh": (16, 14562, 84530)}
TRI_TRI = {"projection": 95.0, "moller": 80.0, "guigue_devillers": 70.0, "cgal_epick": 400.0,
           "batch_soa": 30.0}
TREES = {"hybrid": 1.0, "sphere": 1.3, "aabb": 1.1, "fcl_aabb": 2.5}
TARGETS = [0, 32, 97, 279, 534, 733, 925, 1106]


def specs():
    """(executable, name, unit, time in that unit, counters, aggregates only)."""
    result = []
    for model, (ms, exponent) in MODELS.items():
        for mesh, (factor, vertices, tets) in MESHES.items():
            time = ms * factor ** exponent
            name = f"BM_Step/{model}/{mesh}/iterations:120/real_time"
            result.append(("step_bench", name, "ms", time,
                           {"steps_per_s": 1e3 / time, "mean_iterations": 17.5,
                            "vertices": vertices, "dt_s": 1 / 60}, False))
    for solver, ms in (("cg", 1.8), ("cholmod", 21.0)):
        for mesh, (factor, vertices, tets) in MESHES.items():
            time = ms * factor ** 1.25
            name = f"BM_FemStep/{solver}/{mesh}/threads:1/iterations:120/real_time"
            result.append(("fem_bench", name, "ms",
                           time, {"steps_per_s": 1e3 / time, "tets": tets, "vertices": vertices,
                                  "cholmod_match": 5e-4}, False))
    result.append(("mass_spring_bench", "BM_MassSpringStep/defaults/liver.msh", "ms", 2.25,
                   {"steps_per_s": 444.0, "mean_iterations": 16.9, "cholmod_match": 4e-8},
                   False))
    for mesh, (factor, vertices, tets) in MESHES.items():
        result.append(("mesh_bench", f"BM_ReadAndValidate/{mesh}", "ms", 2.1 * factor,
                       {"tets": tets, "tets_per_s": tets / (2.1e-3 * factor)}, False))
    for method, ns in TRI_TRI.items():
        for pair_set in ("designed_mix", "random"):
            for thousands in (100, 500, 1000, 1500, 2000):
                ms = ns * thousands * 1000 * 1e-6
                result.append(("tri_tri_bench",
                               f"BM_TriTri/{method}/{pair_set}/{thousands}/iterations:1/repeats:5",
                               "ms", ms, {"ns_per_pair": ns, "ms_per_million": ns,
                                          "hit_fraction": 0.3}, True))
    result.append(("tri_tri_bench",
                   "BM_TriTriVersus/projection_over_moller/random/iterations:1/repeats:11", "ms",
                   190.0, {"ns_per_pair": 95.0, "peer_ns_per_pair": 80.0, "ratio": 1.19}, True))
    for target in TARGETS:
        for tree, factor in TREES.items():
            us = (40.0 + 0.9 * target * factor) * factor
            result.append(("bvh_bench",
                           f"BM_Frame/tet_faces/target:{target}/{tree}/min_time:0.200/repeats:5",
                           "us", us, {"pairs": float(target), "refit_us": 30.0,
                                      "query_us": us - 30.0}, True))
    return result


def gb_entry(executable, name, unit, real, cpu, counters, index, repetitions, run_type,
             aggregate=None):
    entry = {"name": name + (f"_{aggregate}" if aggregate else ""), "family_index": index,
             "per_family_instance_index": 0, "run_name": name, "run_type": run_type,
             "repetitions": repetitions, "threads": 1}
    if aggregate:
        entry.update({"aggregate_name": aggregate,
                      "aggregate_unit": "percentage" if aggregate == "cv" else "time"})
    else:
        entry["repetition_index"] = 0
    entry.update({"iterations": 10, "real_time": real, "cpu_time": cpu, "time_unit": unit})
    entry.update(counters)
    entry["executable"] = executable
    return entry


def entries(spec, index, repetitions, rng, factor, noise):
    """A benchmark's entries as Google Benchmark 1.7 writes them: the repetitions, then mean,
    median, stddev and cv when there are several (only those when it reports aggregates only)."""
    executable, name, unit, time, counters, aggregates_only = spec
    if aggregates_only:
        repetitions = 5
    samples = []
    for repetition in range(repetitions):
        scale = factor * (1.0 + rng.gauss(0.0, noise))
        cpu = time * scale
        sample_counters = {k: (v / scale if k in ("steps_per_s", "tets_per_s") else
                               v * scale if k in ("ns_per_pair", "ms_per_million") else v)
                           for k, v in counters.items()}
        entry = gb_entry(executable, name, unit, cpu * 1.01, cpu, sample_counters, index,
                         repetitions, "iteration")
        entry["repetition_index"] = repetition
        samples.append(entry)
    result = [] if aggregates_only else list(samples)
    if repetitions > 1:
        for aggregate, reduce in (("mean", statistics.mean), ("median", statistics.median),
                                  ("stddev", statistics.stdev)):
            values = {key: reduce([s[key] for s in samples])
                      for key in ["real_time", "cpu_time"] + list(counters)}
            result.append(gb_entry(executable, name, unit, values.pop("real_time"),
                                   values.pop("cpu_time"), values, index, repetitions,
                                   "aggregate", aggregate))
        result.append(gb_entry(executable, name, unit, 0.01, 0.01, {}, index, repetitions,
                               "aggregate", "cv"))
    return result


def make_run(date, revision="abc1234", host="testhost", repetitions=5, seed=1, factor=None,
             noise=0.01, keep=None):
    """A bench/run file: `factor(name)` scales a benchmark's times (the injected slowdown),
    `keep(name)` selects benchmarks (a filtered or quick run)."""
    rng = random.Random(seed)
    benchmarks = []
    for index, spec in enumerate(specs()):
        if keep is not None and not keep(spec[1]):
            continue
        scale = factor(spec[1]) if factor else 1.0
        benchmarks.extend(entries(spec, index, repetitions, rng, scale, noise))
    context = {"date": date, "host_name": host, "executable": "/build/bench/step_bench",
               "num_cpus": 2, "mhz_per_cpu": 2445, "cpu_scaling_enabled": False,
               "load_avg": [1.0, 1.0, 1.0], "library_build_type": "release",
               "softbench_build_type": "Release", "softbench_compiler": "GCC 12.2.0",
               "softbench_cpu": "Test CPU", "softbench_revision": revision,
               "softbench_threads": "2", "softbench_version": "0.1.0"}
    return {"context": context,
            "softbench_run": {"tool": "bench/run", "mode": "full", "filter": None,
                              "repetitions": repetitions, "min_time_s": None, "host": host,
                              "revision": revision, "executables": []},
            "benchmarks": benchmarks}


def write(path, run):
    with open(path, "w", encoding="utf-8") as handle:
        json.dump(run, handle, indent=1)
    return path
