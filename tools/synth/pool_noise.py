#!/usr/bin/env python3
"""What pooling frames would buy: the disparity error of one floor patch
seen once, against its mean over N consecutive frames.

    pool_noise.py --build BUILD [--textures concrete,worn,...]
                  [--baselines 120,60] [--frames 24] [--work DIR]

Renders a flat walk per texture and baseline with negobs_synth (ground
truth disparity on, 1.2 m / 20 deg camera, 1.2 m/s, 10 fps, noise 2, blur
0.5, bobbing and sway), runs negobs_png --disparity on it, and follows
fixed floor patches through the walk: cells 40 mm along the walk by 160 mm
across, placed with each frame's true pose (gt.json), so the alignment is
exact and the figures are an upper bound of what a device that measures
its own travel can pool. Per cell and frame the error is the median of
(negobs - truth) over the cell's pixels (at least 8), like the strip
medians the detector's drop test reads. Printed per floor band (1-2, 2-3,
3-4 m ahead; a mean over frames counts in the band of its last frame):

  sd1       standard deviation of one frame's cell errors (px; errors
            clipped to +-2 px like the detector's histograms)
  corr      correlation of a cell's error in two consecutive frames
            (0: independent frames, each adds information)
  sdN       standard deviation of a cell's mean over N consecutive
            frames it was seen in (N = 2, 4, 8); 1/sqrt(N) of sd1 when
            the frames are independent

A minimum drop of h at floor distance D shows as a deficit of about
d(D) * h / (H + h); the detector needs it above about 3 sd. Exit 1 when a
tool fails, 2 on a bad command line, 77 without python3-opencv.
"""
import argparse
import json
import os
import sys
import tempfile

from walk_tools import built_tools, int_list, need_opencv, read_disp16, run

PROG = "pool_noise.py"
cv2, np = need_opencv(PROG)

CELL_ALONG_MM = 40
CELL_ACROSS_MM = 160
CELL_MIN_PX = 8
CLIP_PX = 2.0
BANDS_MM = ((1000, 2000), (2000, 3000), (3000, 4000))
POOLS = (2, 4, 8)


def floor_coords(cam, fr, gt):
    """Floor distance along the walk and across it (mm) of every pixel,
    from the true disparity and the frame's true pitch and roll."""
    h, w = gt.shape
    uu, vv = np.meshgrid(np.arange(w), np.arange(h))
    z = cam["f"] * cam["B_mm"] / np.where(gt > 0, gt, 1.0)
    xc = (uu - cam["cx"]) * z / cam["f"]
    yc = (vv - cam["cy"]) * z / cam["f"]
    p = np.radians(fr["pitch"])
    r = np.radians(fr["roll"])
    x1 = xc * np.cos(r) - yc * np.sin(r)
    y1 = xc * np.sin(r) + yc * np.cos(r)
    fwd = z * np.cos(p) - y1 * np.sin(p)
    return fwd, fwd + fr["cam_z_mm"], x1 + fr.get("cam_x_mm", 0.0)


def cell_errors(folder):
    """{cell: [(frame, error px, floor distance mm)]} over the walk."""
    g = json.load(open(os.path.join(folder, "gt.json")))
    cam = g["camera"]
    cells = {}
    for fr in g["frames"]:
        i = fr["i"]
        gt = read_disp16(PROG, os.path.join(folder, fr["disparity"]))
        me = read_disp16(PROG, os.path.join(folder, "out", "disp_%04d.png" % i))
        fwd, along, across = floor_coords(cam, fr, gt)
        ok = (gt > 0.5) & (me > 0) & (fwd >= BANDS_MM[0][0]) & (fwd < BANDS_MM[-1][1])
        key = (np.floor(along[ok] / CELL_ALONG_MM).astype(np.int64) * 100000 +
               np.floor(across[ok] / CELL_ACROSS_MM).astype(np.int64))
        order = np.argsort(key, kind="stable")
        ks = key[order]
        err = np.clip((me - gt)[ok][order], -CLIP_PX, CLIP_PX)
        dist = fwd[ok][order]
        cuts = np.flatnonzero(np.diff(ks)) + 1
        for a, b in zip(np.r_[0, cuts], np.r_[cuts, len(ks)]):
            if b - a >= CELL_MIN_PX:
                cells.setdefault(int(ks[a]), []).append(
                    (i, float(np.median(err[a:b])), float(np.mean(dist[a:b]))))
    return cells


def band_figures(cells, lo, hi):
    one = [e for seen in cells.values() for (_, e, d) in seen if lo <= d < hi]
    pairs = [(seen[k][1], seen[k + 1][1]) for seen in cells.values()
             for k in range(len(seen) - 1)
             if seen[k + 1][0] == seen[k][0] + 1 and lo <= seen[k][2] < hi]
    out = {"n": len(one), "sd1": float(np.std(one)) if one else float("nan"),
           "corr": float(np.corrcoef(np.array(pairs).T)[0, 1])
           if len(pairs) > 10 else float("nan")}
    for n in POOLS:
        means = []
        for seen in cells.values():
            for k in range(0, len(seen) - n + 1, n):
                grp = seen[k:k + n]
                if grp[-1][0] - grp[0][0] == n - 1 and lo <= grp[-1][2] < hi:
                    means.append(np.mean([e for _, e, _ in grp]))
        out["sd%d" % n] = float(np.std(means)) if len(means) > 10 else float("nan")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True, help="meson build directory")
    ap.add_argument("--textures", default="asphalt,worn,concrete")
    ap.add_argument("--baselines", default="120,60")
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--work", help="keep the rendered walks here")
    a = ap.parse_args()
    if a.frames < 2 * max(POOLS):
        ap.error("--frames must be at least %d" % (2 * max(POOLS)))
    synth, png = built_tools(ap, a.build)
    baselines = int_list(ap, a.baselines, "--baselines")
    work = a.work or tempfile.mkdtemp(prefix="pool_noise.")
    print("%-9s %4s %9s %6s %6s %5s %6s %6s %6s" %
          ("texture", "B", "band m", "cells", "sd1", "corr", "sd2", "sd4", "sd8"))
    for tex in a.textures.split(","):
        for b in baselines:
            folder = os.path.join(work, "%s_B%d" % (tex, b))
            run(PROG, [synth, "--out", folder, "--scene", "flat",
                       "--texture-kind", tex, "--baseline-mm", str(b),
                       "--frames", str(a.frames), "--noise", "2", "--blur", "0.5",
                       "--seed", str(a.seed), "--gt-disparity"])
            run(PROG, [png, "--seq", folder, "--out", os.path.join(folder, "out"),
                       "--disparity", "--no-overlay", "-q"])
            cells = cell_errors(folder)
            for lo, hi in BANDS_MM:
                f = band_figures(cells, lo, hi)
                print("%-9s %4d %4.0f-%-4.0f %6d %6.3f %5.2f %6.3f %6.3f %6.3f" %
                      (tex, b, lo / 1000, hi / 1000, f["n"], f["sd1"], f["corr"],
                       f["sd2"], f["sd4"], f["sd8"]))
            sys.stdout.flush()
    if not a.work:
        print("(walks in %s)" % work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
