#!/usr/bin/env python3
"""Compares the GPU sweep's images (run.sh): GPU against CPU reference geometry per pixel, and the light transport
images' finiteness and means (method / GPU path tracer, GPU / CPU path tracer). Standard library only."""
import math, os, re, struct, sys

O, CAMS = sys.argv[1], sys.argv[2]


def pfm(p):
    d = open(p, "rb").read()
    a, b, c, rest = d.split(b"\n", 3)
    w, h = map(int, b.split())
    ch = 3 if a == b"PF" else 1
    v = struct.unpack(("<" if float(c) < 0 else ">") + "%df" % (w * h * ch), rest[: w * h * ch * 4])
    return w, h, ch, v


def ppm(p):
    d = open(p, "rb").read()
    m = re.match(rb"P6\s+(\d+)\s+(\d+)\s+(\d+)\s", d)
    w, h = int(m.group(1)), int(m.group(2))
    px = d[m.end():]
    return [px[3 * i:3 * i + 3] for i in range(w * h)]


def px(v, ch, i):
    return tuple(v[i * ch:(i + 1) * ch])


def geo(n, view, m2):
    _, _, _, dg = pfm(f"{O}/{n}_{view}_depth_gpu.pfm")
    _, _, _, dc = pfm(f"{O}/{n}_{view}_depth_cpu.pfm")
    if m2 == "normal":
        _, _, _, ng = pfm(f"{O}/{n}_{view}_normal_gpu.pfm")
        _, _, _, nc = pfm(f"{O}/{n}_{view}_normal_cpu.pfm")
        # a normal within 1e-6 a component is the same (NVIDIA's normalize of a scaled axis gives
        # 0.99999994 where lavapipe and the CPU give 1)
        sg = lambda i: tuple(round(x * 1e6) for x in px(ng, 3, i)) if all(map(math.isfinite, px(ng, 3, i))) else px(ng, 3, i)
        sc = lambda i: tuple(round(x * 1e6) for x in px(nc, 3, i)) if all(map(math.isfinite, px(nc, 3, i))) else px(nc, 3, i)
    else:
        ig, ic = ppm(f"{O}/{n}_{view}_instance_gpu.ppm"), ppm(f"{O}/{n}_{view}_instance_cpu.ppm")
        sg = lambda i: ig[i]
        sc = lambda i: ic[i]
    hits = hm = dep = sec = 0
    for i in range(len(dg)):
        a, b = dg[i], dc[i]
        ha, hb = math.isfinite(a), math.isfinite(b)
        hits += hb
        if ha != hb:
            hm += 1
        elif hb:
            if abs(a - b) > 1e-4 * max(abs(b), 1e-3):
                dep += 1
            if sg(i) != sc(i):
                sec += 1
    return hits, hm, dep, sec


def rad(p):
    if not os.path.exists(p):
        return None
    w, h, ch, v = pfm(p)
    bad = sum(1 for x in v if not math.isfinite(x) or x < 0)
    fin = [x for x in v if math.isfinite(x)]
    return bad, sum(fin) / max(len(fin), 1)


geo_tot = {"views": 0, "clean": 0, "le2": 0, "more": []}
ratios = {k: [] for k in ("pt_cpu", "direct_ao", "gi_pt", "gi_cones", "gi_photons")}
bad_tot = []
for line in open(CAMS):
    n, m2, _, _ = line.split()
    row = [n]
    for view in ("def", "obl", "close"):
        try:
            hits, hm, dep, sec = geo(n, view, m2)
        except Exception as e:
            row.append(f"{view}:ERR({e.__class__.__name__})")
            geo_tot["more"].append((n, view, "missing"))
            continue
        d = hm + dep + sec
        geo_tot["views"] += 1
        geo_tot["clean"] += d == 0
        geo_tot["le2"] += 0 < d <= 2
        if d > 2:
            geo_tot["more"].append((n, view, f"hitmiss {hm} depth {dep} {m2} {sec} of {hits} hits"))
        row.append(f"{view}:{d}/{hits}")
    keys = ("pt_gpu", "pt_cpu", "gi_pt", "gi_cones", "gi_photons") + (() if os.environ.get("LITE") else ("direct_ao",))
    r = {k: rad(f"{O}/{n}_{k}.pfm") for k in keys}
    for k, x in r.items():
        if x is None:
            row.append(f"{k}:MISSING")
            bad_tot.append((n, k, "missing"))
        elif x[0]:
            row.append(f"{k}:BAD{x[0]}")
            bad_tot.append((n, k, f"{x[0]} non-finite or negative values"))
    g = r["pt_gpu"]
    if g and g[1] > 0:
        for k in ratios:
            if r.get(k):
                q = r[k][1] / g[1]
                ratios[k].append((q, n))
                row.append(f"{k}/pt={q:.4f}")
    print(" ".join(row))
print()
print(f"geometry: {geo_tot['views']} views, {geo_tot['clean']} identical, {geo_tot['le2']} with 1-2 pixels, "
      f"{len(geo_tot['more'])} with more:")
for x in geo_tot["more"]:
    print("  ", *x)
print(f"non-finite/negative/missing images: {len(bad_tot)}")
for x in bad_tot:
    print("  ", *x)
for k, v in ratios.items():
    v.sort()
    if v:
        print(f"{k} / GPU path tracer mean: min {v[0][0]:.4f} ({v[0][1]}) median {v[len(v)//2][0]:.4f} "
              f"max {v[-1][0]:.4f} ({v[-1][1]}) over {len(v)}")
