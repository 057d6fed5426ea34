#!/usr/bin/env python3
"""bench/gi_plot.py - the GI comparison's table and plot from gi_bench's CSV.

    python3 bench/gi_plot.py gi_table.csv OUTDIR

Writes OUTDIR/gi_table.md (one markdown table: the reference's own noise and
every row) and, with matplotlib (python3-matplotlib), OUTDIR/gi_error.png and
OUTDIR/gi_error.svg: one column per scene; rows: relMSE of the full image and
of the indirect light against render time (log-log, one line per method and
setting over its samples per pixel, the reference's noise dashed), and the
full image's relMSE against build (bake) time for the methods that have one.
Without matplotlib only the table is written. A new method needs nothing
here: lines are drawn per (method, setting) found in the CSV."""
import csv
import os
import sys
from collections import OrderedDict


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("probes", "spp", "width", "height", "nonfinite"):
            r[k] = int(r.get(k) or 0)
        for k in ("build_s", "full_ms", "indirect_ms", "relmse_full", "relmse_indirect"):
            r[k] = float(r[k])
    return rows


def scenes_of(rows):
    return list(OrderedDict((r["scene"], None) for r in rows))


def write_md(rows, path):
    r0 = rows[0]
    refs = [r for r in rows if r["method"] == "reference"]
    out = [
        "GI methods against a path-traced reference; %s, %dx%d; reference: the mean of two "
        "path-traced images of %d spp (seeds 999 and 1000); relMSE over the pixels that hit; "
        "render ms: GPU timestamps, median; build s: probe bake, wall clock." %
        (r0["device"], r0["width"], r0["height"], refs[0]["spp"] if refs else 0),
        "",
        "| scene | method | setting | probes | spp | build s | full ms | indirect ms | relMSE full | relMSE indirect |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for r in rows:
        ref = r["method"] == "reference"
        out.append("| %s | %s | %s | %s | %d | %s | %.3g | %.3g | %.3g | %.3g |" % (
            r["scene"], "reference noise (seed A vs B)" if ref else r["method"], r["setting"],
            r["probes"] or "", r["spp"], "%.2f" % r["build_s"] if r["build_s"] > 0 else "",
            r["full_ms"], r["indirect_ms"], r["relmse_full"], r["relmse_indirect"]))
    bad = [r for r in rows if r["nonfinite"]]
    if bad:
        out.append("")
        out.append("Non-finite pixels (relMSE nan): " + "; ".join(
            "%s %s %s %d spp: %d" % (r["scene"], r["method"], r["setting"], r["spp"], r["nonfinite"])
            for r in bad) + ".")
    out.append("")
    with open(path, "w") as f:
        f.write("\n".join(out))


def plot(rows, outdir):
    import matplotlib
    import matplotlib.ticker
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = scenes_of(rows)
    methods = list(OrderedDict((r["method"], None) for r in rows if r["method"] != "reference"))
    cmap = plt.get_cmap("tab10")
    colour = {m: cmap(i % 10) for i, m in enumerate(methods)}
    markers = "o^sDv<>p*h"
    fig, axes = plt.subplots(3, len(scenes), figsize=(4.2 * len(scenes), 10.5), squeeze=False)
    r0 = rows[0]
    fig.suptitle("GI error against time, %s, %dx%d" % (r0["device"], r0["width"], r0["height"]))
    for c, scene in enumerate(scenes):
        sr = [r for r in rows if r["scene"] == scene]
        ref = next((r for r in sr if r["method"] == "reference"), None)
        for row, (key, tkey, label) in enumerate((("relmse_full", "full_ms", "full image"),
                                                  ("relmse_indirect", "indirect_ms", "indirect light"))):
            ax = axes[row][c]
            for m in methods:
                settings = list(OrderedDict((r["setting"], None) for r in sr if r["method"] == m))
                for k, s in enumerate(settings):
                    pts = sorted((r[tkey], r[key], r["spp"]) for r in sr if r["method"] == m and r["setting"] == s)
                    pts = [p for p in pts if p[0] > 0 and p[1] > 0]
                    if not pts:
                        continue
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=markers[k % len(markers)],
                            color=colour[m], ms=4, lw=1.2, label=m if s == "-" else "%s %s" % (m, s))
                    ax.annotate(str(pts[-1][2]), (pts[-1][0], pts[-1][1]), fontsize=6, color=colour[m],
                                xytext=(3, 0), textcoords="offset points")
            if ref and ref[key] > 0:
                ax.axhline(ref[key], color="grey", ls="--", lw=1, label="reference noise")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("render ms (GPU)")
            ax.set_ylabel("relMSE, %s" % label)
            ax.set_title("%s: %s" % (scene, label), fontsize=10)
            ax.grid(True, which="both", alpha=0.25)
        ax = axes[2][c]
        built = [r for r in sr if r["build_s"] > 0 and r["relmse_full"] > 0]  # nan compares false
        for m in methods:
            mr = [r for r in built if r["method"] == m]
            best = OrderedDict()
            for r in mr:  # per setting, the row with the most samples per pixel
                if r["setting"] not in best or r["spp"] > best[r["setting"]]["spp"]:
                    best[r["setting"]] = r
            if best:
                b = sorted(best.values(), key=lambda r: r["build_s"])
                ax.plot([r["build_s"] for r in b], [r["relmse_full"] for r in b], marker="o", color=colour[m],
                        ms=4, lw=1.2, label="%s (%d spp)" % (m, max(r["spp"] for r in b)))
                for r in b:
                    ax.annotate("%s, %d probes" % (r["setting"], r["probes"]), (r["build_s"], r["relmse_full"]),
                                fontsize=6, color=colour[m], xytext=(3, 2), textcoords="offset points")
        if ref and ref["relmse_full"] > 0:
            ax.axhline(ref["relmse_full"], color="grey", ls="--", lw=1, label="reference noise")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ticks = sorted(set(round(r["build_s"], 2) for r in built))
        if ticks:  # the bake times themselves as ticks (they often span less than a decade)
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_xticks(ticks, ["%.2g" % t for t in ticks], fontsize=7)
        ax.set_xlabel("build (bake) s")
        ax.set_ylabel("relMSE, full image")
        ax.set_title("%s: error against build time" % scene, fontsize=10)
        ax.grid(True, which="both", alpha=0.25)
        if built:
            ax.legend(fontsize=6, loc="best")
    # one legend for the render-time panels: every (method, setting) of any scene
    seen = OrderedDict()
    for ax in list(axes[0]) + list(axes[1]):
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab.startswith("reference noise"):
                lab = "reference noise (seed A vs B)"
            seen.setdefault(lab, h)
    fig.legend(list(seen.values()), list(seen.keys()), loc="lower center", ncol=min(6, len(seen)), fontsize=7)
    for ax in axes.flat:  # an empty panel cannot be log-scaled
        if not ax.lines:
            ax.set_xscale("linear")
            ax.set_yscale("linear")
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(outdir, "gi_error." + ext), dpi=110)


def main():
    if len(sys.argv) != 3:
        print("usage: gi_plot.py gi_table.csv OUTDIR", file=sys.stderr)
        return 2
    rows = load(sys.argv[1])
    if not rows:
        print("gi_plot.py: %s has no rows" % sys.argv[1], file=sys.stderr)
        return 1
    write_md(rows, os.path.join(sys.argv[2], "gi_table.md"))
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        print("gi_plot.py: no matplotlib (apt-get install python3-matplotlib): wrote the table only",
              file=sys.stderr)
        return 0
    plot(rows, sys.argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main())
