#!/usr/bin/env python3
"""Compile a build tree's objects with and without their precompiled header; print CPU seconds.

    scripts/pch-ab.py BUILD_DIR REGEX [--jobs N]

Reads BUILD_DIR/compile_commands.json, keeps the sources whose path matches REGEX and that use
a precompiled header (GCC's `-include …/cmake_pch.hxx`, clang's `-Xclang -include-pch …`),
and compiles each twice to /dev/null: once as CMake wrote the command ("with"), once with the
header's flags removed ("without"), N at a time (default 2, CI's cores). The figures of
docs/DESIGN.md's build decisions came from
    scripts/pch-ab.py build/ci 'src/illum/(render|bake|scene)/[^/]+\\.cpp$'
    scripts/pch-ab.py build/asan 'src/illum/(render|bake|scene)/[^/]+\\.cpp$'
The header itself must be built already (build the tree first). ccache is bypassed.
"""
import argparse
import json
import os
import re
import resource
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

GCC_PCH = re.compile(r" -Winvalid-pch -include \S+")
CLANG_PCH = re.compile(r" -Xclang -include-pch -Xclang \S+ -Xclang -include -Xclang \S+")


def die(message):
    print(f"pch-ab: {message}", file=sys.stderr)
    sys.exit(2)


def commands(build_dir, pattern):
    with open(os.path.join(build_dir, "compile_commands.json")) as f:
        entries = json.load(f)
    out = []
    for e in entries:
        if not re.search(pattern, e["file"]) or "cmake_pch" in e["file"]:
            continue
        cmd = re.sub(r" -o \S+", " -o /dev/null", e["command"])
        cmd = re.sub(r"^\S*ccache ", "", cmd)
        without = CLANG_PCH.sub("", GCC_PCH.sub("", cmd))
        if without != cmd:
            out.append((e["directory"], cmd, without))
    return out


def run_all(jobs, items):
    def one(item):
        directory, cmd = item
        r = subprocess.run(cmd, shell=True, cwd=directory, capture_output=True, text=True)
        if r.returncode != 0:
            die(f"compiling {cmd.split()[-1]} failed: {r.stderr.strip().splitlines()[:1]}")

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    with ThreadPoolExecutor(jobs) as pool:
        list(pool.map(one, items))
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime - before.ru_utime, time.monotonic() - start


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("build_dir")
    p.add_argument("regex")
    p.add_argument("--jobs", type=int, default=2)
    a = p.parse_args()
    if a.jobs < 1:
        die("--jobs must be at least 1")
    try:
        cmds = commands(a.build_dir, a.regex)
    except (OSError, ValueError, re.error) as err:
        die(f"cannot use {a.build_dir}/compile_commands.json with {a.regex!r}: {err}")
    if not cmds:
        die(f"no object matching {a.regex!r} uses a precompiled header")
    for label, index in (("without", 2), ("with", 1)):
        cpu, wall = run_all(a.jobs, [(c[0], c[index]) for c in cmds])
        print(f"{label:8s} header: {len(cmds)} objects, {cpu:7.1f} s CPU, {wall:6.1f} s wall")


if __name__ == "__main__":
    main()
