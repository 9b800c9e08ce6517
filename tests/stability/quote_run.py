#!/usr/bin/env python3
"""Quotes the last `ctest -L stability` run in docs/stability.md: replaces the text between the
`measured: begin` and `measured: end` markers with the rows and notes the tests wrote into
build/stability/. Usage: quote_run.py [BUILD_DIR] (default: build beside this repository's root)."""
import datetime
import os
import platform
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASES = ["stiff_soft_foot", "mass_ratio", "pd_gains", "long_chain", "closed_loop",
         "deep_penetration", "impact", "rough_floor", "stairs", "straight_knee"]
NOTES = ["false_positives_stand.txt", "false_positives_walk.txt", "cost.txt"]


def cpu():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def system():
    try:
        with open("/etc/os-release") as f:
            for line in f:
                if line.startswith("PRETTY_NAME="):
                    return line.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    return platform.system()


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build")
    rows_dir = os.path.join(build, "stability")
    missing = [c for c in CASES if not os.path.exists(os.path.join(rows_dir, c + ".md"))]
    if missing:
        sys.exit(f"quote_run.py: no rows for {', '.join(missing)} in {rows_dir}; "
                 "run `ctest -L stability` in the build directory first")
    stamp = datetime.datetime.fromtimestamp(
        max(os.path.getmtime(os.path.join(rows_dir, c + ".md")) for c in CASES),
        datetime.timezone.utc).strftime("%Y-%m-%d %H:%M")
    out = [f"Quoted by `tests/stability/quote_run.py` from a run of `ctest -L stability` on {stamp} "
           f"UTC, {system()} on {cpu()} ({os.cpu_count()} cores, shared with other builds: "
           "the wall times vary with the load). Each row is written by its test into "
           "`build/stability/<case>.md`; E is the watch's energy, W the sources' work.", "",
           "| case | setting | simulated | outcome | figure | wall |", "|---|---|---|---|---|---|"]
    for c in CASES:
        with open(os.path.join(rows_dir, c + ".md")) as f:
            out += [line.rstrip("\n") for line in f if line.strip()]
    out.append("")
    for n in NOTES:
        path = os.path.join(rows_dir, n)
        if os.path.exists(path):
            with open(path) as f:
                out.append(f"- {f.read().strip()} (`build/stability/{n}`)")
    doc = os.path.join(ROOT, "docs", "stability.md")
    with open(doc) as f:
        text = f.read()
    begin, end = "<!-- measured: begin -->", "<!-- measured: end -->"
    if begin not in text or end not in text:
        sys.exit(f"quote_run.py: {doc} lacks the {begin} / {end} markers")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    with open(doc, "w") as f:
        f.write(head + begin + "\n" + "\n".join(out) + "\n" + end + tail)
    print(f"quote_run.py: {doc} quotes the run of {stamp} UTC")


if __name__ == "__main__":
    main()
