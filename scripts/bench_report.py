#!/usr/bin/python3
"""How long `pxh report` takes on a results folder: the whole command (tables, data, figures in
PNG, SVG and PDF), timed REPEATS times, each on a fresh copy of the folder (a report replaces
only its own files, so every repeat does the whole work). Prints the median, the fastest and
slowest repeat and the machine it ran on; with --against OTHER_PXH, the same for another pxh
binary in the same run, interleaved (A B A B ...) so a busy spell hits both alike, and the ratio
of the medians. With --plot-jobs N the figures are drawn by N processes (PXH_PLOT_JOBS; the
default is one per core).

    /usr/bin/python3 scripts/bench_report.py build/pxh results/runs/default [--repeats 5]
        [--against OLD/pxh] [--plot-jobs 1]
"""
import argparse
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time


def cpu_model():
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def time_once(pxh, results, env):
    with tempfile.TemporaryDirectory(prefix="pxh_bench_report_") as tmp:
        copy = os.path.join(tmp, "run")
        shutil.copytree(results, copy, ignore=shutil.ignore_patterns("report"))
        t0 = time.perf_counter()
        p = subprocess.run([pxh, "report", copy], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, env=env, check=False)
        secs = time.perf_counter() - t0
        if p.returncode != 0:
            sys.exit(f"bench_report: {pxh} report {copy} failed ({p.returncode}): "
                     + p.stderr.decode(errors="replace").strip().splitlines()[-1])
        return secs


def summary(name, times):
    return (f"{name}: median {statistics.median(times):.2f} s, fastest {min(times):.2f} s, "
            f"slowest {max(times):.2f} s over {len(times)} repeats")


def main():
    ap = argparse.ArgumentParser(prog="bench_report.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("pxh", help="the pxh binary to time")
    ap.add_argument("results", help="a results folder (with results.csv)")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--against", help="a second pxh binary, timed in the same run")
    ap.add_argument("--plot-jobs", type=int, default=0,
                    help="processes drawing the figures (0: one per core)")
    a = ap.parse_args()
    if not os.path.isfile(os.path.join(a.results, "results.csv")):
        ap.error(f"{a.results}: no results.csv")
    if a.repeats < 1:
        ap.error("--repeats: at least 1")
    env = dict(os.environ)
    if a.plot_jobs:
        env["PXH_PLOT_JOBS"] = str(a.plot_jobs)
    print(f"machine: {cpu_model()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
          f"load average {os.getloadavg()[0]:.2f} at the start")
    binaries = [a.pxh] + ([a.against] if a.against else [])
    times = {b: [] for b in binaries}
    time_once(a.pxh, a.results, env)  # warm-up: page cache, matplotlib's font cache
    for _ in range(a.repeats):
        for b in binaries:
            times[b].append(time_once(b, a.results, env))
    for b in binaries:
        print(summary(b, times[b]))
    if a.against:
        ratio = statistics.median(times[a.pxh]) / statistics.median(times[a.against])
        print(f"ratio of the medians {a.pxh} / {a.against}: {ratio:.2f}")
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
