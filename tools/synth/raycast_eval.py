#!/usr/bin/env python3
"""Score negobs_png on walks of the independent renderer (raycast_walk.py).

Draws `--walks` walks (scene, material, mounting, baseline and camera
mismatch at random from `--draw`), renders them, runs negobs_png told only
f, B and the image centre (no mounting hint; `--hint` gives the generic
1.2 m / 20 deg instead) and prints, per baseline, the figures of issue 21
with its definitions (docs/DETECTION.md 10.1):

* false vouches: frames whose vouched distance exceeds 1.1 x the floor
  distance of a minimum drop (5 cm within 1.5 m, 10 cm beyond) whose edge
  is in view, or CLEAR with one within 1.5 m; counted apart, the same for
  an edge that was in view and has gone below it;
* NO_INFO share; detection of drops >= 10 cm whose edge is in view at
  1.5-3 m (a hazard at CAUTION or IMMINENT whose range is within 30 % of
  the edge's, a held one included); false IMMINENT / CAUTION frames on
  flat and up-step walks; the median clear_to_mm on flat walks;
* false alerts before an edge: frames of drop and stairs walks whose
  edge is still ahead with a hazard at CAUTION or IMMINENT nearer than
  0.7 x the edge's distance (the detection tolerance's other side) less
  AHEAD_SLACK_MM: a phantom before the real drop.

A frame vouches clear_to_mm, and a CLEAR frame at least the warning range
(4 m) or, short-sighted, the near-zone minimum (1.5 m), as the suite
scores it.

usage: raycast_eval.py NEGOBS_PNG WORKDIR [--walks N] [--draw D] [--jobs J]
       [--hint] [--keep]
"""
import argparse
import json
import os
import random
import shutil
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
NEAR_ZONE_MM = 1500.0
WARN_MM = 4000.0
# a hazard matches the edge when its range is within 30 % of the edge's:
# the detector's range error reaches 12 % at p95 on the suite, so this
# only refuses a hazard reported somewhere else
DETECT_TOL = 0.3
# a confirmed edge lost below the view is held, dead-reckoned at the
# detector's hold speed (1.4 m/s), which runs ahead of a slower walker by
# up to about 0.3 m over the last metre: not a phantom
AHEAD_SLACK_MM = 300.0


def draw_walk(rng, k):
    """Parameters of walk k: scene, material, mounting, rig, camera."""
    scene = rng.choice(["flat", "drop", "drop", "stairs", "upstep"])
    drop = {"flat": 0, "drop": rng.choice([50, 100, 150, 200]),
            "stairs": 170, "upstep": 150}[scene]
    return {
        "name": "w%02d_%s_%d" % (k, scene, drop),
        "scene": scene, "drop_mm": drop,
        "edge_mm": round(rng.uniform(4000, 5000)),
        "material": rng.choice(["concrete", "worn", "asphalt", "tiles"]),
        "height_mm": round(rng.uniform(900, 1600)),
        "pitch_deg": round(rng.uniform(8, 40), 1),
        "roll_deg": round(rng.uniform(-8, 8), 1),
        "baseline_mm": rng.choice([60, 120]),
        "gain_right": round(rng.uniform(0.85, 1.15), 3),
        "offset_right": round(rng.uniform(-8, 8), 1),
        "speed": round(rng.uniform(1.0, 1.4), 2),
        "seed": rng.randrange(1, 1 << 30),
    }


def run_walk(png, work, w, hint, keep):
    seq = os.path.join(work, w["name"])
    args = [sys.executable, os.path.join(HERE, "raycast_walk.py"), "--out",
            seq]
    for key in ("scene", "drop_mm", "edge_mm", "material", "height_mm",
                "pitch_deg", "roll_deg", "baseline_mm", "gain_right",
                "offset_right", "speed", "seed"):
        args += ["--" + key.replace("_", "-"), str(w[key])]
    subprocess.run(args, check=True)
    with open(os.path.join(seq, "scene.json")) as fh:
        meta = json.load(fh)
    cam = meta["camera"]
    jsonl = seq + ".jsonl"
    subprocess.run(
        [png, "--seq", seq, "--out", seq + "_out", "--json", jsonl,
         "--no-overlay", "--quiet", "--f", str(cam["f"]), "--baseline-mm",
         str(cam["B_mm"]), "--cx", str(cam["cx"]), "--cy", str(cam["cy"])] +
        (["--height-mm", "1200", "--pitch-deg", "20"] if hint else
         ["--height-mm", "0"]), check=True)
    with open(jsonl) as fh:
        rows = [json.loads(line) for line in fh]
    if not keep:
        shutil.rmtree(seq, ignore_errors=True)
        shutil.rmtree(seq + "_out", ignore_errors=True)
    return w, meta, rows


def vouched(r):
    v = float(r["clear_to_mm"])
    if r["state"] == "CLEAR":
        v = max(v, NEAR_ZONE_MM if r["short_sight"] else WARN_MM)
    return v


def min_drop(dist_mm):
    return 50.0 if dist_mm <= NEAR_ZONE_MM else 100.0


class Fig:
    def __init__(self):
        self.frames = self.noinfo = 0
        self.drop_frames = self.fv = 0
        self.under_frames = self.fv_under = 0
        self.det = [0, 0]
        self.neg_frames = self.imm = self.caut = 0
        self.ahead_frames = self.ahead_false = 0
        self.flat_clear = []
        self.fv_list = []


