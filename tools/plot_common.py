"""What every softbench plot script shares: matplotlib without a display, atomic PNG writes
(a viewer never sees a half-written file), and the convention that each script prints the path
of every file it wrote, one per line (softbench reads them)."""

import argparse
import json
import math
import os
import re
import tempfile

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402,F401  (re-exported for the scripts)


def read_input(description, json_name):
    """The command line every script takes (`<json_name> [--out DIR]`): the parsed JSON and the
    output folder (default: the JSON's), created if missing."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument(json_name)
    parser.add_argument("--out", default=None)
    arguments = parser.parse_args()
    path = getattr(arguments, json_name)
    with open(path, encoding="utf-8") as handle:
        data = json.load(handle)
    out = arguments.out or os.path.dirname(os.path.abspath(path))
    os.makedirs(out, exist_ok=True)
    return data, out


def finite_pairs(xs, ys):
    """The (x, y) pairs where both are numbers (null in JSON is NaN: no value)."""
    pairs = [(x, y) for x, y in zip(xs, ys)
             if x is not None and y is not None and math.isfinite(x) and math.isfinite(y)]
    return [p[0] for p in pairs], [p[1] for p in pairs]


def safe_name(name):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)


def save(figure, path):
    """Saves atomically (temporary file + rename) and prints the path."""
    folder = os.path.dirname(os.path.abspath(path))
    handle, temporary = tempfile.mkstemp(suffix=".png", dir=folder)
    os.close(handle)
    try:
        figure.savefig(temporary, dpi=120, format="png")
        umask = os.umask(0)  # mkstemp makes the file private: give it the usual mode
        os.umask(umask)
        os.chmod(temporary, 0o666 & ~umask)
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise
    finally:
        plt.close(figure)
    print(path)
