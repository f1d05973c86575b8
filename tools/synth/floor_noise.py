#!/usr/bin/env python3
"""Disparity noise on rendered floors, per texture: negobs against OpenCV.

    floor_noise.py --build BUILD [--textures concrete,worn,...]
                   [--baselines 120,60] [--frames 6] [--work DIR]

Renders a flat walk per texture and baseline with negobs_synth (ground
truth disparity on), runs negobs_png --disparity on it, and OpenCV's
StereoBM (15x15) and StereoSGBM (5x5 blocks) on the same pairs, and
prints per matcher, over the lower 60 % of the rows (the floor the
detector fits) and columns 70 and up (a disparity of 63 px is searched):

  valid       share of floor pixels with a value
  mae         mean absolute error (px)
  bad0.5      share of values wrong by more than 0.5 px
  strip sd    standard deviation of the error of 16-px strip medians,
              one per row (the detector's drop test reads such medians)
  bias        their mean error

A drop of dh at floor distance D shows as a disparity deficit of about
d(D) * dh / H (camera height H); the strip sd says how many of them a
texture leaves visible. Frame 0 is skipped (the walk's first frame has no
motion). Exit 1 when a tool fails, 2 on a bad command line, 77 without
python3-opencv.
"""
import argparse
import os
import sys
import tempfile

from walk_tools import built_tools, int_list, need_opencv, read_disp16, run

PROG = "floor_noise.py"
cv2, np = need_opencv(PROG)

STRIP_PX = 16
FIRST_COL = 70
FLOOR_ROWS_FROM = 0.4


def read16(path):
    return read_disp16(PROG, path).astype(np.float32)


def measure(folder, frames):
    acc = {k: {"abs": [], "strip": [], "valid": []} for k in ("negobs", "bm", "sgbm")}
    sgbm = cv2.StereoSGBM_create(0, 64, 5, P1=8 * 25, P2=32 * 25,
                                 uniquenessRatio=10)
    bm = cv2.StereoBM_create(64, 15)
    for i in range(1, frames):
        left = cv2.imread(os.path.join(folder, "left_%04d.png" % i), cv2.IMREAD_GRAYSCALE)
        right = cv2.imread(os.path.join(folder, "right_%04d.png" % i), cv2.IMREAD_GRAYSCALE)
        if left is None or right is None:
            sys.exit("floor_noise.py: pair %d missing in %s" % (i, folder))
        gt = read16(os.path.join(folder, "disp_%04d.png" % i))
        maps = {
            "negobs": read16(os.path.join(folder, "out", "disp_%04d.png" % i)),
            "bm": bm.compute(left, right).astype(np.float32) / 16.0,
            "sgbm": sgbm.compute(left, right).astype(np.float32) / 16.0,
        }
        h, w = left.shape
        y0 = int(h * FLOOR_ROWS_FROM)
        for name, m in maps.items():
            ok = (m[y0:] > 0) & (gt[y0:] > 0)
            ok[:, :FIRST_COL] = False
            err = m[y0:] - gt[y0:]
            a = acc[name]
            a["abs"].append(np.abs(err[ok]))
            a["valid"].append(ok[:, FIRST_COL:].mean())
            for y in range(err.shape[0]):
                for x in range(FIRST_COL + 10, w - STRIP_PX, STRIP_PX):
                    sel = ok[y, x:x + STRIP_PX]
                    if sel.sum() >= STRIP_PX // 2:
                        a["strip"].append(np.median(err[y, x:x + STRIP_PX][sel]))
    return acc


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True,
                    help="a meson build folder with tools/ built (use a release build)")
    ap.add_argument("--textures", default="asphalt,paving,worn,concrete")
    ap.add_argument("--baselines", default="120,60", help="mm, comma-separated")
    ap.add_argument("--frames", type=int, default=6)
    ap.add_argument("--noise", type=float, default=2.0, help="sensor noise, grey levels")
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--work", help="keep the walks here (default: a temporary folder)")
    args = ap.parse_args()
    if args.frames < 2:
        ap.error("--frames must be at least 2")
    synth, png = built_tools(ap, args.build)
    baselines = int_list(ap, args.baselines, "--baselines")
    work = args.work or tempfile.mkdtemp(prefix="floor_noise_")
    print("texture   B mm  matcher  valid   mae  bad0.5  strip sd  bias (px)")
    for tex in args.textures.split(","):
        for b in baselines:
            d = os.path.join(work, "%s_%d" % (tex, b))
            run(PROG, [synth, "--scene", "flat", "--texture-kind", tex,
                       "--baseline-mm", str(b), "--frames", str(args.frames),
                       "--noise", str(args.noise), "--seed", str(args.seed),
                       "--gt-disparity", "-q", "--out", d])
            run(PROG, [png, "--seq", d, "--out", os.path.join(d, "out"),
                       "--disparity", "--json", os.path.join(d, "out.json")])
            for name, a in measure(d, args.frames).items():
                e = np.concatenate(a["abs"])
                s = np.array(a["strip"])
                print("%-9s %4d  %-7s %5.2f %5.3f  %6.3f  %8.3f  %+.3f" %
                      (tex, b, name, np.mean(a["valid"]), e.mean(), (e > 0.5).mean(),
                       s.std(), s.mean()))
    if not args.work:
        print("(walks in %s)" % work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
