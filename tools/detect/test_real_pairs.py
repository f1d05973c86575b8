#!/usr/bin/env python3
"""Real pairs from three other cameras: no false confidence.

The synthetic suite cannot show how the detector behaves on real sensors.
This test runs the real data beside the repository ($NEGOBS_DATA, default
../shared/data; docs/DETECTION.md, "Real cameras") through the tools and
fails on the two verdicts that would hurt a wearer or switch the device
off for nothing:

* OAK-D Lite pairs (640x480, B = 75 mm, no drop, no mounting hint), at
  640x480 and binned to 320x240 as the device processes them: no pair may
  report a hazard, and a CLEAR verdict needs the measured noise to vouch
  for at least the near-zone minimum (1.5 m, the default `near_min_mm`).
* SurDis sequence 21 (a 3 cm wearable rig walking towards down-steps),
  told the generic hint and told no mounting: 0 false vouches (a frame
  whose clear_to_mm exceeds 1.1x the estimated distance to the steps).
* LIBELAS urban pairs (car-mounted, 1344x391, no calibration shipped):
  flat streets ahead, so no hazard may be reported. The camera values are
  assumed, not given (f = 645.24 px, cx, cy = 635.96, 194.13, B = 570.7
  mm: libviso2's published calibration of a Karlsruhe street sequence of
  the same image size, assumed to fit these pairs); a wrong f or B scales
  the measured mounting, not the flatness of the street.

Each set that is absent is skipped with a message; with none present the
test exits 77 (skipped). `--selftest` feeds the checks known-bad reports
and must see each of them refused.

usage: test_real_pairs.py NEGOBS_DETECT_EVAL NEGOBS_PNG WORKDIR
       test_real_pairs.py --selftest
"""
import json
import os
import subprocess
import sys

NEAR_MIN_MM = 1500  # near_min_mm's default (docs/DETECTION.md, section 10)
URBAN_CAMERA = ["--f", "645.24", "--baseline-mm", "570.7", "--cx", "635.96",
                "--cy", "194.13"]


def data_dir():
    env = os.environ.get("NEGOBS_DATA")
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.normpath(os.path.join(here, "..", "..", "..", "shared",
                                         "data"))


def table_rows(text):
    """Cells of every Markdown table row that is not a header rule."""
    rows = []
    for line in text.splitlines():
        if not line.startswith("|") or line.startswith("|---"):
            continue
        rows.append([c.strip() for c in line.strip().strip("|").split("|")])
    return rows


def leading_int(cell):
    digits = ""
    for ch in cell:
        if ch.isdigit():
            digits += ch
        elif digits:
            break
    return int(digits) if digits else None


def check_oakd(text, label):
    """Errors of one `negobs_detect_eval --oakd` report."""
    errors = []
    pairs = 0
    for cells in table_rows(text):
        if len(cells) < 6 or cells[0] == "pair":
            continue
        pairs += 1
        name, verdict, vouch = cells[0], cells[1], leading_int(cells[5])
        if verdict.startswith("HAZARD"):
            errors.append("%s %s: a hazard on a pair without a drop (%s)" %
                          (label, name, verdict))
        if verdict.startswith("CLEAR") and (vouch is None or
                                            vouch < NEAR_MIN_MM):
            errors.append("%s %s: CLEAR while the noise vouches for %s "
                          "(< %d)" % (label, name, cells[5], NEAR_MIN_MM))
    if pairs == 0:
        errors.append("%s: no pair in the report" % label)
    return errors


def check_surdis(text, label):
    """Errors of one `negobs_detect_eval --surdis` report."""
    errors = []
    rows = table_rows(text)
    summary = None
    for i, cells in enumerate(rows):
        if "false vouches" in cells and i + 1 < len(rows):
            summary = (cells.index("false vouches"), rows[i + 1])
            break
    if summary is None:
        return ["%s: no summary table" % label]
    col, values = summary
    if col >= len(values) or leading_int(values[col]) is None:
        return ["%s: unreadable summary row %s" % (label, values)]
    if leading_int(values[col]) != 0:
        errors.append("%s: %s false vouches" % (label, values[col]))
    frames = 0
    for cells in rows:
        if len(cells) == 6 and cells[0].isdigit():
            frames += 1
            if cells[5] != "no":
                errors.append("%s frame %s: false vouch (clear_to_mm %s, "
                              "steps at %s)" % (label, cells[0], cells[2],
                                                cells[3]))
    if frames == 0:
        errors.append("%s: no per-frame rows" % label)
    return errors


def check_urban(lines, label):
    """Errors of negobs_png's JSON lines for one urban pair."""
    errors = []
    frames = 0
    for line in lines:
        line = line.strip()
        if not line:
            continue
        frame = json.loads(line)
        frames += 1
        if frame.get("state") == "HAZARD" or frame.get("hazards"):
            errors.append("%s frame %s: hazard on a flat street (%s)" %
                          (label, frame.get("frame"), frame.get("hazards")))
    if frames == 0:
        errors.append("%s: no frames" % label)
    return errors


