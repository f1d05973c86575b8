"""Shared helpers of the rendered-walk measurements (floor_noise.py,
pool_noise.py): OpenCV present or exit 77, a tool run that stops the
script on failure, the built tools' paths, and png16 disparity reading."""
import os
import subprocess
import sys


def need_opencv(prog):
    """(cv2, numpy), or exit 77: meson's "skipped" for the test that runs
    the script (the host tools' OpenCV is the Debian one)."""
    try:
        import cv2
        import numpy
    except ImportError as e:
        sys.stderr.write("%s: needs python3-opencv and python3-numpy (%s)\n" % (prog, e))
        sys.exit(77)
    return cv2, numpy


def run(prog, cmd):
    """Run cmd quietly; on failure print its stderr and exit 1."""
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                       text=True)
    if r.returncode != 0:
        sys.stderr.write("%s: %s failed (exit %d)\n%s" %
                         (prog, os.path.basename(cmd[0]), r.returncode, r.stderr))
        sys.exit(1)


def built_tools(ap, build):
    """negobs_synth and negobs_png of the meson build folder, or a
    command-line error."""
    synth = os.path.join(build, "tools", "synth", "negobs_synth")
    png = os.path.join(build, "tools", "detect", "negobs_png")
    for p in (synth, png):
        if not os.access(p, os.X_OK):
            ap.error("%s not found: build the tools first" % p)
    return synth, png


def int_list(ap, text, what):
    """Comma-separated integers, or a command-line error."""
    try:
        return [int(x) for x in text.split(",")]
    except ValueError:
        ap.error("%s takes integers" % what)
        return []


def read_disp16(prog, path):
    """A png16 disparity map (value = 16 x disparity, 0 = none) in px, as
    float64; exit 1 when it cannot be read."""
    cv2, np = need_opencv(prog)
    m = cv2.imread(path, cv2.IMREAD_UNCHANGED)
    if m is None:
        sys.exit("%s: cannot read %s" % (prog, path))
    return m.astype(np.float64) / 16.0
