#!/bin/sh
# tools/synth/floor_noise.py on one asphalt walk (B = 12 cm, 2 frames):
# it must run, print the three matchers, and negobs's 16-px strip medians
# must scatter by less than 0.1 px there (0.04 px measured; a matcher
# that lost sub-pixel precision reads 0.2-0.3). Exit 77 (skipped) when
# python3-opencv is missing.
# usage: test_floor_noise.sh FLOOR_NOISE_PY BUILD_DIR WORK_DIR
set -u
py=$1 build=$2 work=$3
rm -rf "$work"
pyi=python3; [ -x /usr/bin/python3 ] && pyi=/usr/bin/python3  # the Debian one has cv2
out=$("$pyi" "$py" --build "$build" --textures asphalt --baselines 120 --frames 2 --work "$work")
rc=$?
[ "$rc" -eq 77 ] && { echo "skipped: python3-opencv missing"; exit 77; }
echo "$out"
[ "$rc" -eq 0 ] || { echo "FAIL: floor_noise.py exit $rc"; exit 1; }
for m in negobs bm sgbm; do
    echo "$out" | grep -q "^asphalt  *120  $m " || { echo "FAIL: no $m row"; exit 1; }
done
echo "$out" | awk '$1 == "asphalt" && $3 == "negobs" { sd = $7 }
    END { if (sd == "" || sd + 0 >= 0.1) { print "FAIL: negobs strip sd " sd " px"; exit 1 }
          print "negobs strip sd " sd " px < 0.1" }'
