#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""bench/run against a fake build: a bench/ folder of tiny shell scripts that write
Google-Benchmark-like JSON to --benchmark_out and log the arguments they got, so the run file's
shape, the arguments passed and the all-or-nothing write are checked without a real benchmark.

Usage: bench_run_test.py [unittest arguments, e.g. a test class name]"""

import importlib.util
import json
import os
import re
import signal
import socket
import stat
import subprocess
import sys
import tempfile
import time
import unittest

sys.dont_write_bytecode = True  # keep the source tree free of __pycache__
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import dashboard_support as support  # noqa: E402

# A fake executable. FAKE_MODE picks a misbehaviour: fail (exit 3), garbage (not JSON), nomatch
# (an empty --benchmark_out, as Google Benchmark leaves when its filter matches nothing), sleep
# (hangs until killed). FAKE_FAILING names the one executable that misbehaves.
FAKE = r"""#!/bin/sh
name=$(basename "$0")
out=""
for argument in "$@"; do
  printf '%s\n' "$argument" >> "$FAKE_LOG/$name.args"
  case "$argument" in
    --benchmark_out=*) out="${argument#--benchmark_out=}" ;;
  esac
done
if [ "${FAKE_FAILING:-}" = "$name" ]; then
  case "${FAKE_MODE:-}" in
    fail) echo "$name: failing on purpose" >&2; exit 3 ;;
    garbage) echo "not json" > "$out"; exit 0 ;;
    sleep) touch "$FAKE_LOG/$name.started"; exec sleep 60 ;;
  esac
fi
if [ "${FAKE_MODE:-}" = "nomatch" ]; then
  : > "$out"
  echo "Failed to match any benchmarks against regex: x" >&2
  exit 0