def run(cmd):
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True)
    return proc.returncode, proc.stdout, proc.stderr


def selftest():
    bad = []
    oakd_hazard = ("| pair | verdict (reasons) | clear_to_mm | mounting | fit "
                   "| noise could vouch for |\n|---|---|---|---|---|---|\n"
                   "| desk | HAZARD | 900 | x | y | 2000 mm |\n")
    oakd_clear = oakd_hazard.replace("HAZARD", "CLEAR").replace("2000", "900")
    oakd_good = oakd_hazard.replace("HAZARD", "NO_INFO (NOISY)").replace(
        "2000", "900")
    surdis = ("| frames | x | false vouches |\n|---|---|---|\n| 83 | 1 | %d |\n"
              "\n| frame | verdict | clear_to_mm | steps at | noise vouch mm "
              "| false vouch |\n|---|---|---|---|---|---|\n"
              "| 18 | CLEAR | 5000 | 1353 | 5000 | %s |\n")
    urban_bad = ['{"frame": 0, "state": "CLEAR", "hazards": []}',
                 '{"frame": 1, "state": "HAZARD", "hazards": [{"range_mm": 4}]}']
    cases = [
        ("OAK-D hazard", check_oakd(oakd_hazard, "t"), True),
        ("OAK-D short CLEAR", check_oakd(oakd_clear, "t"), True),
        ("OAK-D empty", check_oakd("", "t"), True),
        ("OAK-D honest NO_INFO", check_oakd(oakd_good, "t"), False),
        ("SurDis false vouches", check_surdis(surdis % (1, "no"), "t"), True),
        ("SurDis frame flagged", check_surdis(surdis % (0, "yes"), "t"), True),
        ("SurDis no table", check_surdis("nothing", "t"), True),
        ("SurDis clean", check_surdis(surdis % (0, "no"), "t"), False),
        ("urban hazard", check_urban(urban_bad, "t"), True),
        ("urban clean", check_urban(urban_bad[:1], "t"), False),
    ]
    for name, errors, want_errors in cases:
        if bool(errors) != want_errors:
            bad.append("%s: errors %s, expected %s" %
                       (name, errors, "some" if want_errors else "none"))
    for line in bad:
        print("FAIL selftest " + line)
    print("selftest: %d cases, %d wrong" % (len(cases), len(bad)))
    return 1 if bad else 0


def main():
    if len(sys.argv) == 2 and sys.argv[1] == "--selftest":
        return selftest()
    if len(sys.argv) != 4:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    evaluator, png, work = sys.argv[1:]
    data = data_dir()
    runs = []  # (label, command, check of its stdout)

    oakd = os.path.join(data, "oakd")
    if os.path.isfile(os.path.join(oakd, "calibration.json")):
        for binning in ("1", "2"):
            runs.append(("OAK-D (--bin %s)" % binning,
                         [evaluator, "--oakd", oakd, "--bin", binning],
                         check_oakd))
    else:
        print("OAK-D pairs not found under %s: skipped" % oakd)

    surdis = os.path.join(data, "surdis")
    if os.path.isdir(surdis):
        for hint, extra in (("the generic hint", []),
                            ("no mounting hint", ["--surdis-height-mm", "0"])):
            runs.append(("SurDis (%s)" % hint,
                         [evaluator, "--surdis", surdis] + extra,
                         check_surdis))
    else:
        print("SurDis not found under %s: skipped" % surdis)

    urban = os.path.join(data, "libelas_urban")
    if os.path.isdir(urban):
        for n in range(1, 5):
            label = "urban%d" % n
            runs.append((label, [png,
                                 os.path.join(urban, label + "_left.pgm"),
                                 os.path.join(urban, label + "_right.pgm"),
                                 "--out", os.path.join(work, label),
                                 "--no-overlay", "--height-mm", "0",
                                 "--repeat", "5", "--bin", "2"] + URBAN_CAMERA,
                         lambda out, lab: check_urban(out.splitlines(), lab)))
    else:
        print("LIBELAS urban pairs not found under %s: skipped" % urban)

    errors = []
    ran = 0
    for label, cmd, check in runs:
        rc, out, err = run(cmd)
        if rc != 0:
            errors.append("%s: exit %d: %s" % (label, rc, err.strip()))
            continue
        errors += check(out, label)
        ran += 1
        print("%s: checked" % label)

    if ran == 0 and not errors:
        print("no real data under %s (set NEGOBS_DATA): skipped" % data)
        return 77
    for line in errors:
        print("FAIL " + line)
    print("%d real-data runs checked, %d errors" % (ran, len(errors)))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
