#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/dashboard on run files made in code: the comparison's verdicts, the page's charts (or
their no-data notes), the softbench compare folder, and bad input.

Usage: dashboard_test.py [unittest arguments, e.g. a test class name]
Exit status 77 (ctest: skipped) when this python has no matplotlib or scipy."""

import json
import os
import re
import shutil
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True  # keep the source tree free of __pycache__
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import dashboard_support as support  # noqa: E402

support.require_modules("matplotlib", "scipy")
dashboard = support.load_dashboard()
goals_module = support.load_goals_module()

OLD_DATE = "2026-11-20T10:00:00+00:00"
NEW_DATE = "2026-11-21T10:00:00+00:00"
SLOW = "BM_Step/shape_matching/liver.msh/iterations:120/real_time"
SLIGHTLY_SLOW = "BM_Step/mass_spring/liver.msh/iterations:120/real_time"
CHART_IDS = ["steps-per-model", "cost-vs-size", "tri-tri-ns-per-pair", "bvh-frame-time"]


def injected(factors):
    return lambda name: factors.get(name, 1.0)


def run_object(path, data, order):
    return dashboard.Run(path, data, order)


def figures(page):
    """{id: the figure's HTML} for every <figure class="chart ..."> of the page."""
    found = {}
    for match in re.finditer(r'<figure class="chart[^"]*" id="([^"]+)">(.*?)</figure>', page,
                             re.S):
        found[match.group(1)] = match.group(2)
    return found


def row_classes(page, table_id):
    table = re.search(rf'<table class="[^"]*" id="{table_id}">(.*?)</table>', page, re.S)
    if table is None:
        return {}
    return {html_name: verdict for verdict, html_name in re.findall(
        r'<tr class="([a-z]+)"><td class="name">([^<]+)</td>', table.group(1))}


class ComparisonTest(unittest.TestCase):
    """The rules of the comparison, on the Run objects the page is made from."""

    def compare(self, old, new):
        rows = dashboard.compare_runs(run_object("old.json", old, 0),
                                      run_object("new.json", new, 1))
        return {row["name"]: row for row in rows}

    def test_flags_a_doubled_time_and_not_two_percent(self):
        old = support.make_run(OLD_DATE, seed=1)
        new = support.make_run(NEW_DATE, seed=2, factor=injected({SLOW: 2.0, SLIGHTLY_SLOW: 1.02}))
        rows = self.compare(old, new)
        self.assertEqual(rows[SLOW]["verdict"], "regression")
        self.assertEqual(rows[SLOW]["basis"], "U test")
        self.assertAlmostEqual(rows[SLOW]["ratio"], 2.0, delta=0.1)
        # 5 against 5 with no overlap: the exact two-sided p-value is 2 / C(10, 5).
        self.assertAlmostEqual(rows[SLOW]["p_value"], 2 / 252, places=6)
        self.assertEqual(rows[SLIGHTLY_SLOW]["verdict"], "unchanged")
        self.assertAlmostEqual(rows[SLIGHTLY_SLOW]["ratio"], 1.02, delta=0.015)
        flagged = [name for name, row in rows.items() if row["verdict"] != "unchanged"]
        self.assertEqual(flagged, [SLOW])

    def test_flags_an_improvement_the_same_way(self):
        old = support.make_run(OLD_DATE, seed=1)
        new = support.make_run(NEW_DATE, seed=2, factor=injected({SLOW: 0.5}))
        self.assertEqual(self.compare(old, new)[SLOW]["verdict"], "improvement")

    def test_single_repetitions_are_judged_on_the_ratio_alone(self):
        old = support.make_run(OLD_DATE, seed=1, repetitions=1)
        new = support.make_run(NEW_DATE, seed=2, repetitions=1,
                               factor=injected({SLOW: 2.0, SLIGHTLY_SLOW: 1.3}))
        rows = self.compare(old, new)
        self.assertEqual(rows[SLOW]["basis"], "ratio only")
        self.assertIsNone(rows[SLOW]["p_value"])
        self.assertEqual(rows[SLOW]["verdict"], "regression")
        self.assertEqual(rows[SLIGHTLY_SLOW]["verdict"], "unchanged")

    def test_three_against_three_cannot_be_significant_so_the_ratio_decides(self):
        old = support.make_run(OLD_DATE, seed=1, repetitions=3)
        new = support.make_run(NEW_DATE, seed=2, repetitions=3, factor=injected({SLOW: 2.0}))
        row = self.compare(old, new)[SLOW]
        self.assertAlmostEqual(row["p_value"], 0.1, places=6)  # 2 / C(6, 3): never below 0.05
        self.assertEqual(row["basis"], "ratio only")
        self.assertEqual(row["verdict"], "regression")

    def test_aggregates_only_benchmarks_use_their_median_and_the_ratio(self):
        name = "BM_TriTri/projection/designed_mix/1000/iterations:1/repeats:5"
        old = support.make_run(OLD_DATE, seed=1)
        new = support.make_run(NEW_DATE, seed=2, factor=injected({name: 2.0}))
        row = self.compare(old, new)[name]
        self.assertEqual(row["basis"], "ratio only")
        self.assertEqual(row["verdict"], "regression")
        self.assertEqual(row["new_repetitions"], 5)

    def test_only_benchmarks_in_both_runs_are_compared(self):
        old = support.make_run(OLD_DATE, seed=1, keep=lambda n: n.startswith("BM_Step/"))
        new = support.make_run(NEW_DATE, seed=2, keep=lambda n: "liver.msh" in n)
        rows = self.compare(old, new)
        self.assertTrue(rows)
        self.assertTrue(all(name.startswith("BM_Step/") and "/liver.msh/" in name
                            for name in rows))

    def test_the_newest_run_is_the_latest_date_not_the_last_argument(self):
        runs = [run_object("new.json", support.make_run(NEW_DATE), 0),
                run_object("old.json", support.make_run(OLD_DATE), 1)]
        self.assertEqual([run.path for run in dashboard.newest_first(runs)],
                         ["new.json", "old.json"])

    def test_the_fitted_exponent_of_a_power_law(self):
        sizes = [4777.0, 22861.0, 84530.0]
        self.assertAlmostEqual(dashboard.fit_exponent(sizes, [3e-6 * n ** 1.3 for n in sizes]),
                               1.3, places=9)
        self.assertIsNone(dashboard.fit_exponent([4777.0], [1.0]))


class PageTest(unittest.TestCase):
    """The page the command writes."""

    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.TemporaryDirectory(prefix="dashboard-test-")
        folder = cls.folder.name
        old = support.write(os.path.join(folder, "old.json"), support.make_run(OLD_DATE, seed=1))
        new = support.write(os.path.join(folder, "new.json"), support.make_run(
            NEW_DATE, revision="def5678", seed=2,
            factor=injected({SLOW: 2.0, SLIGHTLY_SLOW: 1.02})))
        # The newer run first: the order of the arguments must not matter.
        cls.result = support.run_tool(support.DASHBOARD, new, old, "--out",
                                      os.path.join(folder, "page"))
        with open(os.path.join(folder, "page", "index.html"), encoding="utf-8") as handle:
            cls.page = handle.read()

    @classmethod
    def tearDownClass(cls):
        cls.folder.cleanup()

    def test_writes_the_page_and_prints_its_path(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        self.assertEqual(self.result.stdout.strip(),
                         os.path.join(self.folder.name, "page", "index.html"))

    def test_every_chart_is_an_inline_svg_with_drawn_paths(self):
        found = figures(self.page)
        for chart_id in CHART_IDS:
            self.assertIn(chart_id, found)
            self.assertIn("<svg", found[chart_id])
            self.assertRegex(found[chart_id], r'<path [^>]*d="M', chart_id)
            self.assertNotIn("no-data", found[chart_id])

    def test_a_history_chart_per_headline_benchmark(self):
        history = [i for i in figures(self.page) if i.startswith("history-")]
        self.assertIn("history-bm-step-shape-matching-liver-msh-iterations-120-real-time", history)
        self.assertIn("history-bm-massspringstep-defaults-liver-msh", history)
        # Families timed at several sizes get one chart, at the largest size.
        self.assertEqual([i for i in history if "tritri" in i],
                         ["history-bm-tritri-projection-designed-mix-2000-iterations-1-repeats-5"])

    def test_the_comparison_table_flags_the_slowdown_only(self):
        rows = row_classes(self.page, "comparison")
        self.assertEqual(rows[SLOW], "regression")
        self.assertEqual(rows[SLIGHTLY_SLOW], "unchanged")
        self.assertEqual(row_classes(self.page, "flagged"), {SLOW: "regression"})
        self.assertIn('<span class="regression-count">1</span>', self.page)

    def test_the_thesis_figures_are_beside_ours(self):
        steps = figures(self.page)["steps-per-model"]
        self.assertIn("thesis", self.page)
        self.assertIn("787 FPS", self.page)
        self.assertIn("i3-2100", self.page)
        self.assertIn("figures 3.11-3.13", steps)

    def test_the_page_is_self_contained_with_unique_ids(self):
        self.assertNotRegex(self.page, r"<script|<link|<iframe|@import")
        self.assertNotRegex(self.page, r'(src|href)="(https?:|//)')
        self.assertNotIn("url(http", self.page)
        ids = re.findall(r'\bid="([^"]+)"', self.page)
        duplicates = sorted({i for i in ids if ids.count(i) > 1})
        self.assertEqual(duplicates, [])
        # Every local reference points at an id of the page.
        references = set(re.findall(r'(?:xlink:href|href)="#([^"]+)"', self.page))
        references |= set(re.findall(r'url\(#([^)]+)\)', self.page))
        self.assertEqual(references - set(ids), set())

    def test_a_run_without_the_charts_benchmarks_gets_notes_not_a_crash(self):
        folder = self.folder.name
        keep = lambda n: n.startswith("BM_MassSpringStep/")  # noqa: E731
        paths = [support.write(os.path.join(folder, f"quick{i}.json"), support.make_run(
            date, seed=i, repetitions=1, keep=keep)) for i, date in enumerate((OLD_DATE, NEW_DATE))]
        pages = []
        for attempt in range(2):
            out = os.path.join(folder, f"quick_page{attempt}")
            result = support.run_tool(support.DASHBOARD, *paths, "--out", out)
            self.assertEqual(result.returncode, 0, result.stderr)
            with open(os.path.join(out, "index.html"), encoding="utf-8") as handle:
                pages.append(handle.read())
        found = figures(pages[0])
        for chart_id in CHART_IDS:
            self.assertIn('class="no-data"', found[chart_id])
            self.assertNotIn("<svg", found[chart_id])
        self.assertIn("history-bm-massspringstep-defaults-liver-msh", found)
        self.assertEqual(row_classes(pages[0], "comparison"),
                         {"BM_MassSpringStep/defaults/liver.msh": "unchanged"})
        # The same runs give the same page, byte for byte (the SVG ids are salted by chart).
        self.assertEqual(pages[0], pages[1])

    def test_a_single_run_says_the_comparison_needs_two(self):
        out = os.path.join(self.folder.name, "single")
        run = support.write(os.path.join(self.folder.name, "single.json"), support.make_run(
            NEW_DATE, keep=lambda n: n.startswith("BM_Step/") and "/liver.msh/" in n))
        result = support.run_tool(support.DASHBOARD, run, "--out", out)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(os.path.join(out, "index.html"), encoding="utf-8") as handle:
            page = handle.read()
        self.assertIn("comparison and history need two or more", page)
        self.assertNotIn('id="comparison"', page)
        self.assertIn("<svg", figures(page)["steps-per-model"])
        self.assertIn('class="no-data"', figures(page)["cost-vs-size"])


class CompareFolderTest(unittest.TestCase):
    """--compare-dir: the latest softbench compare folder, its markdown and PNGs inline."""

    def test_shows_the_latest_compare_folder(self):
        with tempfile.TemporaryDirectory(prefix="dashboard-compare-") as folder:
            run = support.write(os.path.join(folder, "run.json"), support.make_run(
                NEW_DATE, keep=lambda n: n.startswith("BM_MassSpringStep/")))
            compares = os.path.join(folder, "compares")
            for name, when, title in (("older", 1_000_000, "Old table"),
                                      ("newer", 2_000_000, "New table")):
                path = os.path.join(compares, name)
                os.makedirs(path)
                with open(os.path.join(path, "compare.md"), "w", encoding="utf-8") as handle:
                    handle.write(f"# {title}\n\nSome `text` & more.\n\n"
                                 "| model | steps/s |\n|---|---:|\n| mass_spring | 500 |\n")
                self.write_png(os.path.join(path, "steps_per_second.png"))
                os.utime(os.path.join(path, "compare.md"), (when, when))
            out = os.path.join(folder, "page")
            result = support.run_tool(support.DASHBOARD, run, "--compare-dir", compares,
                                      "--out", out)
            self.assertEqual(result.returncode, 0, result.stderr)
            with open(os.path.join(out, "index.html"), encoding="utf-8") as handle:
                page = handle.read()
        section = re.search(r'<section id="softbench-compare">(.*?)</section>', page, re.S)
        self.assertIsNotNone(section)
        self.assertIn("New table", section.group(1))
        self.assertNotIn("Old table", section.group(1))
        self.assertIn("<th>model</th><th>steps/s</th>", section.group(1))
        self.assertIn("<td>mass_spring</td><td>500</td>", section.group(1))
        self.assertIn("<code>text</code> &amp; more", section.group(1))
        self.assertRegex(section.group(1),
                         r'<img alt="steps_per_second.png" src="data:image/png;base64,iVBORw0KGgo')

    @staticmethod
    def write_png(path):
        import matplotlib

        matplotlib.use("Agg")
        from matplotlib.figure import Figure

        figure = Figure(figsize=(1, 1))
        figure.subplots().plot([0, 1], [0, 1])
        figure.savefig(path, format="png", dpi=20)


class BadInputTest(unittest.TestCase):
    """Bad input: one line naming the file, status 2, and no page."""

    def expect_refusal(self, arguments, named):
        with tempfile.TemporaryDirectory(prefix="dashboard-bad-") as folder:
            out = os.path.join(folder, "page")
            arguments = [a.replace("{folder}", folder) for a in arguments]
            result = support.run_tool(support.DASHBOARD, *arguments, "--out", out)
            self.assertEqual(result.returncode, 2, result.stderr)
            lines = result.stderr.splitlines()
            self.assertEqual(len(lines), 1, result.stderr)
            self.assertIn(named.replace("{folder}", folder), lines[0])
            self.assertFalse(os.path.exists(os.path.join(out, "index.html")))
            return lines[0]

    def with_file(self, name, content):
        folder = tempfile.mkdtemp(prefix="dashboard-input-")
        self.addCleanup(shutil.rmtree, folder)
        path = os.path.join(folder, name)
        with open(path, "wb") as handle:
            handle.write(content)
        return path

    def test_a_missing_file(self):
        line = self.expect_refusal(["{folder}/missing.json"], "{folder}/missing.json")
        self.assertIn("no such file", line)

    def test_a_file_that_is_not_json(self):
        path = self.with_file("run.txt", b'{"context": {}, "benchmarks": [')
        self.assertIn("not JSON", self.expect_refusal([path], path))

    def test_a_file_that_is_not_text(self):
        path = self.with_file("run.bin", b"\x89PNG\r\n\x1a\n\xff\xfe")
        self.assertIn("not JSON", self.expect_refusal([path], path))

    def test_json_that_is_not_a_benchmark_run(self):
        for content in (b'{"context": {}}', b"[1, 2]", b'{"context": [], "benchmarks": []}'):
            path = self.with_file("run.data", content)
            self.assertIn("not a Google Benchmark run", self.expect_refusal([path], path))

    def test_a_bad_file_among_good_ones(self):
        good = self.with_file("good.data", json.dumps(
            support.make_run(NEW_DATE, keep=lambda n: False)).encode())
        bad = self.with_file("bad.data", b"nonsense")
        self.expect_refusal([good, bad], bad)

    def test_a_compare_folder_without_compare_md(self):
        good = self.with_file("good.data", json.dumps(
            support.make_run(NEW_DATE, keep=lambda n: False)).encode())
        empty = os.path.dirname(good)
        self.assertIn("compare.md", self.expect_refusal([good, "--compare-dir", empty], empty))
        self.expect_refusal([good, "--compare-dir", "{folder}/nowhere"], "{folder}/nowhere")

    def test_an_unknown_option_and_no_runs(self):
        self.expect_refusal(["--colour"], "--colour")
        self.expect_refusal([], "run files")


class GoalsTest(unittest.TestCase):
    """bench/goals.json judged against runs made in code: each kind of figure, the floor, the
    bounds beside a goal, missing data, the goals file's checks and the markdown table."""

    @staticmethod
    def run_of(specs, tets=None):
        """A Run of the given (name, cpu ms, real ms, counters) benchmarks, 3 repetitions."""
        rng = support.random.Random(3)
        benchmarks = []
        for index, (name, cpu, real, counters) in enumerate(specs):
            spec = ("any_bench", name, "ms", cpu, counters, False)
            entries = support.entries(spec, index, 3, rng, 1.0, 0.0)
            for entry in entries:
                if entry["run_type"] == "iteration" or entry.get("aggregate_name") != "cv":
                    entry["real_time"] = real
            benchmarks.extend(entries)
        data = support.make_run(NEW_DATE, keep=lambda n: False)
        data["benchmarks"] = benchmarks
        return run_object("goals.json", data, 0)

    def judge(self, goal, specs):
        return dashboard.judge_all(self.run_of(specs), [goal])[0]

    def test_the_shipped_goals_load_and_name_every_figure(self):
        goals = goals_module.load_goals()
        self.assertGreaterEqual(len(goals), 10)
        run = self.run_of([])
        for result in dashboard.judge_all(run, goals):
            self.assertEqual(result["verdict"], "no data")
            self.assertTrue(result["missing"])

    def test_a_rate_is_steps_per_cpu_second_against_its_bound(self):
        goal = {"workload": "w", "unit": "steps/s", "at_least": 1000,
                "measure": {"rate": "BM_A"}}
        fast = self.judge(goal, [("BM_A", 0.8, 2.0, {})])
        self.assertAlmostEqual(fast["value"], 1250.0)
        self.assertEqual(fast["verdict"], "met")
        self.assertEqual(self.judge(goal, [("BM_A", 1.25, 1.0, {})])["verdict"], "unmet")

    def test_a_floor_is_met_short_of_the_goal(self):
        goal = {"workload": "w", "unit": "steps/s", "at_least": 1000, "floor": 700,
                "measure": {"counter": "rate", "of": "BM_A"}}
        self.assertEqual(self.judge(goal, [("BM_A", 1, 1, {"rate": 750.0})])["verdict"], "floor")
        self.assertEqual(self.judge(goal, [("BM_A", 1, 1, {"rate": 650.0})])["verdict"], "unmet")
        self.assertEqual(self.judge(goal, [("BM_A", 1, 1, {"rate": 1e4})])["verdict"], "met")

    def test_a_speed_counts_only_beside_its_accuracy(self):
        goal = {"workload": "w", "unit": "steps/s", "at_least": 1000,
                "measure": {"rate": "BM_A"},
                "beside": [{"label": "error", "counter": "match", "at_most": 0.01,
                            "percent": True}, {"label": "its", "counter": "iterations"}]}
        right = self.judge(goal, [("BM_A", 0.5, 0.5, {"match": 0.001, "iterations": 4.0})])
        self.assertEqual(right["verdict"], "met")
        self.assertEqual(right["beside"][0]["shown"], "0.1%")
        self.assertEqual(right["beside"][1]["within"], None)
        wrong = self.judge(goal, [("BM_A", 0.5, 0.5, {"match": 0.05, "iterations": 4.0})])
        self.assertEqual(wrong["verdict"], "unmet")
        self.assertFalse(wrong["beside"][0]["within"])
        unknown = self.judge(goal, [("BM_A", 0.5, 0.5, {"iterations": 4.0})])
        self.assertEqual(unknown["verdict"], "no data")
        self.assertEqual(unknown["missing"], ["BM_A (match)"])

    def test_a_ratio_reads_the_clock_it_names(self):
        goal = {"workload": "w", "unit": "x", "at_least": 1.8,
                "measure": {"ratio": ["BM_1", "BM_2"], "clock": "real"}}
        # Two threads: the same CPU time on the main thread, half the wall time.
        specs = [("BM_1", 10.0, 10.0, {}), ("BM_2", 9.0, 5.0, {})]
        result = self.judge(goal, specs)
        self.assertAlmostEqual(result["value"], 2.0)
        self.assertEqual(result["verdict"], "met")
        goal["measure"]["clock"] = "cpu"
        self.assertEqual(self.judge(goal, specs)["verdict"], "unmet")

    def test_an_exponent_is_fitted_on_the_tets_the_run_reports(self):
        goal = {"workload": "w", "unit": "exponent", "at_most": 1.15,
                "measure": {"exponent": "BM_S/{mesh}", "meshes": list(support.MESHES)}}
        specs = []
        for mesh, (_, _, tets) in support.MESHES.items():
            specs.append((f"BM_S/{mesh}", 1e-4 * tets ** 1.3, 1.0, {"tets": tets}))
        result = self.judge(goal, specs)
        self.assertAlmostEqual(result["value"], 1.3, places=6)
        self.assertEqual(result["verdict"], "unmet")
        missing = self.judge(goal, specs[:2])
        self.assertEqual(missing["verdict"], "no data")
        self.assertEqual(missing["missing"], ["BM_S/liver_x16.msh"])

    def bad_goals(self, goals, named):
        folder = tempfile.mkdtemp(prefix="goals-")
        self.addCleanup(shutil.rmtree, folder)
        path = os.path.join(folder, "goals.json")
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(goals if isinstance(goals, str) else json.dumps({"goals": goals}))
        with self.assertRaises(goals_module.GoalsError) as caught:
            goals_module.load_goals(path)
        self.assertIn(path, str(caught.exception))
        self.assertIn(named, str(caught.exception))

    def test_a_bad_goals_file_is_named_with_its_key(self):
        good = {"workload": "w", "unit": "u", "at_least": 1, "measure": {"rate": "BM_A"}}
        self.bad_goals("{", "not JSON")
        self.bad_goals([], "\"goals\"")
        self.bad_goals([dict(good, at_most=2)], "goals[0]: give exactly one")
        self.bad_goals([{k: v for k, v in good.items() if k != "at_least"}], "goals[0]")
        self.bad_goals([dict(good, floor=2)], "goals[0].floor")
        self.bad_goals([good, dict(good, measure={"speed": "BM_A"})], "goals[1].measure")
        self.bad_goals([dict(good, measure={"exponent": "BM_A", "meshes": ["liver.msh"]})],
                       "goals[0].measure.exponent")
        self.bad_goals([dict(good, measure={"ratio": ["BM_A", "BM_B"]},
                             beside=[{"label": "l", "counter": "c"}])],
                       "goals[0].beside[0].of")

    def test_the_table_is_markdown_on_stdout_and_no_page(self):
        with tempfile.TemporaryDirectory(prefix="dashboard-goals-") as folder:
            path = support.write(os.path.join(folder, "run.json"), support.make_run(NEW_DATE))
            out = os.path.join(folder, "page")
            result = support.run_tool(support.DASHBOARD, path, "--goals", "--out", out)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertIn("| workload | measured | goal | beside | verdict |", result.stdout)
            self.assertRegex(result.stdout, r"\n\d+ of \d+ goals met\.\n$")
            self.assertFalse(os.path.exists(out))

    def test_two_runs_give_before_and_after(self):
        fem = "BM_FemStep/cg/liver.msh/threads:1/iterations:120/real_time"
        with tempfile.TemporaryDirectory(prefix="dashboard-goals-") as folder:
            old = support.write(os.path.join(folder, "old.json"), support.make_run(OLD_DATE))
            new = support.write(os.path.join(folder, "new.json"), support.make_run(
                NEW_DATE, factor=injected({fem: 0.5}), noise=0.0))
            result = support.run_tool(support.DASHBOARD, new, old, "--goals")
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertIn("| workload | before | after | goal |", result.stdout)
            row = next(line for line in result.stdout.splitlines()
                       if line.startswith("| corotational_fem step, liver, one core"))
            before, after = (float(cell.split()[0].replace(",", ""))
                             for cell in row.split("|")[2:4])
            self.assertAlmostEqual(after / before, 2.0, delta=0.05)
            out = os.path.join(folder, "page")
            self.assertEqual(support.run_tool(support.DASHBOARD, old, new, "--out",
                                              out).returncode, 0)
            with open(os.path.join(out, "index.html"), encoding="utf-8") as handle:
                self.assertIn("run before -&gt; newest", handle.read())

    def test_the_page_has_a_row_a_goal(self):
        with tempfile.TemporaryDirectory(prefix="dashboard-goals-") as folder:
            path = support.write(os.path.join(folder, "run.json"), support.make_run(NEW_DATE))
            out = os.path.join(folder, "page")
            result = support.run_tool(support.DASHBOARD, path, "--out", out)
            self.assertEqual(result.returncode, 0, result.stderr)
            with open(os.path.join(out, "index.html"), encoding="utf-8") as handle:
                page = handle.read()
            table = re.search(r'<table class="goals" id="goals">(.*?)</table>', page, re.S)
            self.assertIsNotNone(table)
            rows = re.findall(r'<tr class="(met|floor|unmet|no-data)">', table.group(1))
            self.assertEqual(len(rows), len(goals_module.load_goals()))
            self.assertIn("no-data", rows)


if __name__ == "__main__":
    unittest.main()
