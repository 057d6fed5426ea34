#!/usr/bin/env python3
"""bench/vox_bench.py - conversion benchmark over the .vox corpus.

For every corpus file and every minimization setting (none, collapse only,
DAG only, both = the default) runs `vox2svo` RUNS times and prints the median
conversion time (whole run of the tool, and the octree build alone), peak
memory and output bytes per voxel, against the input's 4.0 bytes per voxel
(XYZI) measured in the same run. Prints a Markdown table for
docs/PERFORMANCE.md.

usage: bench/vox_bench.py [--bin build/bin] [--corpus ../shared/corpus] [--runs 7]
"""
import argparse
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time

MODES = [
    ("none", ["--no-collapse", "--no-dag"]),
    ("collapse", ["--no-dag"]),
    ("dag", ["--no-collapse"]),
    ("both", []),
]


def machine():
    cpu = "unknown cpu"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}"


def run(bin_dir, src, dst, flags):
    t0 = time.perf_counter()
    out = subprocess.run([os.path.join(bin_dir, "vox2svo"), src, dst] + flags,
                         check=True, capture_output=True, text=True).stdout
    wall = time.perf_counter() - t0
    voxels = int(re.search(r"voxels\s+([\d,]+)", out).group(1).replace(",", ""))
    outb = int(re.search(r"output\s+([\d,]+) bytes", out).group(1).replace(",", ""))
    conv = float(re.search(r"convert ([\d.]+)", out).group(1)) * 1e-3
    peak = re.search(r"peak memory\s+(.*)", out).group(1).strip()
    mem = int(re.search(r"in memory\s+([\d,]+) bytes", out).group(1).replace(",", ""))
    desc = re.search(r"plain ([\d,]+) -> collapsed ([\d,]+) -> dag ([\d,]+)", out).groups()
    return wall, conv, voxels, outb, peak, [int(d.replace(",", "")) for d in desc], mem


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="build/bin")
    ap.add_argument("--corpus", default=os.environ.get("VX_CORPUS_DIR", "../shared/corpus"))
    ap.add_argument("--runs", type=int, default=7)
    a = ap.parse_args()
    vox_dir = os.path.join(a.corpus, "vox")
    files = sorted(f for f in os.listdir(vox_dir) if f.endswith(".vox"))
    print(f"machine: {machine()}")
    print(f"command: bench/vox_bench.py --runs {a.runs}\n")
    print("| file | voxels | input B/voxel | descriptors plain / collapsed / dag | "
          "file B/voxel none | collapse | dag | both | in-memory B/voxel none / both | tool run ms (median) | build ms | peak memory |")
    print("|---|---:|---:|---|---:|---:|---:|---:|---|---:|---:|---:|")
    tot_vox = 0
    tot_out = 0
    tot_in = 0
    with tempfile.TemporaryDirectory() as tmp:
        dst = os.path.join(tmp, "out.svo")
        for f in files:
            src = os.path.join(vox_dir, f)
            row = {}
            for name, flags in MODES:
                runs = [run(a.bin, src, dst, flags) for _ in range(a.runs if name == "both" else 1)]
                row[name] = runs
            both = row["both"]
            voxels = both[0][2]
            in_bytes = os.path.getsize(src)
            bpv = {n: row[n][0][3] / max(voxels, 1) for n, _ in MODES}
            wall = statistics.median(r[0] for r in both) * 1e3
            conv = statistics.median(r[1] for r in both) * 1e3
            d = both[0][5]
            print(f"| {f} | {voxels:,} | {in_bytes / max(voxels, 1):.2f} | {d[0]:,} / {d[1]:,} / {d[2]:,} | "
                  f"{bpv['none']:.3f} | {bpv['collapse']:.3f} | {bpv['dag']:.3f} | **{bpv['both']:.3f}** | "
                  f"{row['none'][0][6] / max(voxels, 1):.2f} / {both[0][6] / max(voxels, 1):.2f} | "
                  f"{wall:.1f} | {conv:.1f} | {both[0][4]} |")
            tot_vox += voxels
            tot_out += both[0][3]
            tot_in += in_bytes
    print(f"\noverall: {tot_vox:,} voxels, output {tot_out:,} bytes = {tot_out / max(tot_vox, 1):.3f} bytes/voxel "
          f"(input .vox files {tot_in / max(tot_vox, 1):.3f} bytes/voxel)")


if __name__ == "__main__":
    sys.exit(main())