def score(w, meta, rows, fig):
    negative = w["scene"] in ("drop", "stairs")
    was_in_view = False
    for r, fr in zip(rows, meta["frames"]):
        fig.frames += 1
        fig.noinfo += r["state"] == "NO_INFO"
        edge = fr["edge_range_mm"]
        in_view = fr["edge_in_view"]
        if w["scene"] == "flat":
            fig.flat_clear.append(r["clear_to_mm"])
        if negative and edge is not None and edge > 0 and \
                w["drop_mm"] >= min_drop(edge):
            if in_view:
                fig.drop_frames += 1
                bad = (r["state"] == "CLEAR" and edge <= NEAR_ZONE_MM) or \
                    vouched(r) > 1.1 * edge
                fig.fv += bad
                if bad:
                    fig.fv_list.append((w["name"], r["frame"], edge,
                                        r["state"], r["clear_to_mm"]))
            elif was_in_view:
                fig.under_frames += 1
                bad = vouched(r) > 1.1 * edge
                fig.fv_under += bad
                if bad:
                    fig.fv_list.append((w["name"], r["frame"], edge,
                                        "below view " + r["state"],
                                        r["clear_to_mm"]))
        was_in_view = was_in_view or bool(in_view)
        if negative and edge is not None and edge > 0:
            fig.ahead_frames += 1
            fig.ahead_false += any(
                h["range_mm"] < (1.0 - DETECT_TOL) * edge - AHEAD_SLACK_MM and
                h["level"] != "NONE" for h in r["hazards"])
        if negative and w["drop_mm"] >= 100 and in_view and edge and \
                1500 <= edge <= 3000 and r["frame"] >= 4:
            fig.det[1] += 1
            fig.det[0] += any(
                abs(h["range_mm"] - edge) <= DETECT_TOL * edge and
                h["level"] != "NONE" for h in r["hazards"])
        if w["scene"] in ("flat", "upstep"):
            fig.neg_frames += 1
            fig.imm += r["level"] == "IMMINENT"
            fig.caut += r["level"] == "CAUTION"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("png")
    ap.add_argument("work")
    ap.add_argument("--walks", type=int, default=20)
    ap.add_argument("--draw", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--hint", action="store_true")
    ap.add_argument("--keep", action="store_true")
    o = ap.parse_args()
    if not os.access(o.png, os.X_OK):
        print("raycast_eval: %s is not an executable" % o.png,
              file=sys.stderr)
        return 2
    os.makedirs(o.work, exist_ok=True)
    rng = random.Random(o.draw)
    walks = [draw_walk(rng, k) for k in range(o.walks)]
    with ThreadPoolExecutor(max_workers=max(1, o.jobs)) as ex:
        results = list(ex.map(
            lambda w: run_walk(o.png, o.work, w, o.hint, o.keep), walks))
    figs = {60: Fig(), 120: Fig()}
    print("| walk | material | mounting | B | frames | NO_INFO | HAZARD |"
          " CLEAR | false vouches |")
    print("|---|---|---|---|---|---|---|---|---|")
    for w, meta, rows in results:
        f = figs[w["baseline_mm"]]
        before = f.fv + f.fv_under
        score(w, meta, rows, f)
        n = len(rows)
        print("| %s | %s | %d mm / %.1f deg / %.1f deg | %d | %d | %d | %d |"
              " %d | %d |" % (
                  w["name"], w["material"], w["height_mm"], w["pitch_deg"],
                  w["roll_deg"], w["baseline_mm"], n,
                  sum(r["state"] == "NO_INFO" for r in rows),
                  sum(r["state"] == "HAZARD" for r in rows),
                  sum(r["state"] == "CLEAR" for r in rows),
                  f.fv + f.fv_under - before))
    print()
    print("| figure | B = 12 cm | B = 6 cm |")
    print("|---|---|---|")

    def row(label, fn):
        print("| %s | %s | %s |" % (label, fn(figs[120]), fn(figs[60])))

    row("frames", lambda f: str(f.frames))
    row("NO_INFO", lambda f: "%d (%.0f %%)" % (
        f.noinfo, 100.0 * f.noinfo / max(1, f.frames)))
    row("false vouches (frames with a minimum drop in view)",
        lambda f: "%d (%d)" % (f.fv, f.drop_frames))
    row("vouches over a minimum drop below the view",
        lambda f: "%d (%d)" % (f.fv_under, f.under_frames))
    row("detection >= 10 cm at 1.5-3 m", lambda f: "%d/%d" % tuple(f.det))
    row("IMMINENT / CAUTION frames on flat and up-step walks",
        lambda f: "%d / %d of %d" % (f.imm, f.caut, f.neg_frames))
    row("alerts nearer than 0.7 x the edge ahead less 0.3 m (drop and "
        "stairs frames)",
        lambda f: "%d of %d" % (f.ahead_false, f.ahead_frames))
    row("median clear_to_mm on flat walks", lambda f: (
        "%.0f mm" % statistics.median(f.flat_clear)) if f.flat_clear
        else "-")
    bad = figs[60].fv_list + figs[120].fv_list
    for b in bad:
        print("false vouch: %s frame %d, edge %.0f mm, %s, clear_to %d" % b)
    total = sum(f.fv + f.fv_under for f in figs.values())
    print("%d false vouches" % total)
    return 1 if total else 0


if __name__ == "__main__":
    sys.exit(main())
