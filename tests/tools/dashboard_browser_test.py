#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The dashboard page in a real headless browser (Debian's chromium): every chart present with
an SVG the browser laid out at a real size and paths it drew, the comparison's regression row
rendered, and a screenshot that is not blank.

Usage: dashboard_browser_test.py
  SOFTBENCH_BROWSER      the browser to use (default: the first of chromium, chromium-browser,
                         google-chrome on the PATH)
  SOFTBENCH_TEST_OUTPUT  a folder to keep the page and screenshot in (ctest sets it to the
                         test's build folder); otherwise they go with the temporary folder
Exit status 77 (ctest: skipped) when no browser is installed or this python lacks matplotlib."""

import html
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

sys.dont_write_bytecode = True  # keep the source tree free of __pycache__
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import dashboard_support as support  # noqa: E402

support.require_modules("matplotlib", "scipy")


def find_browser():
    wanted = os.environ.get("SOFTBENCH_BROWSER")
    if wanted:
        return shutil.which(wanted)
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        if shutil.which(name):
            return shutil.which(name)
    return None


BROWSER = find_browser()
if BROWSER is None:
    print("SKIP: no headless browser (install Debian's chromium, or set SOFTBENCH_BROWSER)")
    sys.exit(support.SKIP)

WIDTH, HEIGHT = 1280, 3600
SLOW = "BM_Step/shape_matching/liver.msh/iterations:120/real_time"

# Appended to a copy of the page (never to the page itself, which has no script): what the
# browser made of each chart, written into the DOM that --dump-dom prints.
MEASURE = """
<script>
const charts = [];
for (const figure of document.querySelectorAll('figure.chart')) {
  const svg = figure.querySelector('svg');
  const box = svg ? svg.getBoundingClientRect() : {width: 0, height: 0};
  let drawn = 0;
  for (const path of figure.querySelectorAll('svg path')) {
    if (path.closest('defs')) continue;
    const extent = path.getBBox();
    if (extent.width > 0 || extent.height > 0) drawn += 1;
  }
  charts.push({id: figure.id, svg: !!svg, width: box.width, height: box.height, drawn: drawn,
               noData: !!figure.querySelector('.no-data')});
}
const regressions = [...document.querySelectorAll('#comparison tr.regression td.name')]
    .map(cell => cell.textContent);
const result = document.createElement('pre');
result.id = 'measurements';
result.textContent = JSON.stringify({charts: charts, regressions: regressions});
document.body.appendChild(result);
</script>
"""


def browser(profile, *arguments):
    command = [BROWSER, "--headless", "--disable-gpu", "--no-sandbox", "--hide-scrollbars",
               "--no-first-run", "--disable-extensions", f"--user-data-dir={profile}",
               *arguments]
    return subprocess.run(command, capture_output=True, text=True, timeout=180, check=False)


def png_size(path):
    with open(path, "rb") as handle:
        header = handle.read(24)
    if header[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    return int.from_bytes(header[16:20], "big"), int.from_bytes(header[20:24], "big")


class BrowserTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.temporary = tempfile.TemporaryDirectory(prefix="dashboard-browser-")
        folder = cls.temporary.name
        cls.keep = os.environ.get("SOFTBENCH_TEST_OUTPUT") or folder
        os.makedirs(cls.keep, exist_ok=True)
        old = support.write(os.path.join(folder, "old.json"),
                            support.make_run("2026-11-20T10:00:00+00:00", seed=1))
        new = support.write(os.path.join(folder, "new.json"), support.make_run(
            "2026-11-21T10:00:00+00:00", revision="def5678", seed=2,
            factor=lambda name: 2.0 if name == SLOW else 1.0))
        cls.page_folder = os.path.join(cls.keep, "page")
        result = support.run_tool(support.DASHBOARD, old, new, "--out", cls.page_folder)
        if result.returncode != 0:
            raise AssertionError(f"tools/dashboard failed: {result.stderr}")
        cls.page = os.path.join(cls.page_folder, "index.html")
        cls.profile = os.path.join(folder, "profile")

    @classmethod
    def tearDownClass(cls):
        cls.temporary.cleanup()

    def test_every_chart_is_drawn_in_the_browser(self):
        with open(self.page, encoding="utf-8") as handle:
            text = handle.read()
        measured = os.path.join(self.temporary.name, "measured.html")
        with open(measured, "w", encoding="utf-8") as handle:
            handle.write(text.replace("</body>", MEASURE + "</body>"))
        result = browser(self.profile, "--dump-dom", "file://" + measured)
        self.assertEqual(result.returncode, 0, result.stderr[-2000:])
        found = re.search(r'<pre id="measurements">(.*?)</pre>', result.stdout, re.S)
        self.assertIsNotNone(found, "the browser ran no script: " + result.stdout[:500])
        report = json.loads(html.unescape(found.group(1)))
        charts = {chart["id"]: chart for chart in report["charts"]}
        for chart_id in ("steps-per-model", "cost-vs-size", "tri-tri-ns-per-pair",
                         "bvh-frame-time"):
            self.assertIn(chart_id, charts)
        self.assertTrue(any(i.startswith("history-") for i in charts))
        for chart in charts.values():
            self.assertTrue(chart["svg"], chart)
            self.assertFalse(chart["noData"], chart)
            self.assertGreater(chart["width"], 200, chart)
            self.assertGreater(chart["height"], 100, chart)
            self.assertGreater(chart["drawn"], 10, chart)
        self.assertEqual(report["regressions"], [SLOW])

    def test_the_screenshot_is_the_page_not_a_blank(self):
        screenshot = os.path.join(self.keep, "dashboard.png")
        if os.path.exists(screenshot):
            os.unlink(screenshot)
        result = browser(self.profile, f"--window-size={WIDTH},{HEIGHT}",
                         f"--screenshot={screenshot}", "file://" + self.page)
        self.assertEqual(result.returncode, 0, result.stderr[-2000:])
        self.assertEqual(png_size(screenshot), (WIDTH, HEIGHT))
        import matplotlib.image

        pixels = matplotlib.image.imread(screenshot)[:, :, :3]
        inked = (pixels.min(axis=2) < 0.9).mean()
        # Charts, tables and text cover a good part of a page this long; a blank or an
        # error page inks almost nothing.
        self.assertGreater(inked, 0.03)
        colours = {tuple(p) for p in (pixels[::7, ::7] * 8).astype(int).reshape(-1, 3)}
        self.assertGreater(len(colours), 20)  # the charts' palette, not text alone
        print(f"screenshot: {screenshot}")


if __name__ == "__main__":
    unittest.main()