fi
cat > "$out" <<EOF
{
  "context": {
    "date": "2026-11-27T05:57:27+00:00", "host_name": "fakehost", "executable": "$0",
    "num_cpus": 2, "mhz_per_cpu": 2445, "load_avg": [1.5, 1.2, 1.0],
    "library_build_type": "release", "softbench_build_type": "Release",
    REVISION_LINE
    "softbench_compiler": "GCC 12.2.0", "softbench_cpu": "Fake CPU", "softbench_threads": "2",
    "softbench_version": "0.1.0", "fake_name": "$name"
  },
  "benchmarks": [
    {"name": "BM_${name}/liver.msh", "run_name": "BM_${name}/liver.msh", "run_type": "iteration",
     "repetitions": 2, "repetition_index": 0, "threads": 1, "iterations": 8,
     "real_time": 2.0, "cpu_time": 1.9, "time_unit": "ms", "steps_per_s": 526.3,
     "mean_iterations": 16.9},
    {"name": "BM_${name}/liver.msh", "run_name": "BM_${name}/liver.msh", "run_type": "iteration",
     "repetitions": 2, "repetition_index": 1, "threads": 1, "iterations": 8,
     "real_time": 2.2, "cpu_time": 2.1, "time_unit": "ms", "steps_per_s": 476.2,
     "mean_iterations": 16.9},
    {"name": "BM_${name}/liver.msh_median", "run_name": "BM_${name}/liver.msh",
     "run_type": "aggregate", "repetitions": 2, "threads": 1, "aggregate_name": "median",
     "aggregate_unit": "time", "iterations": 2, "real_time": 2.1, "cpu_time": 2.0,
     "time_unit": "ms", "steps_per_s": 501.2, "mean_iterations": 16.9}
  ]
}
EOF
"""
REVISION = '"softbench_revision": "abc1234-dirty",'
EXECUTABLES = ["alpha_bench", "beta_bench"]


def make_build(folder, revision_line=REVISION):
    """A build folder whose bench/ holds the two fakes and things that are not benchmarks."""
    bench = os.path.join(folder, "build", "bench")
    os.makedirs(os.path.join(bench, "CMakeFiles"))
    for name in EXECUTABLES + ["helper.sh"]:
        path = os.path.join(bench, name)
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(FAKE.replace("REVISION_LINE", revision_line))
        os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR)
    with open(os.path.join(bench, "gamma_bench"), "w", encoding="utf-8") as handle:
        handle.write("not executable\n")
    return os.path.join(folder, "build")


class Fixture(unittest.TestCase):

    def setUp(self):
        temporary = tempfile.TemporaryDirectory(prefix="bench-run-test-")
        self.addCleanup(temporary.cleanup)
        self.folder = temporary.name
        self.build = make_build(self.folder)
        self.out = os.path.join(self.folder, "out")
        self.log = os.path.join(self.folder, "log")
        os.makedirs(self.log)

    def run_bench(self, *arguments, mode=None, failing=None):
        environment = dict(os.environ, FAKE_LOG=self.log)
        environment.pop("OMP_WAIT_POLICY", None)
        if mode:
            environment.update(FAKE_MODE=mode, FAKE_FAILING=failing or "")
        return support.run_tool(support.BENCH_RUN, *arguments, environment=environment,
                                timeout=120)

    def arguments_of(self, name):
        with open(os.path.join(self.log, name + ".args"), encoding="utf-8") as handle:
            return handle.read().splitlines()

    def out_files(self):
        return sorted(os.listdir(self.out)) if os.path.isdir(self.out) else []


class ArgumentTest(Fixture):
    """Bad arguments: one line naming the option, status 2, nothing run or written."""

    def expect_refusal(self, arguments, option):
        result = self.run_bench("--out", self.out, *arguments)
        self.assertEqual(result.returncode, 2, result.stderr)
        lines = result.stderr.splitlines()
        self.assertEqual(len(lines), 1, result.stderr)
        self.assertTrue(lines[0].startswith("bench/run: " + option), lines[0])
        self.assertEqual(os.listdir(self.log), [])  # no executable ran
        self.assertEqual(self.out_files(), [])
        return lines[0]

    def test_unknown_options(self):
        self.expect_refusal(["--build", self.build, "--repeat", "3"], "--repeat")
        self.expect_refusal(["--build", self.build, "quick"], "quick")

    def test_values_out_of_range_or_missing(self):
        for value in ("0", "-2", "three", "2.5"):
            self.assertIn(f"'{value}'", self.expect_refusal(
                ["--build", self.build, "--repetitions", value], "--repetitions"))
        for value in ("0", "-1", "soon", "inf", "nan"):
            self.expect_refusal(["--build", self.build, "--min-time", value], "--min-time")
        self.expect_refusal(["--build", self.build, "--filter"], "--filter")
        self.expect_refusal(["--build", self.build, "--filter", ""], "--filter")
        self.expect_refusal(["--build", self.build, "--filter", "BM_(Step"], "--filter")
        self.expect_refusal(["--build", self.build, "--quick", "--quick", "--filter", "a",
                             "--filter", "b"], "--filter")

    def test_goals_runs_its_own_benchmarks_alone(self):
        self.expect_refusal(["--build", self.build, "--goals", "--quick"], "--goals")
        self.expect_refusal(["--build", self.build, "--goals", "--filter", "BM_Step"], "--goals")

    def test_a_build_without_benchmarks(self):
        self.expect_refusal(["--build", os.path.join(self.folder, "nowhere")], "--build")
        self.expect_refusal(["--build", self.log], "--build")  # no bench/ in it
        empty = os.path.join(self.folder, "empty")
        os.makedirs(os.path.join(empty, "bench"))
        self.assertIn("no *_bench executables",
                      self.expect_refusal(["--build", empty], "--build"))

    def test_a_filter_that_matches_nothing_writes_nothing(self):
        result = self.run_bench("--build", self.build, "--out", self.out, "--filter", "BM_None",
                                mode="nomatch")
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("bench/run: --filter: no benchmark matched 'BM_None'", result.stderr)
        self.assertEqual(self.out_files(), [])


class MergeTest(Fixture):
    """A run of every executable merged into one file, landing whole or not at all."""

    def target(self, revision="abc1234-dirty"):
        return os.path.join(self.out, f"{revision}-{socket.gethostname()}.json")

    def test_one_file_with_every_executables_entries(self):
        result = self.run_bench("--build", self.build, "--out", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stdout.splitlines()[-1], self.target())
        self.assertEqual(self.out_files(), [os.path.basename(self.target())])
        with open(self.target(), encoding="utf-8") as handle:
            run = json.load(handle)
        self.assertEqual(sorted(run), ["benchmarks", "context", "softbench_run"])
        # Google Benchmark's context and softbench's provenance, from the first executable.
        self.assertEqual(run["context"]["fake_name"], "alpha_bench")
        self.assertEqual(run["context"]["softbench_revision"], "abc1234-dirty")
        self.assertEqual(run["context"]["num_cpus"], 2)
        # Every entry of every executable, in order, tagged, counters and repetitions kept.
        self.assertEqual([(b["executable"], b["name"]) for b in run["benchmarks"]], [
            ("alpha_bench", "BM_alpha_bench/liver.msh"),
            ("alpha_bench", "BM_alpha_bench/liver.msh"),
            ("alpha_bench", "BM_alpha_bench/liver.msh_median"),
            ("beta_bench", "BM_beta_bench/liver.msh"),
            ("beta_bench", "BM_beta_bench/liver.msh"),
            ("beta_bench", "BM_beta_bench/liver.msh_median")])
        self.assertEqual([b["steps_per_s"] for b in run["benchmarks"][:3]], [526.3, 476.2, 501.2])
        self.assertEqual(run["benchmarks"][1]["repetition_index"], 1)
        info = run["softbench_run"]
        self.assertEqual(info["mode"], "full")
        self.assertEqual(info["repetitions"], 5)
        self.assertEqual([e["executable"] for e in info["executables"]], EXECUTABLES)
        self.assertEqual(info["executables"][1]["context"]["fake_name"], "beta_bench")
        self.assertEqual(info["executables"][0]["benchmarks"], 3)
        # What each executable was asked for.
        for name in EXECUTABLES:
            arguments = self.arguments_of(name)
            self.assertIn("--benchmark_repetitions=5", arguments)
            self.assertIn("--benchmark_enable_random_interleaving=true", arguments)
            self.assertIn("--benchmark_display_aggregates_only=true", arguments)
            self.assertIn("--benchmark_out_format=json", arguments)
            self.assertTrue(any(a.startswith("--benchmark_out=") for a in arguments))
            self.assertFalse(any(a.startswith(("--benchmark_filter", "--benchmark_min_time"))
                                 for a in arguments))
        self.assertFalse(os.path.exists(os.path.join(self.log, "helper.sh.args")))

    @unittest.skipUnless(importlib.util.find_spec("matplotlib") and
                         importlib.util.find_spec("scipy"), "no matplotlib or scipy")
    def test_the_dashboard_reads_the_file_as_it_is(self):
        self.assertEqual(self.run_bench("--build", self.build, "--out", self.out).returncode, 0)
        page = support.run_tool(support.DASHBOARD, self.target(), "--out",
                                os.path.join(self.folder, "page"))
        self.assertEqual(page.returncode, 0, page.stderr)
        with open(os.path.join(self.folder, "page", "index.html"), encoding="utf-8") as handle:
            self.assertIn("BM_alpha_bench/liver.msh", handle.read())

    def test_quick_and_filter_reach_every_executable(self):
        result = self.run_bench("--build", self.build, "--out", self.out, "--quick")
        self.assertEqual(result.returncode, 0, result.stderr)
        arguments = self.arguments_of("beta_bench")
        self.assertIn("--benchmark_repetitions=1", arguments)
        self.assertNotIn("--benchmark_enable_random_interleaving=true", arguments)  # nothing to mix
        self.assertIn("--benchmark_min_time=0.05", arguments)
        self.assertTrue(any(a.startswith("--benchmark_filter=^BM_Step/") for a in arguments))
        os.unlink(os.path.join(self.log, "beta_bench.args"))
        result = self.run_bench("--build", self.build, "--out", self.out, "--quick", "--filter",
                                "BM_Step/.*/liver.msh|BM_TriTri/projection", "--repetitions=3",
                                "--min-time", "0.2")
        self.assertEqual(result.returncode, 0, result.stderr)
        arguments = self.arguments_of("beta_bench")
        self.assertIn("--benchmark_filter=BM_Step/.*/liver.msh|BM_TriTri/projection", arguments)
        self.assertIn("--benchmark_repetitions=3", arguments)
        self.assertIn("--benchmark_min_time=0.2", arguments)
        with open(self.target(), encoding="utf-8") as handle:
            info = json.load(handle)["softbench_run"]
        self.assertEqual((info["mode"], info["repetitions"], info["min_time_s"]),
                         ("quick", 3, 0.2))

    def test_goals_asks_every_executable_for_the_goals_benchmarks_exactly(self):
        self.run_bench("--build", self.build, "--out", self.out, "--goals")
        arguments = self.arguments_of("beta_bench")
        self.assertIn("--benchmark_repetitions=5", arguments)
        regex = [a.partition("=")[2] for a in arguments if a.startswith("--benchmark_filter=")]
        self.assertEqual(len(regex), 1)
        pattern = re.compile(regex[0])
        for name in support.load_goals_module().benchmark_names(
                support.load_goals_module().load_goals()):
            self.assertTrue(pattern.search(name), name)
            self.assertFalse(pattern.search(name + "/repeats:2"), name)
        self.assertFalse(pattern.search("BM_FemStep/cg/liver.msh/threads:2/real_time"))

    def test_a_failing_executable_leaves_the_last_file_as_it_was(self):
        os.makedirs(self.out)
        with open(self.target(), "w", encoding="utf-8") as handle:
            handle.write("the previous run\n")
        for mode, status, message in (("fail", 1, "beta_bench exited with status 3"),
                                      ("garbage", 1, "beta_bench wrote JSON that does not parse")):
            result = self.run_bench("--build", self.build, "--out", self.out, mode=mode,
                                    failing="beta_bench")
            self.assertEqual(result.returncode, status, result.stderr)
            self.assertIn(f"bench/run: {message}", result.stderr.splitlines()[-1])
            self.assertEqual(self.out_files(), [os.path.basename(self.target())])
            with open(self.target(), encoding="utf-8") as handle:
                self.assertEqual(handle.read(), "the previous run\n")

    def test_sigterm_stops_the_executable_and_writes_nothing(self):
        environment = dict(os.environ, FAKE_LOG=self.log, FAKE_MODE="sleep",
                           FAKE_FAILING="beta_bench")
        process = subprocess.Popen([sys.executable, support.BENCH_RUN, "--build", self.build,
                                    "--out", self.out], env=environment,
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        started = os.path.join(self.log, "beta_bench.started")
        deadline = time.monotonic() + 60
        while not os.path.exists(started) and time.monotonic() < deadline:
            time.sleep(0.05)
        self.assertTrue(os.path.exists(started))
        process.send_signal(signal.SIGTERM)
        _, stderr = process.communicate(timeout=60)
        self.assertEqual(process.returncode, 130, stderr)
        self.assertEqual(stderr.splitlines()[-1], "bench/run: interrupted; nothing written")
        self.assertEqual(self.out_files(), [])

    def test_without_a_revision_in_the_context_the_file_is_named_after_git(self):
        self.build = make_build(os.path.join(self.folder, "other"), revision_line="")
        result = self.run_bench("--build", self.build, "--out", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        git = subprocess.run(["git", "-C", support.REPOSITORY, "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, check=False)
        revision = git.stdout.strip() if git.returncode == 0 and git.stdout.strip() \
            else "unknown"
        self.assertEqual(result.stdout.splitlines()[-1], self.target(revision))


if __name__ == "__main__":
    unittest.main()
